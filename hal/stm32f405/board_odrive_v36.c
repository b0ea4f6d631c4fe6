/*
 * Board: ODrive v3.6 (STM32F405RG, two DRV8301; this port drives axis M0).
 * Pins from the board's published pinout (ODrive v3.6 schematic); the
 * phase mapping of the two shunts (SO1 = phase B, SO2 = phase C) and the
 * gate-driver settings are the usual ones for this board. Not tried on
 * hardware (hal/stm32f405/README.md): check every line against your
 * board's revision before powering a motor.
 */
#include "board.h"
#include "regs.h"

/* DRV8301 control register 1: GATE_CURRENT 1.7 A (D1:D0 = 00), PWM_MODE
 * six inputs (D3 = 0), OCP_MODE latched shut-down (D5:D4 = 01),
 * OC_ADJ_SET code 21 (D10:D6; the datasheet's V_DS threshold table). */
#define DRV_CTRL1 ((1u << 4) | (21u << 6))
/* Control register 2: OCTW_MODE report OT and OC (D1:D0 = 00), GAIN
 * 40 V/V (D3:D2 = 10), no DC calibration, cycle-by-cycle OC (D6 = 0). */
#define DRV_CTRL2 (2u << 2)

const stm32_board_t stm32_board = {
    .name = "ODrive v3.6, axis M0",
    .hse_hz = 8000000u,

    .pwm_high = { { STM32_PA, 8, 1 }, { STM32_PA, 9, 1 }, { STM32_PA, 10, 1 } },
    .pwm_low = { { STM32_PB, 13, 1 },
                 { STM32_PB, 14, 1 },
                 { STM32_PB, 15, 1 } },
    .dead_time_s = 500e-9f,
    /* The DRV8301's nFAULT goes to PD2, not to TIM1_BKIN: the fault line
     * is polled by the fast ISR (hal_gpio_fault_input_active), and the
     * driver's own over-current protection acts in hardware. */
    .has_break_input = false,

    /* two shunts: B on PC0 (ADC2_IN10), C on PC1 (ADC3_IN11); A computed */
    .current_channel = { STM32_NO_ADC_CHANNEL, 10u, 11u },
    .current_adc = { 1u, 2u, 3u },
    .current_pin = { { 0, 0, 0 }, { STM32_PC, 0, 0 }, { STM32_PC, 1, 0 } },
    .shunt_ohm = 0.0005f,
    .current_gain = 40.0f,
    .adc_vref_V = 3.3f,
    .current_zero_V = 1.65f,
    .vbus_channel = 6u, /* PA6, ADC1_IN6 */
    .vbus_pin = { STM32_PA, 6, 0 },
    .vbus_divider = 19.0f, /* 56 V version (11 for the 24 V one) */

    .encoder_a = { STM32_PB, 4, 2 }, /* TIM3_CH1, AF2 */
    .encoder_b = { STM32_PB, 5, 2 }, /* TIM3_CH2, AF2 */
    .encoder_counts_per_rev = 8192u, /* a 2048-line encoder */

    .spi_sck = { STM32_PC, 10, 6 },
    .spi_miso = { STM32_PC, 11, 6 },
    .spi_mosi = { STM32_PC, 12, 6 },
    .spi_cs = { STM32_PC, 13, 0 },
    .drv_ctrl1 = DRV_CTRL1,
    .drv_ctrl2 = DRV_CTRL2,
    .enable_gate = { STM32_PB, 12, 0 },
    .fault_input = { STM32_PD, 2, 0 },
    .debug_pin = { STM32_PA, 0, 0 }, /* GPIO_1 */

    .can_rx = { STM32_PB, 8, 9 },
    .can_tx = { STM32_PB, 9, 9 },
    .console_tx = { STM32_PA, 2, 7 }, /* GPIO_3, USART2_TX */
    .console_baud = 115200u,
};
