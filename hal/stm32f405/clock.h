/*
 * The clock tree: SYSCLK 168 MHz from the crystal (HSE) through the main
 * PLL (VCO 336 MHz, P = 2; Q = 7 gives the 48 MHz of USB), AHB 168 MHz,
 * APB1 42 MHz (its timers 84 MHz), APB2 84 MHz (TIM1 168 MHz), flash
 * 5 wait states, regulator scale 1 (RM0090 6.3.3, 7.2).
 *
 * Every wait has a timeout (a loop count): an oscillator that does not
 * start, a PLL that does not lock or a switch that does not happen leaves
 * the MCU on the 16 MHz HSI with the prescalers at 1 and says which
 * (QEMU's netduinoplus2 does not model the RCC: its registers read 0 and
 * the image takes the HSE timeout). The drive does not start on the HSI
 * (hal_stm32.c): its timing would be wrong by the HSI's +-1 %.
 */
#ifndef STM32_CLOCK_H
#define STM32_CLOCK_H

#include <stdbool.h>
#include <stdint.h>

typedef enum {
    STM32_CLOCK_OK = 0,         /* SYSCLK = PLL from HSE */
    STM32_CLOCK_HSE_TIMEOUT,    /* HSERDY never set: on the HSI */
    STM32_CLOCK_PLL_TIMEOUT,    /* PLLRDY never set: on the HSI */
    STM32_CLOCK_SWITCH_TIMEOUT, /* SWS never showed the PLL: on the HSI */
    STM32_CLOCK_BAD_CRYSTAL     /* hse_hz not a whole number of MHz in
                                   [4, 26] MHz: nothing touched */
} stm32_clock_status_t;

typedef struct {
    stm32_clock_status_t status;
    uint32_t sysclk_hz, hclk_hz;
    uint32_t pclk1_hz, pclk2_hz;       /* APB1, APB2 */
    uint32_t tim_apb1_hz, tim_apb2_hz; /* timer kernels: 2 x PCLK if the
                                          APB prescaler is not 1 */
} stm32_clocks_t;

#define STM32_HSI_HZ           16000000u
#define STM32_SYSCLK_HZ        168000000u
#define STM32_CLOCK_WAIT_LOOPS 200000u /* > 20 ms on the HSI per wait */

/* Bring the clock tree up from reset; *out: what runs now. Call once,
 * first thing after reset. */
void stm32_clock_init(uint32_t hse_hz, uint32_t wait_loops,
                      stm32_clocks_t *out);

/* The PLL's dividers for a crystal (VCO input 1 or 2 MHz, VCO 336 MHz).
 * False for a crystal outside [4, 26] MHz or not a whole number of MHz. */
typedef struct {
    uint32_t m, n, p, q;
} stm32_pll_t;
bool stm32_clock_pll_for(uint32_t hse_hz, stm32_pll_t *pll);

#endif /* STM32_CLOCK_H */
