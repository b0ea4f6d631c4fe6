/*
 * A board for the STM32F405 port: everything that differs between two
 * boards built around it (pins, current and bus sensing, dead time, the
 * gate driver, the encoder, the clock crystal) in one constant struct.
 * One board = one file that defines stm32_board (board_<name>.c, chosen by
 * the CMake variable MC_STM32_BOARD); the drivers read nothing else.
 */
#ifndef STM32_BOARD_H
#define STM32_BOARD_H

#include <stdbool.h>
#include <stdint.h>

/* A pin: port (STM32_PA ..), number 0..15, alternate function 0..15 (for
 * a pin in alternate-function mode). */
typedef struct {
    uint8_t port;
    uint8_t pin;
    uint8_t af;
} stm32_pin_t;

#define STM32_NO_ADC_CHANNEL 0xFFu

typedef struct {
    const char *name;
    uint32_t hse_hz; /* crystal: a whole number of MHz, 4 .. 26 MHz */

    /* TIM1 outputs: CH1..3 (high sides), CH1N..3N (low sides), AF1 */
    stm32_pin_t pwm_high[3];
    stm32_pin_t pwm_low[3];
    float dead_time_s;    /* inserted by TIM1 (BDTR.DTG) */
    bool has_break_input; /* TIM1_BKIN wired to the over-current
                             comparator / the gate driver's fault line */
    stm32_pin_t break_input;
    bool break_active_high;

    /* Current sensing: ADC1/2/3 injected, triggered by TIM1 (adc_inj.h).
     * current_channel[k]: ADC channel of phase k's shunt amplifier, or
     * STM32_NO_ADC_CHANNEL for the phase computed as minus the sum of the
     * other two (two shunts). current_adc[k]: the ADC (1..3) that converts
     * it. */
    uint8_t current_channel[3];
    uint8_t current_adc[3];
    stm32_pin_t current_pin[3];
    float shunt_ohm;
    float current_gain;   /* amplifier V/V (the gate driver's, gain_code) */
    float adc_vref_V;     /* full scale of the 12-bit ADCs */
    float current_zero_V; /* amplifier output at zero current */
    uint8_t vbus_channel; /* converted by ADC1 after its current */
    stm32_pin_t vbus_pin;
    float vbus_divider; /* V_bus / V_pin */

    /* Encoder: TIM3 in encoder mode on CH1/CH2 */
    stm32_pin_t encoder_a, encoder_b;
    uint32_t encoder_counts_per_rev; /* 4 x lines */

    /* Gate driver (DRV8301 over SPI3) and GPIO */
    stm32_pin_t spi_sck, spi_miso, spi_mosi, spi_cs;
    uint16_t drv_ctrl1, drv_ctrl2; /* DRV8301 control registers 1, 2
                                      (11 data bits each) */
    stm32_pin_t enable_gate;       /* output, high: gate driver enabled */
    stm32_pin_t fault_input;       /* input, low: gate driver fault */
    stm32_pin_t debug_pin;         /* output, high while the fast ISR runs */

    /* CAN1 and the console (USART2) */
    stm32_pin_t can_rx, can_tx;
    stm32_pin_t console_tx;
    uint32_t console_baud;
} stm32_board_t;

extern const stm32_board_t stm32_board;

#endif /* STM32_BOARD_H */
