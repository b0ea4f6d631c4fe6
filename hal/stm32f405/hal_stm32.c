/* The HAL contract on the STM32F405 (hal_stm32.h): everything outside the
 * fast ISR's accessors. */
#include "hal_stm32.h"

#include "board.h"
#include "bxcan.h"
#include "drv8301.h"
#include "encoder_tim.h"
#include "gpio_cfg.h"
#include "hal/can.h"
#include "hal/encoder.h"
#include "hal/gpio.h"
#include "hal/pwm.h"
#include "hal/time.h"
#include "pwm_tim1.h"
#include "regs.h"

stm32_hal_t stm32_hal;

/* The gate driver needs 10 ms after EN_GATE rises before its SPI answers
 * (DRV8301 datasheet, power-up). */
#define GATE_DRIVER_WAKE_S 0.010f

static void wait_cycles(uint32_t cycles)
{
    const uint32_t start = STM32_DWT->CYCCNT;
    while (STM32_DWT->CYCCNT - start < cycles) {
    }
}

stm32_hal_status_t stm32_hal_init(const stm32_clocks_t *clocks)
{
    stm32_hal.clocks = *clocks;
    if (clocks->status != STM32_CLOCK_OK) {
        return STM32_HAL_CLOCK;
    }
    if (!stm32_adc_map_for(&stm32_board, &stm32_hal.adc)) {
        return STM32_HAL_ADC_MAP;
    }
    /* the cycle counter (DWT) and the 1 kHz time base (SysTick on HCLK) */
    *STM32_DEMCR |= DEMCR_TRCENA;
    STM32_DWT->CYCCNT = 0u;
    STM32_DWT->CTRL |= DWT_CTRL_CYCCNTENA;
    STM32_SYSTICK->LOAD = clocks->hclk_hz / 1000u - 1u;
    STM32_SYSTICK->VAL = 0u;
    STM32_SYSTICK->CTRL =
        SYSTICK_CTRL_CLKSOURCE | SYSTICK_CTRL_TICKINT | SYSTICK_CTRL_ENABLE;
    /* GPIO: the debug pin low, the fault input pulled up (open drain) */
    stm32_gpio_setup(&stm32_board.debug_pin, GPIO_MODE_OUTPUT, STM32_PULL_NONE);
    stm32_gpio_write(&stm32_board.debug_pin, false);
    stm32_gpio_setup(&stm32_board.fault_input, GPIO_MODE_INPUT, STM32_PULL_UP);
    /* the gate driver: EN_GATE high, its settings over SPI */
    stm32_gpio_setup(&stm32_board.enable_gate, GPIO_MODE_OUTPUT,
                     STM32_PULL_NONE);
    stm32_gpio_write(&stm32_board.enable_gate, true);
    wait_cycles((uint32_t)(GATE_DRIVER_WAKE_S * (float)clocks->hclk_hz));
    if (stm32_drv8301_setup(&stm32_board) != STM32_DRV_OK) {
        stm32_gpio_write(&stm32_board.enable_gate, false);
        return STM32_HAL_GATE_DRIVER;
    }
    if (!stm32_encoder_init(&stm32_board)) {
        return STM32_HAL_ENCODER;
    }
    return STM32_HAL_OK;
}

void SysTick_Handler(void);
void SysTick_Handler(void)
{
    stm32_hal.ms = stm32_hal.ms + 1u;
}

/* ---- hal/pwm.h --------------------------------------------------------- */

hal_status_t hal_pwm_init(float f_pwm_Hz, hal_pwm_timing_t *timing)
{
    if (stm32_hal.clocks.status != STM32_CLOCK_OK) {
        return HAL_ERR_HW;
    }
    const stm32_pwm_cfg_t cfg = {
        .tim_clk_hz = stm32_hal.clocks.tim_apb2_hz,
        .f_pwm_Hz = f_pwm_Hz,
        .dead_time_s = stm32_board.dead_time_s,
        .break_enable = stm32_board.has_break_input,
        .break_active_high = stm32_board.break_active_high,
    };
    stm32_pwm_t pwm;
    if (stm32_pwm_tim1_init(&cfg, &pwm) != STM32_PWM_OK) {
        return HAL_ERR_PARAM;
    }
    stm32_hal.arr_f = (float)pwm.arr;
    for (uint32_t k = 0u; k < 3u; ++k) {
        stm32_gpio_setup(&stm32_board.pwm_high[k], GPIO_MODE_AF,
                         STM32_PULL_NONE);
        stm32_gpio_setup(&stm32_board.pwm_low[k], GPIO_MODE_AF,
                         STM32_PULL_NONE);
    }
    if (stm32_board.has_break_input) {
        stm32_gpio_setup(&stm32_board.break_input, GPIO_MODE_AF,
                         STM32_PULL_NONE);
    }
    stm32_adc_inj_init(&stm32_board, &stm32_hal.adc);
    timing->period_s = pwm.period_s;
    timing->delay_periods = pwm.delay_periods;
    return HAL_OK;
}

/* The STM32F405 has no comparators, and a board's TIM1_BKIN (a fixed-level
 * comparator or a gate driver's fault line) is reported as the fault input:
 * the firmware compares the sampled currents itself. */
bool hal_pwm_overcurrent_arm(float trip_A)
{
    (void)trip_A;
    return false;
}

/* ---- hal/encoder.h ----------------------------------------------------- */

uint32_t hal_encoder_counts_per_rev(void)
{
    return stm32_board.encoder_counts_per_rev;
}

bool hal_encoder_index(uint32_t *count_at_index)
{
    (void)count_at_index;
    return false; /* the index is not wired to a capture (encoder_tim.h) */
}

/* ---- hal/time.h -------------------------------------------------------- */

uint64_t hal_time_ticks(void)
{
    /* 64-bit read against the SysTick interrupt: until two reads agree */
    uint64_t a;
    uint64_t b;
    do {
        a = stm32_hal.ms;
        b = stm32_hal.ms;
    } while (a != b);
    return a;
}

uint32_t hal_time_tick_hz(void)
{
    return 1000u;
}

uint32_t hal_cycle_counter_hz(void)
{
    return stm32_hal.clocks.hclk_hz;
}

/* ---- hal/can.h --------------------------------------------------------- */

hal_status_t hal_can_init(uint32_t bitrate_bps)
{
    return stm32_can_init(&stm32_board, stm32_hal.clocks.pclk1_hz, bitrate_bps);
}

hal_status_t hal_can_send(const hal_can_frame_t *frame)
{
    return stm32_can_send(frame);
}

hal_status_t hal_can_receive(hal_can_frame_t *frame)
{
    return stm32_can_receive(frame);
}

void hal_can_stats(hal_can_stats_t *stats)
{
    stm32_can_stats(stats);
}
