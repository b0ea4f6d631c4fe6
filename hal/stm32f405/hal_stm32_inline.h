/*
 * The fast ISR's HAL functions on the STM32F405, static inline (the build
 * defines HAL_INLINE_ACCESSORS="hal_stm32_inline.h" for everything linked
 * into the port's images): register reads and writes, no call.
 */
#ifndef HAL_STM32_INLINE_H
#define HAL_STM32_INLINE_H

#include <stdbool.h>
#include <stdint.h>

#include "board.h"
#include "gpio_cfg.h"
#include "hal/adc.h"
#include "hal_stm32.h"
#include "pwm_tim1.h"
#include "regs.h"

#define HAL_STM32_INLINE static inline __attribute__((always_inline))

/* One current: ADC a's JDR j in amperes (the amplifier's nominal zero;
 * the firmware calibrates the offset). */
HAL_STM32_INLINE float hal_stm32_current(uint32_t a, uint32_t j)
{
    const stm32_adc_map_t *m = &stm32_hal.adc;
    return ((float)STM32_ADC(a)->JDR[j] - m->zero_counts) * m->amps_per_count;
}

HAL_STM32_INLINE void hal_adc_read(hal_adc_sample_t *out)
{
    const stm32_adc_map_t *m = &stm32_hal.adc;
    float sum = 0.0f;
    uint32_t computed = 3u;
    for (uint32_t k = 0u; k < 3u; ++k) {
        if (m->current_adc[k] == 0u) {
            computed = k;
            continue;
        }
        out->i_abc_A[k] =
            hal_stm32_current(m->current_adc[k], m->current_jdr[k]);
        sum += out->i_abc_A[k];
    }
    if (computed < 3u) {
        out->i_abc_A[computed] = -sum; /* two shunts */
    }
    out->v_dc_V = (float)STM32_ADC(1)->JDR[m->vbus_jdr] * m->volts_per_count;
    out->temp_degC = 0.0f;
    out->temp_valid = false;
}

HAL_STM32_INLINE uint32_t hal_encoder_count(void)
{
    return STM32_TIM3->CNT;
}

/* TIM3's encoder mode keeps no edge times (a capture channel on the
 * inputs would: not wired in this port). */
HAL_STM32_INLINE bool hal_encoder_edge_age(float *age_s)
{
    (void)age_s;
    return false;
}

/* The gate driver's nFAULT (low), or a break that cleared MOE. */
HAL_STM32_INLINE bool hal_gpio_fault_input_active(void)
{
    return !stm32_gpio_read(&stm32_board.fault_input) ||
           (STM32_TIM1->SR & TIM_SR_BIF) != 0u;
}

/* EN_GATE stays high (drv8301.h); off keeps the gates off through MOE
 * and clears a break's flag (the break is level-triggered: a cause still
 * present sets it again at once, so the fault input stays active). */
HAL_STM32_INLINE void hal_gpio_power_stage_enable(bool enable)
{
    if (!enable) {
        STM32_TIM1->BDTR &= ~TIM_BDTR_MOE;
        STM32_TIM1->SR = ~TIM_SR_BIF;
    }
}

HAL_STM32_INLINE void hal_gpio_debug_pin_set(bool level)
{
    stm32_gpio_write(&stm32_board.debug_pin, level);
}

HAL_STM32_INLINE void hal_pwm_set_duties(const float duty_abc[3])
{
    const float arr_f = stm32_hal.arr_f;
    stm32_tim_t *t = STM32_TIM1;
#pragma GCC unroll 3
    for (uint32_t k = 0u; k < 3u; ++k) {
        t->CCR[k] = stm32_pwm_ccr(duty_abc[k], arr_f);
    }
}

/* MOE on unless a break is pending (its flag is cleared only with the
 * power stage off: hal_gpio_power_stage_enable). */
HAL_STM32_INLINE void hal_pwm_enable_outputs(void)
{
    if ((STM32_TIM1->SR & TIM_SR_BIF) == 0u) {
        STM32_TIM1->BDTR |= TIM_BDTR_MOE;
    }
}

HAL_STM32_INLINE void hal_pwm_disable_outputs(void)
{
    STM32_TIM1->BDTR &= ~TIM_BDTR_MOE;
}

HAL_STM32_INLINE bool hal_pwm_outputs_enabled(void)
{
    return (STM32_TIM1->BDTR & TIM_BDTR_MOE) != 0u;
}

/* Never armed (hal_pwm_overcurrent_arm). */
HAL_STM32_INLINE bool hal_pwm_overcurrent_active(void)
{
    return false;
}

HAL_STM32_INLINE uint32_t hal_cycle_counter(void)
{
    return STM32_DWT->CYCCNT;
}

/* CYCCNT wraps at 2^32. */
HAL_STM32_INLINE uint32_t hal_cycles_since(uint32_t start)
{
    return hal_cycle_counter() - start;
}

#endif /* HAL_STM32_INLINE_H */
