/* Application init and the command / telemetry exchange with the fast ISR
 * (see mc/app.h). */
#include <stdatomic.h>

#include "app_internal.h"
#include "dispatch.h"
#include "hal/encoder.h"
#include "hal/gpio.h"
#include "hal/pwm.h"
#include "hal/time.h"

/* Tries of a telemetry read before giving up (the ISR rewrote the snapshot
 * during every copy: only possible if the reader is starved). */
#define MC_TLM_READ_TRIES 4u

/* The largest cycle count c whose cost (float)c * s_per_cycle, as the ISR
 * computes it, is at most period_s: the ISR's deadline test compares
 * counts (cost > period exactly when count > this; the cost is
 * non-decreasing in the count). s_per_cycle > 0, period_s > 0 and
 * finite (validated timing). */
static uint32_t deadline_cycles(float period_s, float s_per_cycle)
{
    const float estimate = period_s / s_per_cycle;
    uint32_t c = (estimate < 4.0e9f) ? (uint32_t)estimate : 4000000000u;
    while (c > 0u && (float)c * s_per_cycle > period_s) {
        --c;
    }
    while (c < 4000000000u && (float)(c + 1u) * s_per_cycle <= period_s) {
        ++c;
    }
    return c;
}

mc_status_t mc_app_init(mc_app_t *app, const mc_config_t *cfg)
{
    mc_status_t st = mc_config_validate(cfg);
    if (st != MC_OK) {
        return st;
    }
    if (hal_cycle_counter_hz() == 0u) {
        return MC_ERR_PARAM;
    }
    hal_pwm_timing_t hw;
    if (hal_pwm_init(cfg->timing.f_pwm_Hz, &hw) != HAL_OK) {
        return MC_ERR_PARAM;
    }
    hal_pwm_disable_outputs();
    hal_gpio_power_stage_enable(false);
    mc_timing_t tm;
    st = mc_timing_init(&tm, &cfg->timing, hw.period_s, hw.delay_periods);
    if (st != MC_OK) {
        return st;
    }
    *app = (mc_app_t){ 0 };
    st = mc_app_configure(app, cfg, &tm);
    if (st != MC_OK) {
        return st;
    }
    app->oc_in_hardware = hal_pwm_overcurrent_arm(cfg->protection.i_trip_A);
    const uint32_t cpr = app->est_info.encoder_cpr;
    if (cpr != 0u && cpr != hal_encoder_counts_per_rev()) {
        return MC_ERR_PARAM;
    }
    app->s_per_cycle = 1.0f / (float)hal_cycle_counter_hz();
    app->period_cycles = deadline_cycles(tm.Ts_s, app->s_per_cycle);
    app->state = MC_STATE_IDLE;
    app->enable_armed = true;
    app->cmd_buf[0].mode = MC_MODE_CURRENT;
    app->cmd_buf[1].mode = MC_MODE_CURRENT;
    app->cmd_run_key[0] =
        mc_app_run_key(false, false, false, false, MC_MODE_CURRENT);
    app->cmd_run_key[1] = app->cmd_run_key[0];
    app->steady_key = MC_APP_NO_RUN_KEY;
    *mc_app_tlm_begin(app) = (mc_telemetry_t){
        .state = MC_STATE_IDLE,
        .mode = MC_MODE_CURRENT,
        .duty_abc = { 0.5f, 0.5f, 0.5f },
    };
    mc_app_tlm_end(app);
    return MC_OK;
}

mc_status_t mc_app_set_command(mc_app_t *app, const mc_command_t *cmd)
{
    if (cmd->mode != MC_MODE_CURRENT && cmd->mode != MC_MODE_SPEED &&
        cmd->mode != MC_MODE_POSITION) {
        return MC_ERR_PARAM;
    }
    /* Write the buffer the ISR is not reading, then flip the index (a
     * single aligned 32-bit store). The ISR preempts this function, never
     * the reverse, so it always copies a complete command. */
    const uint32_t next = (app->cmd_index + 1u) & 1u;
    app->cmd_buf[next] = *cmd;
    app->cmd_run_key[next] =
        mc_app_run_key(cmd->enable, cmd->comm_lost, cmd->clear_fault,
                       mc_app_position_ref_nonfinite(cmd), cmd->mode);
    atomic_signal_fence(memory_order_seq_cst);
    app->cmd_index = next;
    return MC_OK;
}

mc_status_t mc_app_fault_history(const mc_app_t *app, mc_fault_event_t *out,
                                 uint32_t n, uint32_t *copied)
{
    for (uint32_t k = 0u; k < MC_TLM_READ_TRIES; ++k) {
        const uint32_t s1 = app->history_seq;
        atomic_signal_fence(memory_order_seq_cst);
        const uint32_t count = app->history_count;
        const uint32_t kept =
            (count < MC_FAULT_HISTORY_LEN) ? count : MC_FAULT_HISTORY_LEN;
        const uint32_t m = (n < kept) ? n : kept;
        for (uint32_t j = 0u; j < m; ++j) {
            out[j] = app->history[(count - 1u - j) % MC_FAULT_HISTORY_LEN];
        }
        atomic_signal_fence(memory_order_seq_cst);
        if (s1 == app->history_seq && (s1 & 1u) == 0u) {
            *copied = m;
            return MC_OK;
        }
    }
    *copied = 0u;
    return MC_ERR_STATE;
}

const mc_timing_t *mc_app_timing(const mc_app_t *app)
{
    return &app->timing;
}

mc_status_t mc_app_get_telemetry(const mc_app_t *app, mc_telemetry_t *out)
{
    for (uint32_t k = 0u; k < MC_TLM_READ_TRIES; ++k) {
        const uint32_t s1 = app->tlm_seq;
        atomic_signal_fence(memory_order_seq_cst);
        *out = app->tlm;
        const uint32_t cost_cycles = app->isr_cost_cycles;
        const uint32_t cost_max_cycles = app->isr_cost_max_cycles;
        atomic_signal_fence(memory_order_seq_cst);
        const uint32_t s2 = app->tlm_seq;
        if (s1 == s2 && (s1 & 1u) == 0u) {
            /* the ISR keeps its costs in cycles (mc/app.h) */
            out->isr_cost_s = (float)cost_cycles * app->s_per_cycle;
            out->isr_cost_max_s = (float)cost_max_cycles * app->s_per_cycle;
            return MC_OK;
        }
    }
    return MC_ERR_STATE;
}
