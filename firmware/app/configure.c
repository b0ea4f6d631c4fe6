/* Designing every block of the application from a configuration and a
 * timing record (app_internal.h): used by mc_app_init and, on a scratch
 * instance, by mc_config_validate. No HAL call here, so a configuration
 * can be validated without a HAL backend. */
#include <float.h>

#include "app_internal.h"
#include "dispatch.h"

/* The blocks every controller shares (mc/drive.h). */
static mc_status_t drive_init(mc_drive_t *d, const mc_config_t *c,
                              const mc_timing_t *tm)
{
    const mc_current_loop_params_t cp = {
        .cfg = c->current,
        .R_ohm = c->motor.R_ohm,
        .Ld_H = c->motor.Ld_H,
        .Lq_H = c->motor.Lq_H,
        .psi_Wb = c->motor.psi_Wb,
        .Ts_s = tm->Ts_s,
    };
    mc_status_t st = mc_current_loop_init_f32(&d->current, &cp);
    if (st != MC_OK) {
        return st;
    }
    const mc_outer_loop_params_t op = {
        .position_kp_per_s = c->position.kp_per_s,
        .omega_max_rad_s = c->limits.omega_max_rad_s,
        .i_max_A = c->limits.i_max_A,
    };
    st = mc_outer_loop_init_f32(&d->outer, &op);
    if (st != MC_OK) {
        return st;
    }
    const mc_current_limit_params_t lp = {
        .limit_A = c->protection.current_limit_A,
        .R_ohm = c->motor.R_ohm,
        .L_H = c->motor.Lq_H,
        .bandwidth_rad_s = c->current.bandwidth_rad_s,
        .Ts_s = tm->Ts_s,
    };
    st = mc_current_limit_init_f32(&d->limit, &lp);
    if (st != MC_OK) {
        return st;
    }
    st = mc_deadtime_comp_init_f32(&d->deadtime, &c->deadtime, tm->Ts_s,
                                   c->protection.v_dc_min_V);
    d->n_p = (float)c->motor.pole_pairs;
    d->v_d_last_V = 0.0f;
    d->v_q_last_V = 0.0f;
    return st;
}

/* The ALIGN sequence of a sensorless start (mc/align.h). */
static mc_status_t align_init(mc_align_f32_t *a, const mc_config_t *c,
                              const mc_timing_t *tm)
{
    const mc_align_params_t ap = {
        .cfg = c->align,
        .R_ohm = c->motor.R_ohm,
        .L_H = c->motor.Lq_H,
        .psi_Wb = c->motor.psi_Wb,
        .J_kgm2 = c->motor.J_kgm2,
        .kt_Nm_per_A = mc_motor_kt_f32(&c->motor),
        .pole_pairs = c->motor.pole_pairs,
        .Ts_s = tm->Ts_s,
    };
    return mc_align_init_f32(a, &ap);
}

mc_status_t mc_app_configure(mc_app_t *app, const mc_config_t *cfg,
                             const mc_timing_t *tm)
{
    app->cfg = *cfg;
    app->timing = *tm;
    /* v_dc_min_V = 0 (the under-voltage check off) still rejects a bus
     * the modulator cannot divide by: at or below 0 V, or subnormal */
    app->protection_powered = cfg->protection;
    if (!(cfg->protection.v_dc_min_V >= FLT_MIN)) {
        app->protection_powered.v_dc_min_V = FLT_MIN;
    }
    if (!mc_dispatch_estimator_info(cfg, &app->est_info)) {
        return MC_ERR_PARAM;
    }
    mc_status_t st = drive_init(&app->drive, cfg, tm);
    if (st == MC_OK) {
        st = mc_supervisor_init(&app->supervisor, &cfg->protection,
                                tm->Ts_slow_s);
    }
    if (st == MC_OK) {
        const mc_emf_monitor_params_t ep = {
            .R_ohm = cfg->motor.R_ohm,
            .L_H = cfg->motor.Lq_H,
            .psi_Wb = cfg->motor.psi_Wb,
            .Ts_s = tm->Ts_s,
            .filter_s = cfg->emf_check.filter_s,
            .decimation = tm->slow_decimation,
        };
        st = mc_emf_check_init_f32(&app->emf, &cfg->emf_check, &ep);
    }
    if (st == MC_OK) {
        st = mc_dispatch_estimator_init(app, cfg, tm);
    }
    if (st == MC_OK) {
        st = mc_dispatch_controller_init(app, cfg, tm);
    }
    if (st == MC_OK && app->est_info.sensorless) {
        st = align_init(&app->align, cfg, tm);
    }
    if (st == MC_OK) {
        st = mc_delay_comp_init_f32(&app->delay_comp, tm->Ts_s,
                                    tm->delay_periods, tm->delay_compensation);
    }
    if (st == MC_OK) {
        st = mc_applied_voltage_init_f32(&app->v_applied, tm->delay_periods);
    }
    return st;
}
