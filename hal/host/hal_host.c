/* Host binding of the HAL contract to the simulator mailbox (hal_host.h). */
#define _POSIX_C_SOURCE 199309L

#include "hal_host.h"

#include <math.h>
#include <stdlib.h>
#include <time.h>

#include "hal/encoder.h"
#include "hal/gpio.h"
#include "hal/pwm.h"
#include "hal/time.h"

#define HAL_HOST_NS_PER_S 1000000000u

static _Thread_local hal_host_mailbox_t *bound;

static hal_host_mailbox_t *mb(void)
{
    if (bound == NULL) {
        abort(); /* wiring error of the test bench: no mailbox bound */
    }
    return bound;
}

void hal_host_bind(hal_host_mailbox_t *mailbox)
{
    bound = mailbox;
}

void hal_host_mailbox_reset(hal_host_mailbox_t *mailbox)
{
    *mailbox = (hal_host_mailbox_t){
        .duty_abc = { 0.5f, 0.5f, 0.5f },
    };
}

bool hal_host_outputs_active(const hal_host_mailbox_t *mailbox)
{
    return mailbox->pwm_outputs_enabled && mailbox->power_stage_enabled;
}

/* ---- PWM ---------------------------------------------------------------- */

hal_status_t hal_pwm_init(float f_pwm_hz)
{
    hal_host_mailbox_t *m = mb();
    if (!isfinite(f_pwm_hz) || !(f_pwm_hz > 0.0f)) {
        return HAL_ERR_PARAM;
    }
    m->pwm_period_s = 1.0f / f_pwm_hz;
    m->pwm_outputs_enabled = false;
    return HAL_OK;
}

float hal_pwm_period_s(void)
{
    return mb()->pwm_period_s;
}

void hal_pwm_set_duties(const float duty_abc[3])
{
    hal_host_mailbox_t *m = mb();
    for (unsigned k = 0u; k < 3u; ++k) {
        float d = duty_abc[k];
        if (!(d >= 0.0f)) {
            d = isnan(d) ? 0.5f : 0.0f; /* contract: protect the hardware */
        } else if (d > 1.0f) {
            d = 1.0f;
        }
        m->duty_abc[k] = d;
    }
}

void hal_pwm_enable_outputs(void)
{
    mb()->pwm_outputs_enabled = true;
}

void hal_pwm_disable_outputs(void)
{
    mb()->pwm_outputs_enabled = false;
}

bool hal_pwm_outputs_enabled(void)
{
    return mb()->pwm_outputs_enabled;
}

/* ---- ADC ---------------------------------------------------------------- */

void hal_adc_read(hal_adc_sample_t *out)
{
    *out = mb()->adc;
}

/* ---- Encoder ------------------------------------------------------------ */

uint32_t hal_encoder_counts_per_rev(void)
{
    return mb()->encoder_cpr;
}

uint32_t hal_encoder_count(void)
{
    return mb()->encoder_count;
}

bool hal_encoder_index(uint32_t *count_at_index)
{
    const hal_host_mailbox_t *m = mb();
    if (count_at_index != NULL) {
        *count_at_index = m->encoder_count_at_index;
    }
    return m->encoder_index_seen;
}

/* ---- Time --------------------------------------------------------------- */

uint64_t hal_time_ticks(void)
{
    return mb()->sim_time_ns;
}

uint32_t hal_time_tick_hz(void)
{
    return HAL_HOST_NS_PER_S;
}

uint32_t hal_cycle_counter(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) {
        abort(); /* Linux always provides this clock */
    }
    const uint64_t ns = (uint64_t)ts.tv_sec * HAL_HOST_NS_PER_S +
                        (uint64_t)ts.tv_nsec;
    return (uint32_t)ns; /* wraps every 4.29 s: differences stay valid */
}

uint32_t hal_cycle_counter_hz(void)
{
    return HAL_HOST_NS_PER_S;
}

/* ---- GPIO --------------------------------------------------------------- */

bool hal_gpio_fault_input_active(void)
{
    return mb()->fault_input_active;
}

void hal_gpio_power_stage_enable(bool enable)
{
    mb()->power_stage_enabled = enable;
}

void hal_gpio_debug_pin_set(bool level)
{
    mb()->debug_pin = level;
}
