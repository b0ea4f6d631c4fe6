/* Controller "cdobc": paper 002's speed regulator family in the drive
 * (mc/ctl_cdobc.h). */
#include "mc/ctl_cdobc.h"

#include <math.h>

#include "mc/angle.h"
#include "mc/config.h"
#include "mc/encoder_tracker.h"

/* the block models one period of delay beyond the hold (mc/ctl_cdobc.h) */
#define CDOBC_DELAY_MAX_PERIODS 1.75f

const mc_param_t mc_ctl_cdobc_params[] = {
    MC_PARAM(mc_ctl_cdobc_config_t, poly_order, MC_PARAM_U32),
    MC_PARAM(mc_ctl_cdobc_config_t, dead_time_model, MC_PARAM_BOOL),
    MC_PARAM(mc_ctl_cdobc_config_t, cogging_order, MC_PARAM_U32),
    MC_PARAM(mc_ctl_cdobc_config_t, sensor_offset_model, MC_PARAM_BOOL),
    MC_PARAM(mc_ctl_cdobc_config_t, sensor_gain_model, MC_PARAM_BOOL),
    MC_PARAM(mc_ctl_cdobc_config_t, robust_placement, MC_PARAM_BOOL),
    MC_PARAM(mc_ctl_cdobc_config_t, harm_zeta, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, sensor_zeta, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, ctl_pole_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, ref_pole_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, obs_pole_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, kp_d_V_A, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, ki_d_V_As, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, v_max_V, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, omega_min_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, design_speed_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, redesign_rel_tol, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, pid, MC_PARAM_BOOL),
    MC_PARAM(mc_ctl_cdobc_config_t, pid_kp_V_s, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, pid_ki_V, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, pid_kd_V_s2, MC_PARAM_F32),
    MC_PARAM(mc_ctl_cdobc_config_t, pid_feedforward, MC_PARAM_BOOL),
    MC_PARAM(mc_ctl_cdobc_config_t, count_periods, MC_PARAM_U32),
    MC_PARAM_END,
};

void mc_ctl_cdobc_config_default(mc_ctl_cdobc_config_t *c)
{
    /* Paper 002 Section IV: CDOBC with the 6th electrical and Q = 32
     * mechanical harmonics and N = 2, poles -200 / -520 (robust
     * placement, mc/cdobc.h), d-axis PI 120 / 240, 200 V; designed for
     * 500 rpm; PID gains 23, 10, 0.0167 when `pid` is chosen. */
    *c = (mc_ctl_cdobc_config_t){
        .poly_order = 2u,
        .dead_time_model = true,
        .cogging_order = 32u,
        .sensor_offset_model = false,
        .sensor_gain_model = false,
        .robust_placement = true,
        .harm_zeta = 0.03f,
        .sensor_zeta = 0.5f,
        .ctl_pole_rad_s = 200.0f,
        .ref_pole_rad_s = 0.0f,
        .obs_pole_rad_s = 520.0f,
        .kp_d_V_A = 120.0f,
        .ki_d_V_As = 240.0f,
        .v_max_V = 200.0f,
        .omega_min_rad_s = 10.0f,
        .design_speed_rad_s = 52.359878f, /* 500 rpm */
        .redesign_rel_tol = 0.0f,
        .pid = false,
        .pid_kp_V_s = 23.0f,
        .pid_ki_V = 10.0f,
        .pid_kd_V_s2 = 0.0167f,
        .pid_feedforward = false,
        .count_periods = 4u,
    };
}

static void add_harmonic(mc_cdobc_models_t *m, mc_cdobc_axis_t axis,
                         uint32_t order, float zeta)
{
    m->harm[m->n_harm] = (mc_cdobc_harm_t){ axis, order, zeta };
    m->n_harm++;
}

mc_status_t mc_ctl_cdobc_init(mc_ctl_cdobc_t *ctl, const mc_config_t *cfg,
                              const mc_timing_t *tm,
                              const mc_estimator_info_t *est)
{
    const mc_ctl_cdobc_config_t *c = &cfg->cdobc;
    const mc_motor_params_t *m = &cfg->motor;
    if (!(tm->delay_periods <= CDOBC_DELAY_MAX_PERIODS) ||
        !(c->redesign_rel_tol >= 0.0f) || !(c->design_speed_rad_s >= 0.0f) ||
        !(c->sensor_zeta > 0.0f) || !(c->sensor_zeta < 1.0f)) {
        return MC_ERR_PARAM;
    }
    mc_cdobc_params_t p;
    mc_cdobc_params_paper002(&p, tm->Ts_s, MC_CDOBC_KIND_CDOBC);
    p.pole_pairs = m->pole_pairs;
    p.psi_f_Wb = m->psi_Wb;
    p.L_q_H = m->Lq_H;
    p.L_d_H = m->Ld_H;
    p.R_ohm = m->R_ohm;
    p.J_kgm2 = m->J_kgm2;
    p.B_Nms_rad = m->B_Nm_s_rad;
    p.models = (mc_cdobc_models_t){ .poly_order = c->poly_order };
    if (c->dead_time_model) {
        add_harmonic(&p.models, MC_CDOBC_ELEC, 6u, 0.0f);
    }
    if (c->cogging_order != 0u) {
        add_harmonic(&p.models, MC_CDOBC_MECH, c->cogging_order, 0.0f);
    }
    if (c->sensor_offset_model) {
        add_harmonic(&p.models, MC_CDOBC_ELEC, 1u, c->sensor_zeta);
    }
    if (c->sensor_gain_model) {
        add_harmonic(&p.models, MC_CDOBC_ELEC, 2u, c->sensor_zeta);
    }
    p.placement =
        c->robust_placement ? MC_CDOBC_PLACE_ROBUST : MC_CDOBC_PLACE_LITERAL;
    p.harm_zeta = c->harm_zeta;
    p.ctl_pole_rad_s = c->ctl_pole_rad_s;
    p.obs_pole_rad_s = c->obs_pole_rad_s;
    p.omega_min_rad_s = c->omega_min_rad_s;
    p.v_max_V = c->v_max_V;
    p.kp_d_V_A = c->kp_d_V_A;
    p.ki_d_V_As = c->ki_d_V_As;
    mc_status_t st = mc_cdobc_init_f32(&ctl->law, &p, c->design_speed_rad_s);
    if (st != MC_OK) {
        /* a model frequency at or above a quarter of the sampling rate
         * (MC_ERR_RANGE) is a configuration the drive cannot run: the
         * configuration's contract says MC_ERR_PARAM (mc/config.h) */
        return (st == MC_ERR_RANGE) ? MC_ERR_PARAM : st;
    }
    /* (6) with i_d = 0 (mc/cdobc.h) */
    const float np = (float)m->pole_pairs;
    const float c_qd = c->pid_feedforward ? 2.0f * m->B_Nm_s_rad * m->R_ohm /
                                                    (3.0f * np * m->psi_Wb) +
                                                np * m->psi_Wb
                                          : 0.0f;
    st = mc_cdobc_pid_init_f32(&ctl->pid, c->pid_kp_V_s, c->pid_ki_V,
                               c->pid_kd_V_s2, tm->Ts_s, c_qd, c->v_max_V);
    if (st != MC_OK) {
        return st;
    }
    ctl->use_prefilter = c->ref_pole_rad_s != 0.0f;
    if (ctl->use_prefilter) {
        st = mc_cdobc_prefilter_init_f32(&ctl->prefilter, tm->Ts_s,
                                         c->ctl_pole_rad_s, c->ref_pole_rad_s);
        if (st != MC_OK) {
            return st;
        }
    }
    ctl->p = p;
    ctl->use_pid = c->pid;
    ctl->redesign_tol = c->redesign_rel_tol;
    /* observer speed from the count when an encoder gives the angle, else
     * any speed estimate (mc/ctl_cdobc.h) */
    if (c->count_periods > MC_CTL_CDOBC_COUNT_MAX) {
        return MC_ERR_PARAM;
    }
    const uint32_t cpr = est->encoder_cpr;
    const bool counts = c->count_periods != 0u && !est->sensorless &&
                        cpr >= 4u && cpr <= MC_ENCODER_CPR_MAX;
    ctl->cpr = counts ? cpr : 0u;
    ctl->half_cpr = (int32_t)(ctl->cpr / 2u);
    ctl->n_count = counts ? c->count_periods : 0u;
    ctl->count_rad_s =
        counts ? MC_TWO_PI_F / ((float)cpr * (float)c->count_periods * tm->Ts_s)
               : 0.0f;
    ctl->rad_per_count = counts ? MC_TWO_PI_F / (float)cpr : 0.0f;
    ctl->window_s = counts ? (float)c->count_periods * tm->Ts_s : 0.0f;
    ctl->count_next = 0u;
    ctl->count_valid = 0u;
    ctl->count_sum = 0;
    mc_ctl_cdobc_start(ctl);
    return MC_OK;
}

void mc_ctl_cdobc_start(mc_ctl_cdobc_t *ctl)
{
    ctl->restart = true;
    ctl->u_c_prev_V = 0.0f;
    ctl->v_dc_prev_V = 0.0f;
}

void mc_ctl_cdobc_mode_change(mc_ctl_cdobc_t *ctl, mc_drive_t *d,
                              mc_mode_t from, mc_mode_t to,
                              const mc_telemetry_t *t)
{
    if (to == MC_MODE_CURRENT) {
        /* the current loop takes over from the regulator's last voltage */
        mc_drive_current_loop_takeover(d, t);
    } else if (from == MC_MODE_CURRENT) {
        /* the regulator restarts at the measured speed; the voltage the
         * current loop left is read back at the next step */
        ctl->restart = true;
        ctl->v_dc_prev_V = t->v_dc_V;
    }
    /* speed <-> position: the regulator continues */
}

void mc_ctl_cdobc_redesign(mc_ctl_cdobc_t *ctl, float omega_ref_rad_s)
{
    mc_cdobc_design_t d;
    mc_cdobc_coef_f32_t k;
    if (mc_cdobc_design_f64(&ctl->p, (double)omega_ref_rad_s, &d) == MC_OK &&
        mc_cdobc_coef_f32(&d, &k) == MC_OK) {
        (void)mc_cdobc_set_coef_f32(&ctl->law, &k);
    }
}
