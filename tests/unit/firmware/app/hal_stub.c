#include "hal_stub.h"

#include "hal/encoder.h"
#include "hal/gpio.h"
#include "hal/pwm.h"
#include "hal/time.h"

hal_stub_t g_hal;

void hal_stub_reset(void)
{
    g_hal = (hal_stub_t){
        .adc = { .v_dc_V = 48.0f },
        .encoder_cpr = 10000u,
        .cycle_step = 2u,
        .cycle_hz = HAL_STUB_CYCLE_HZ,
        .pwm_init_status = HAL_OK,
        .pwm_period_s = 0.0f,
        .pwm_delay_periods = HAL_STUB_DELAY_PERIODS,
        .duty_abc = { 0.5f, 0.5f, 0.5f },
    };
}

hal_status_t hal_pwm_init(float f_pwm_Hz, hal_pwm_timing_t *timing)
{
    g_hal.f_pwm_Hz = f_pwm_Hz;
    g_hal.pwm_inits++;
    g_hal.outputs_enabled = false;
    if (g_hal.pwm_init_status != HAL_OK) {
        return g_hal.pwm_init_status;
    }
    timing->period_s = (g_hal.pwm_period_s != 0.0f) ? g_hal.pwm_period_s : 1.0f / f_pwm_Hz;
    timing->delay_periods = g_hal.pwm_delay_periods;
    return HAL_OK;
}

void hal_pwm_set_duties(const float duty_abc[3])
{
    for (int k = 0; k < 3; ++k) {
        g_hal.duty_abc[k] = duty_abc[k];
    }
    g_hal.duty_writes++;
}

void hal_pwm_enable_outputs(void)
{
    g_hal.outputs_enabled = true;
}
void hal_pwm_disable_outputs(void)
{
    g_hal.outputs_enabled = false;
}
bool hal_pwm_outputs_enabled(void)
{
    return g_hal.outputs_enabled;
}
bool hal_pwm_overcurrent_arm(float trip_A)
{
    g_hal.oc_trip_A = g_hal.oc_comparator ? trip_A : 0.0f;
    return g_hal.oc_comparator;
}
bool hal_pwm_overcurrent_active(void)
{
    return g_hal.oc_active;
}
void hal_adc_read(hal_adc_sample_t *out)
{
    *out = g_hal.adc;
}
uint32_t hal_encoder_counts_per_rev(void)
{
    return g_hal.encoder_cpr;
}
uint32_t hal_encoder_count(void)
{
    return g_hal.encoder_count;
}

bool hal_encoder_edge_age(float *age_s)
{
    if (!g_hal.encoder_edge_capture) {
        return false;
    }
    *age_s = g_hal.encoder_edge_age_s;
    return true;
}

bool hal_encoder_index(uint32_t *count_at_index)
{
    if (count_at_index != 0) {
        *count_at_index = 0u;
    }
    return false;
}

uint64_t hal_time_ticks(void)
{
    return 0u;
}
uint32_t hal_time_tick_hz(void)
{
    return 1000000u;
}

uint32_t hal_cycle_counter(void)
{
    const uint32_t v = g_hal.cycle_now;
    g_hal.cycle_now += g_hal.cycle_step;
    return v;
}

uint32_t hal_cycle_counter_hz(void)
{
    return g_hal.cycle_hz;
}
bool hal_gpio_fault_input_active(void)
{
    return g_hal.fault_input;
}
void hal_gpio_power_stage_enable(bool enable)
{
    g_hal.power_stage = enable;
}
void hal_gpio_debug_pin_set(bool level)
{
    (void)level;
}
