/* Controller "idapbc": paper 001 eq. (11) in the drive (mc/ctl_idapbc.h). */
#include "mc/ctl_idapbc.h"

#include <math.h>

#include "mc/config.h"

const mc_param_t mc_ctl_idapbc_params[] = {
    MC_PARAM(mc_ctl_idapbc_config_t, r_ohm, MC_PARAM_F32),
    MC_PARAM(mc_ctl_idapbc_config_t, integral_enabled, MC_PARAM_BOOL),
    MC_PARAM(mc_ctl_idapbc_config_t, integral_pole_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_ctl_idapbc_config_t, integral_tau_max_Nm, MC_PARAM_F32),
    MC_PARAM(mc_ctl_idapbc_config_t, paper_rotation, MC_PARAM_BOOL),
    MC_PARAM_END,
};

void mc_ctl_idapbc_config_default(mc_ctl_idapbc_config_t *c)
{
    /* Critical damping; integral action off (the paper's scheme). When on:
     * slow pole 10 1/s (the pair at -87.5 1/s, mc/idapbc.h; offsets decay
     * as e^(-10 t)); tau_I limited to 2.5 N m, a third of kt i_max and
     * twice what flux +15 % needs at 120 rpm (0.15 n_p Phi w r^-1 kt =
     * 1.3 N m, full-information estimate). Rotations by the unit vector
     * of rho_hat's angle, not by rho_hat itself: its magnitude is the
     * flux observer's error, not the machine's, and the printed form
     * passes it on to the current and the voltage. Measured on the
     * paper-001 benchmark (steady speed error at 120 rpm, no delay
     * compensation; tests/sim/test_p001_robust.c and
     * test_p001_paper_figures.c): R +50 % 3.16 rpm with the unit vector
     * against 5.40 rpm as printed, flux +15 % 11.3 against 17.7 rpm,
     * nominal 0.075 rpm either way. */
    *c = (mc_ctl_idapbc_config_t){
        .r_ohm = 0.0f,
        .integral_enabled = false,
        .integral_pole_rad_s = 10.0f,
        .integral_tau_max_Nm = 2.5f,
        .paper_rotation = false,
    };
}

/* Integral action (mc/idapbc.h): a PI on w_ref - w_hat whose output tau_I
 * is limited to +-integral_tau_max_Nm (the integrator too: mc/pi.h's
 * clamping anti-windup). Disabled: kp = ki = 0 is not a valid mc_pi (and
 * never stepped), the instance is zeroed. The parameters are checked
 * either way. */
static mc_status_t integral_init(mc_ctl_idapbc_t *ctl,
                                 const mc_ctl_idapbc_config_t *c,
                                 const mc_idapbc_params_t *ip, float J_kgm2,
                                 float Ts_s)
{
    ctl->integral = (mc_pi_f32_t){ 0 };
    if (!(c->integral_pole_rad_s > 0.0f) || !(c->integral_tau_max_Nm > 0.0f)) {
        return MC_ERR_PARAM;
    }
    if (!c->integral_enabled) {
        return MC_OK;
    }
    float kp;
    float ki;
    const mc_status_t st = mc_idapbc_integral_design_f32(
        ip, J_kgm2, c->integral_pole_rad_s, &kp, &ki);
    if (st != MC_OK) {
        return st;
    }
    const float lim = c->integral_tau_max_Nm;
    return mc_pi_init_f32(&ctl->integral, kp, ki, Ts_s, -lim, lim);
}

mc_status_t mc_ctl_idapbc_init(mc_ctl_idapbc_t *ctl, const mc_config_t *cfg,
                               const mc_timing_t *tm,
                               const mc_estimator_info_t *est)
{
    if (!est->provides_load) {
        return MC_ERR_PARAM; /* (11) needs tau_hat */
    }
    const mc_motor_params_t *m = &cfg->motor;
    const mc_ctl_idapbc_config_t *c = &cfg->idapbc;
    const float kt = mc_motor_kt_f32(m);
    const float inv_kt = 1.0f / kt; /* kt > 0: the motor's validation */
    if (c->r_ohm < 0.0f || !isfinite(inv_kt)) {
        return MC_ERR_PARAM;
    }
    float r = c->r_ohm;
    if (r == 0.0f) {
        r = mc_idapbc_critical_damping_f32(m->pole_pairs, m->psi_Wb, kt,
                                           m->Lq_H, m->J_kgm2);
    }
    /* Non-salient model of the paper: L = Lq (the torque-producing axis). */
    const mc_idapbc_params_t ip = {
        .R_ohm = m->R_ohm,
        .L_H = m->Lq_H,
        .psi_Wb = m->psi_Wb,
        .pole_pairs = m->pole_pairs,
        .kt_Nm_per_A = kt,
        .r_ohm = r,
    };
    mc_status_t st = mc_idapbc_init_f32(&ctl->law, &ip);
    if (st != MC_OK) {
        return st;
    }
    st = integral_init(ctl, c, &ip, m->J_kgm2, tm->Ts_s);
    if (st != MC_OK) {
        return st;
    }
    ctl->integral_enabled = c->integral_enabled;
    ctl->paper_rotation = c->paper_rotation;
    ctl->inv_kt_A_per_Nm = inv_kt;
    ctl->tau_max_Nm = kt * cfg->limits.i_max_A;
    return MC_OK;
}

void mc_ctl_idapbc_start(mc_ctl_idapbc_t *ctl)
{
    mc_pi_reset_f32(&ctl->integral, 0.0f);
}

void mc_ctl_idapbc_mode_change(mc_ctl_idapbc_t *ctl, mc_drive_t *d,
                               mc_mode_t from, mc_mode_t to,
                               const mc_telemetry_t *t)
{
    if (to == MC_MODE_CURRENT) {
        /* The current loop takes over from (11), its integrators stale
         * (ALIGN or an earlier current mode): restart them at (11)'s last
         * voltage, bumpless. */
        mc_drive_current_loop_takeover(d, t);
    } else if (from == MC_MODE_CURRENT) {
        /* (11) takes over: its integral action starts at 0; kept between
         * speed and position ((11) runs in both) */
        mc_pi_reset_f32(&ctl->integral, 0.0f);
    }
}
