/* The HAL contract on the bound simulator mailbox (hal_sim_mailbox.h). */
#include "hal_sim_mailbox.h"

#include <math.h>
#include <stddef.h>

#include "hal/encoder.h"
#include "hal/gpio.h"
#include "hal/pwm.h"
#include "hal/time.h"

/* The ISR-path functions: here on the host's bound mailbox; an image with
 * HAL_INLINE_ACCESSORS has them static inline from the HAL headers. */
#ifndef HAL_INLINE_ACCESSORS
#define HAL_SIM_ACCESSOR
#define HAL_SIM_MAILBOX hal_sim_bound()
#include "hal_sim_accessors.h"
#endif

#define HAL_SIM_NS_PER_S 1000000000u

void hal_sim_mailbox_reset(hal_sim_mailbox_t *mailbox)
{
    *mailbox = (hal_sim_mailbox_t){
        .encoder_edge_age_s = HAL_ENCODER_EDGE_AGE_MAX_S, /* no edge yet */
        .duty_abc = { 0.5f, 0.5f, 0.5f },
    };
}

bool hal_sim_outputs_active(const hal_sim_mailbox_t *mailbox)
{
    return mailbox->pwm_outputs_enabled && mailbox->power_stage_enabled &&
           !mailbox->oc_active;
}

/* ---- PWM ---------------------------------------------------------------- */

hal_status_t hal_pwm_init(float f_pwm_Hz, hal_pwm_timing_t *timing)
{
    hal_sim_mailbox_t *m = hal_sim_bound();
    /* The simulated inverter switches at the plant's rate whatever was
     * asked (as a timer realises the nearest period it can make); the
     * firmware compares the realised period with its request. */
    if (!isfinite(f_pwm_Hz) || !(f_pwm_Hz > 0.0f) || !(m->pwm_f_Hz > 0.0f)) {
        return HAL_ERR_PARAM;
    }
    timing->period_s = 1.0f / m->pwm_f_Hz;
    timing->delay_periods = m->pwm_delay_periods;
    m->pwm_outputs_enabled = false;
    m->oc_trip_A = 0.0f;
    return HAL_OK;
}

/* The engine compares the sampled phase currents with the level and stops
 * the outputs (host_sim/engine: sim_engine_step). */
bool hal_pwm_overcurrent_arm(float trip_A)
{
    hal_sim_mailbox_t *m = hal_sim_bound();
    if (!m->oc_comparator || !isfinite(trip_A) || !(trip_A > 0.0f)) {
        return false;
    }
    m->oc_trip_A = trip_A;
    return true;
}

/* ---- ADC, encoder, GPIO -------------------------------------------------- */

uint32_t hal_encoder_counts_per_rev(void)
{
    return hal_sim_bound()->encoder_cpr;
}

bool hal_encoder_index(uint32_t *count_at_index)
{
    const hal_sim_mailbox_t *m = hal_sim_bound();
    if (count_at_index != NULL) {
        *count_at_index = m->encoder_count_at_index;
    }
    return m->encoder_index_seen;
}

/* ---- Time (the cycle counter is the backend's) --------------------------- */

uint64_t hal_time_ticks(void)
{
    return hal_sim_bound()->sim_time_ns; /* simulated time, set by the engine */
}

uint32_t hal_time_tick_hz(void)
{
    return HAL_SIM_NS_PER_S;
}
