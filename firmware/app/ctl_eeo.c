/* Controller "eeo": paper 000's position regulator in the drive
 * (mc/ctl_eeo.h). */
#include "mc/ctl_eeo.h"

#include "mc/angle.h"
#include "mc/config.h"

#define EEO_UNITS_PER_TURN (1u << 24) /* a turn exact in float32 */
#define EEO_FRAC_BITS_MAX  8u

const mc_param_t mc_ctl_eeo_params[] = {
    MC_PARAM(mc_ctl_eeo_config_t, kappa, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, b_bar_Nm_per_Vs, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, k1, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, k2, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, k3, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, N_V, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, g3_bound_per_kgm2, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, g3_amplitude_per_kgm2, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, g3_omega_rad_s, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, g3_phase_rad, MC_PARAM_F32),
    MC_PARAM(mc_ctl_eeo_config_t, matched_start, MC_PARAM_BOOL),
    MC_PARAM_END,
};

void mc_ctl_eeo_config_default(mc_ctl_eeo_config_t *c)
{
    /* Paper 000 Section 6: kappa = 1e3, b_bar = 20, K = (-1 -3 -3),
     * N = 1e7; g3 within 1/J +- 0.5/J unless stated (the paper's 1e4 is
     * 0.55/j on its motor: its scenarios state it); the observer on the
     * constant 1/J (the known schedule is a scenario's choice); matched start
     * (the zero start peaks the observer to hundreds of kV, mc/eeo.h). */
    *c = (mc_ctl_eeo_config_t){
        .kappa = 1e3f,
        .b_bar_Nm_per_Vs = 20.0f,
        .k1 = -1.0f,
        .k2 = -3.0f,
        .k3 = -3.0f,
        .N_V = 1e7f,
        .g3_bound_per_kgm2 = 0.0f,
        .g3_amplitude_per_kgm2 = 0.0f,
        .g3_omega_rad_s = 1.0f,
        .g3_phase_rad = 0.0f,
        .matched_start = true,
    };
}

mc_status_t mc_ctl_eeo_init(mc_ctl_eeo_t *ctl, const mc_config_t *cfg,
                            const mc_timing_t *tm,
                            const mc_estimator_info_t *est)
{
    /* the angle is the encoder count: no sensorless estimator */
    const uint32_t cpr = est->encoder_cpr;
    if (est->sensorless || cpr < 4u || cpr > EEO_UNITS_PER_TURN) {
        return MC_ERR_PARAM;
    }
    const mc_ctl_eeo_config_t *c = &cfg->eeo;
    const mc_motor_params_t *m = &cfg->motor;
    const float g3 = 1.0f / m->J_kgm2;
    const float bound =
        (c->g3_bound_per_kgm2 == 0.0f) ? 0.5f * g3 : c->g3_bound_per_kgm2;
    const float amp = c->g3_amplitude_per_kgm2;
    if (!isfinite(g3) || !(bound > 0.0f) || !(c->g3_bound_per_kgm2 >= 0.0f) ||
        !(bound < g3) || !(fabsf(amp) <= bound) ||
        !isfinite(c->g3_omega_rad_s) ||
        !(fabsf(c->g3_phase_rad) <= MC_TWO_PI_F)) {
        return MC_ERR_PARAM;
    }
    uint32_t f = 1u;
    while (f < EEO_FRAC_BITS_MAX && (cpr << (f + 1u)) <= EEO_UNITS_PER_TURN) {
        ++f;
    }
    const float units_per_turn = (float)(cpr << f);
    mc_eeo_params_t p;
    mc_eeo_params_paper000(&p, tm->Ts_s, m->pole_pairs, m->J_kgm2,
                           MC_TWO_PI_F / units_per_turn);
    p.g3_min_per_kgm2 = g3 - bound;
    p.g3_max_per_kgm2 = g3 + bound;
    p.kappa = c->kappa;
    p.b_bar_Nm_per_Vs = c->b_bar_Nm_per_Vs;
    p.K[0] = c->k1;
    p.K[1] = c->k2;
    p.K[2] = c->k3;
    p.N_V = c->N_V;
    /* replaced every period by the measured bus (mc/ctl_eeo.h); the
     * over-voltage trip's circle until then */
    p.v_q_max_V = cfg->protection.v_dc_max_V *
                  (1.0f / MC_CTL_EEO_PAPER_TO_DRIVE) * 0.57735027f;
    p.input_delay_steps = (tm->delay_periods >= 1.25f) ? 1u : 0u;
    const mc_status_t st = mc_eeo_init_f32(&ctl->law, &p);
    if (st != MC_OK) {
        return st;
    }
    ctl->cpr = cpr;
    ctl->units_per_count = 1u << f;
    ctl->units_per_rad = units_per_turn / MC_TWO_PI_F;
    ctl->counts_per_rad = (float)cpr / MC_TWO_PI_F;
    ctl->omega_max_rad_s = cfg->limits.omega_max_rad_s;
    ctl->Ts_s = tm->Ts_s;
    ctl->matched = c->matched_start;
    ctl->g3_nominal = g3;
    ctl->g3_amp = amp;
    ctl->g3_dphase = mc_wrap_pi_f32(c->g3_omega_rad_s * tm->Ts_s);
    ctl->g3_phase0 = mc_wrap_pi_f32(c->g3_phase_rad);
    mc_ctl_eeo_start(ctl);
    return MC_OK;
}

void mc_ctl_eeo_start(mc_ctl_eeo_t *ctl)
{
    ctl->primed = false;
    ctl->restart = true;
    ctl->ref_from_pos = true;
    ctl->ref_rad = NAN;
    ctl->ref_units = 0;
    ctl->ref_frac_units = 0.0f;
    ctl->g3_phase = ctl->g3_phase0;
}

void mc_ctl_eeo_mode_change(mc_ctl_eeo_t *ctl, mc_drive_t *d, mc_mode_t from,
                            mc_mode_t to, const mc_telemetry_t *t)
{
    if (to == MC_MODE_CURRENT) {
        /* the current loop takes over from the regulator's last voltage */
        mc_drive_current_loop_takeover(d, t);
    } else if (from == MC_MODE_CURRENT) {
        /* the regulator restarts matched on the error of its next step;
         * a speed reference starts where the rotor is */
        ctl->restart = true;
        ctl->ref_from_pos = true;
        ctl->ref_rad = NAN;
    }
    /* position <-> speed: the regulator and the reference continue */
}
