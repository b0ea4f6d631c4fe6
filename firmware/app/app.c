/* Application init and the command / telemetry exchange with the fast ISR
 * (see mc/app.h). */
#include <stdatomic.h>

#include "app_internal.h"
#include "hal/encoder.h"
#include "hal/gpio.h"
#include "hal/pwm.h"
#include "hal/time.h"

/* Tries of a telemetry read before giving up (the ISR rewrote the snapshot
 * during every copy: only possible if the reader is starved). */
#define MC_TLM_READ_TRIES 4u

static mc_status_t init_loops(mc_app_t *app, const mc_config_t *c)
{
    const mc_current_loop_params_t cp = {
        .R_ohm = c->R_ohm, .Ld_H = c->Ld_H, .Lq_H = c->Lq_H,
        .psi_Wb = c->psi_Wb, .bandwidth_rad_s = c->current_bandwidth_rad_s,
        .modulation_margin = c->modulation_margin, .Ts_s = app->Ts_s,
    };
    mc_status_t st = mc_current_loop_init_f32(&app->current, &cp);
    if (st != MC_OK) {
        return st;
    }
    const mc_speed_loop_params_t sp = {
        .J_kgm2 = c->J_kgm2, .B_Nms = c->B_Nms,
        .k_t_Nm_per_A = 1.5f * (float)c->pole_pairs * c->psi_Wb,
        .bandwidth_rad_s = c->speed_bandwidth_rad_s, .i_q_max_A = c->i_max_A,
        .Ts_s = app->Ts_s * (float)c->speed_loop_decimation,
    };
    st = mc_speed_loop_init_f32(&app->speed, &sp);
    if (st != MC_OK) {
        return st;
    }
    st = mc_position_loop_init_f32(&app->position, c->position_kp_per_s,
                                   c->omega_max_rad_s);
    if (st != MC_OK) {
        return st;
    }
    st = mc_app_sensorless_init(app, c);
    if (st != MC_OK) {
        return st;
    }
    return mc_encoder_tracker_init_f32(&app->encoder, c->encoder_cpr,
                                   c->pole_pairs, c->encoder_offset_e_rad,
                                   c->pll_bandwidth_rad_s, app->Ts_s);
}

mc_status_t mc_app_init(mc_app_t *app, const mc_config_t *cfg)
{
    mc_status_t st = mc_config_validate(cfg);
    if (st != MC_OK) {
        return st;
    }
    if (hal_encoder_counts_per_rev() != cfg->encoder_cpr ||
        hal_cycle_counter_hz() == 0u) {
        return MC_ERR_PARAM;
    }
    *app = (mc_app_t){0};
    app->cfg = *cfg;
    app->Ts_s = 1.0f / cfg->f_pwm_hz;
    app->s_per_cycle = 1.0f / (float)hal_cycle_counter_hz();
    st = init_loops(app, cfg);
    if (st != MC_OK) {
        return st;
    }
    if (hal_pwm_init(cfg->f_pwm_hz) != HAL_OK) {
        return MC_ERR_PARAM;
    }
    hal_pwm_disable_outputs();
    hal_gpio_power_stage_enable(false);
    app->state = MC_STATE_IDLE;
    app->enable_armed = true;
    app->cmd_buf[0].mode = MC_MODE_CURRENT;
    app->cmd_buf[1].mode = MC_MODE_CURRENT;
    app->cmd = app->cmd_buf[0];
    const mc_telemetry_t t = {
        .state = MC_STATE_IDLE,
        .mode = MC_MODE_CURRENT,
        .duty_abc = { 0.5f, 0.5f, 0.5f },
    };
    mc_app_publish_telemetry(app, &t);
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
    atomic_signal_fence(memory_order_seq_cst);
    app->cmd_index = next;
    return MC_OK;
}

void mc_app_publish_telemetry(mc_app_t *app, const mc_telemetry_t *t)
{
    app->tlm_seq = app->tlm_seq + 1u; /* odd: writing */
    atomic_signal_fence(memory_order_seq_cst);
    app->tlm = *t;
    atomic_signal_fence(memory_order_seq_cst);
    app->tlm_seq = app->tlm_seq + 1u; /* even: complete */
}

mc_status_t mc_app_get_telemetry(const mc_app_t *app, mc_telemetry_t *out)
{
    for (uint32_t k = 0u; k < MC_TLM_READ_TRIES; ++k) {
        const uint32_t s1 = app->tlm_seq;
        atomic_signal_fence(memory_order_seq_cst);
        *out = app->tlm;
        atomic_signal_fence(memory_order_seq_cst);
        const uint32_t s2 = app->tlm_seq;
        if (s1 == s2 && (s1 & 1u) == 0u) {
            return MC_OK;
        }
    }
    return MC_ERR_STATE;
}
