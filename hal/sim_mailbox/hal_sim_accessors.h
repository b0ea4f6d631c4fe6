/*
 * The ISR-path HAL functions of the simulator mailbox binding, one body for
 * two linkages: hal_sim_mailbox.c defines them as functions on
 * hal_sim_bound() (the host binding); an image includes them as static
 * inline accessors on its own mailbox pointer through HAL_INLINE_ACCESSORS
 * (hal/include/hal/adc.h), as a board's binding reads and writes its
 * peripheral registers.
 *
 * The includer defines HAL_SIM_ACCESSOR (the linkage) and HAL_SIM_MAILBOX
 * (an expression: the bound mailbox).
 */
#ifndef HAL_SIM_ACCESSORS_H
#define HAL_SIM_ACCESSORS_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "hal_sim_mailbox.h"

#if !defined(HAL_SIM_ACCESSOR) || !defined(HAL_SIM_MAILBOX)
#error "define HAL_SIM_ACCESSOR and HAL_SIM_MAILBOX before this header"
#endif

HAL_SIM_ACCESSOR void hal_adc_read(hal_adc_sample_t *out)
{
    *out = HAL_SIM_MAILBOX->adc;
}

HAL_SIM_ACCESSOR uint32_t hal_encoder_count(void)
{
    return HAL_SIM_MAILBOX->encoder_count;
}

HAL_SIM_ACCESSOR bool hal_gpio_fault_input_active(void)
{
    return HAL_SIM_MAILBOX->fault_input_active;
}

HAL_SIM_ACCESSOR void hal_gpio_power_stage_enable(bool enable)
{
    HAL_SIM_MAILBOX->power_stage_enabled = enable;
}

HAL_SIM_ACCESSOR void hal_gpio_debug_pin_set(bool level)
{
    HAL_SIM_MAILBOX->debug_pin = level;
}

/* A duty outside [0, 1]: the nearer bound; NaN: 0.5 (zero voltage). */
static inline float hal_sim_duty_saturated(float d)
{
    if (isnan(d)) {
        return 0.5f;
    }
    return (d < 0.0f) ? 0.0f : 1.0f;
}

/* The compare registers saturate: a duty outside [0, 1] is clamped and a
 * NaN gives 0.5 (zero voltage), whatever the firmware computed (the
 * contract: protect the hardware). A duty within [0, 1] (both comparisons
 * false for NaN) passes as it is. */
HAL_SIM_ACCESSOR void hal_pwm_set_duties(const float duty_abc[3])
{
    hal_sim_mailbox_t *m = HAL_SIM_MAILBOX;
    for (unsigned k = 0u; k < 3u; ++k) {
        const float d = duty_abc[k];
        m->duty_abc[k] =
            (d >= 0.0f && d <= 1.0f) ? d : hal_sim_duty_saturated(d);
    }
}

HAL_SIM_ACCESSOR void hal_pwm_enable_outputs(void)
{
    HAL_SIM_MAILBOX->pwm_outputs_enabled = true;
}

HAL_SIM_ACCESSOR void hal_pwm_disable_outputs(void)
{
    HAL_SIM_MAILBOX->pwm_outputs_enabled = false;
}

HAL_SIM_ACCESSOR bool hal_pwm_outputs_enabled(void)
{
    return HAL_SIM_MAILBOX->pwm_outputs_enabled;
}

#endif /* HAL_SIM_ACCESSORS_H */
