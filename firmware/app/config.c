/* Default configuration and its validation (see mc/app.h). */
#include <math.h>

#include "app_internal.h"
#include "mc/angle.h"

#define MC_CFG_F_PWM_MIN_HZ 1000.0f
#define MC_CFG_F_PWM_MAX_HZ 100000.0f
#define MC_CFG_DECIMATION_MAX 1000u
#define MC_CFG_CALIB_SAMPLES_MAX 65536u
#define MC_CFG_OVERRUN_LIMIT_MAX 100u
#define MC_CFG_POLE_PAIRS_MAX 64u
#define MC_CFG_CPR_MIN 4u
#define MC_CFG_CPR_MAX (1u << 24)
/* Current loop with the 1.5-period delay: phase margin
 * 90 deg - 1.5 w_c Ts rad >= 47 deg for w_c Ts <= 0.5. */
#define MC_CFG_CURRENT_WTS_MAX 0.5f
/* Speed loop: at least 5x below the current loop, and w_s Ts_slow <= 0.2. */
#define MC_CFG_SPEED_TO_CURRENT_MAX 0.2f
#define MC_CFG_SPEED_WTS_MAX 0.2f
/* PLL at least 2x above the speed loop it feeds. */
#define MC_CFG_SPEED_TO_PLL_MAX 0.5f
#define MC_CFG_PLL_WTS_MAX 0.5f
#define MC_CFG_ALIGN_TIME_MAX_S 10.0f

void mc_config_init_default(mc_config_t *cfg)
{
    *cfg = (mc_config_t){
        /* Paper 001, Section 5 motor (non-salient: Ld = Lq = L). */
        .R_ohm = 0.225f,
        .Ld_H = 3.8e-3f,
        .Lq_H = 3.8e-3f,
        .psi_Wb = 0.17f,
        .pole_pairs = 3u,
        .J_kgm2 = 0.012f,
        .B_Nms = 0.0f,
        /* 20 kHz fast ISR, 2 kHz slow loop, 25.6 ms offset calibration. */
        .f_pwm_hz = 20000.0f,
        .speed_loop_decimation = 10u,
        .calib_samples = 512u,
        /* Three consecutive overruns: see mc/app.h (deadline). */
        .isr_overrun_limit = 3u,
        /* 2500-line encoder (x4), aligned: count 0 at theta_e = 0. */
        .encoder_cpr = 10000u,
        .encoder_offset_e_rad = 0.0f,
        .pll_bandwidth_rad_s = 1000.0f, /* 20 w_s: lag 2/w_pll = 2 ms */
        /* Current loop 400 Hz (w_c Ts = 0.126), speed loop 8 Hz
         * (w_s Ts_slow = 0.025), position 1/4 of the speed bandwidth. */
        .current_bandwidth_rad_s = 2513.0f,
        .speed_bandwidth_rad_s = 50.0f,
        .position_kp_per_s = 12.5f,
        .modulation_margin = 0.95f,
        /* 10 A = 7.65 N m; 40 rad/s mech: back-EMF 20.4 V < 0.95*48/sqrt3. */
        .i_max_A = 10.0f,
        .omega_max_rad_s = 40.0f,
        .i_offset_max_A = 2.0f,
        .fault_limits = { .i_trip_A = 20.0f, .v_dc_max_V = 60.0f,
                          .v_dc_min_V = 20.0f },
        .angle_source = MC_ANGLE_SOURCE_ENCODER,
        .controller = MC_CONTROLLER_FOC_PI,
        /* Paper 001, Section 5 observer gains. */
        .flux_obs_gamma = MC_FLUX_OBS_GAMMA_DEFAULT,
        .speed_obs_a1 = MC_SPEED_LOAD_OBS_A1_DEFAULT,
        .speed_obs_a2 = MC_SPEED_LOAD_OBS_A2_DEFAULT,
        /* NAM PLL: 2x the speed loop (the rule of the encoder PLL). */
        .sensorless_pll_bandwidth_rad_s = 100.0f,
        /* Twice the speed limit; twice the torque at i_max (7.65 N m). */
        .est_omega_max_rad_s = 80.0f,
        .est_tau_max_Nm = 15.0f,
        .est_flux_ratio_min = 0.5f,
        .est_flux_ratio_max = 1.5f,
        /* The drive's timing: sample at t_k, duties applied over
         * [t_k + Ts, t_k + 2 Ts] (mc/delay_comp.h, d = 1.5). */
        .delay_comp_enabled = true,
        .delay_periods = MC_DELAY_PERIODS_DEFAULT,
        .idapbc_r_ohm = 0.0f,
        /* Integral action off (the paper's scheme). When on: slow pole
         * 10 1/s (the pair at -87.5 1/s, mc/idapbc.h; offsets decay as
         * e^(-10 t)); tau_I limited to 2.5 N m, a third of kt i_max and
         * twice what flux +15 % needs at 120 rpm (0.15 n_p Phi w r^-1 kt
         * = 1.3 N m, full-information estimate). */
        .idapbc_integral_enabled = false,
        .idapbc_integral_pole_rad_s = 10.0f,
        .idapbc_integral_tau_max_Nm = 2.5f,
        /* 2 A (1.53 N m of alignment torque per electrical rad: omega_n
         * = sqrt(n_p kt I / J) = 19.6 rad/s), ramped over 0.1 s;
         * critically damped (k_d = 0.204 A per electrical rad/s), the
         * damping current limited to 2 A (|i| <= 2.83 A). Settled: below
         * 0.002 electrical rad/s for 50 ms, i.e. |sin(delta)| <~ 2 * 0.002
         * / (19.6^2 * 0.05) = 2.1e-4 (phase 1: 10x looser, 2.1e-3; see
         * mc/align.h). Timeout 2 s: each phase needs about 0.4 s from
         * 90 deg away. */
        .align_current_A = 2.0f,
        .align_ramp_s = 0.1f,
        .align_time_s = 2.0f,
        .align_angle_e_rad = 0.0f,
        .align_damping_ratio = 1.0f,
        .align_i_q_max_A = 2.0f,
        .align_settle_speed_e_rad_s = 0.002f,
        .align_settle_time_s = 0.05f,
    };
}

/* Algorithm selection and the sensorless fields; the observers' and the
 * delay compensation's own checks (Euler stability, ranges) run on a
 * scratch instance (about 0.9 kB of stack, configuration time only). */
static mc_status_t validate_sensorless(const mc_config_t *c)
{
    const bool src_ok = c->angle_source == MC_ANGLE_SOURCE_ENCODER ||
                        c->angle_source == MC_ANGLE_SOURCE_FLUX_OBSERVER;
    const bool ctl_ok = c->controller == MC_CONTROLLER_FOC_PI ||
                        (c->controller == MC_CONTROLLER_IDAPBC &&
                         c->angle_source == MC_ANGLE_SOURCE_FLUX_OBSERVER);
    if (!src_ok || !ctl_ok) {
        return MC_ERR_PARAM;
    }
    /* NAM: the speed loop at most half the PLL bandwidth that feeds it. */
    const bool nam = c->angle_source == MC_ANGLE_SOURCE_FLUX_OBSERVER &&
                     c->controller == MC_CONTROLLER_FOC_PI;
    if (!(c->sensorless_pll_bandwidth_rad_s > 0.0f) ||
        (nam && c->speed_bandwidth_rad_s >
                    MC_CFG_SPEED_TO_PLL_MAX *
                        c->sensorless_pll_bandwidth_rad_s)) {
        return MC_ERR_PARAM;
    }
    if (!(c->est_omega_max_rad_s > 0.0f) || !(c->est_tau_max_Nm > 0.0f) ||
        !(c->est_flux_ratio_min > 0.0f) || !(c->est_flux_ratio_min < 1.0f) ||
        !(c->est_flux_ratio_max > 1.0f) || c->idapbc_r_ohm < 0.0f ||
        !(c->idapbc_integral_pole_rad_s > 0.0f) ||
        !(c->idapbc_integral_tau_max_Nm > 0.0f)) {
        return MC_ERR_PARAM;
    }
    if (!(c->align_current_A > 0.0f) || !(c->align_current_A < c->i_max_A) ||
        c->align_ramp_s < 0.0f || c->align_ramp_s > c->align_time_s ||
        !(c->align_time_s > 0.0f) ||
        c->align_time_s > MC_CFG_ALIGN_TIME_MAX_S ||
        fabsf(c->align_angle_e_rad) > MC_TWO_PI_F ||
        !(c->align_i_q_max_A > 0.0f) ||
        c->align_current_A * c->align_current_A +
                c->align_i_q_max_A * c->align_i_q_max_A >
            c->i_max_A * c->i_max_A) {
        return MC_ERR_PARAM;
    }
    mc_app_t scratch = { .Ts_s = 1.0f / c->f_pwm_hz };
    return mc_app_sensorless_init(&scratch, c);
}

mc_status_t mc_config_validate(const mc_config_t *c)
{
    const float f[] = {
        c->R_ohm, c->Ld_H, c->Lq_H, c->psi_Wb, c->J_kgm2, c->B_Nms,
        c->f_pwm_hz, c->encoder_offset_e_rad, c->pll_bandwidth_rad_s,
        c->current_bandwidth_rad_s, c->speed_bandwidth_rad_s,
        c->position_kp_per_s, c->modulation_margin, c->i_max_A,
        c->omega_max_rad_s, c->i_offset_max_A, c->flux_obs_gamma,
        c->speed_obs_a1, c->speed_obs_a2, c->sensorless_pll_bandwidth_rad_s,
        c->est_omega_max_rad_s, c->est_tau_max_Nm, c->est_flux_ratio_min,
        c->est_flux_ratio_max, c->delay_periods, c->idapbc_r_ohm,
        c->idapbc_integral_pole_rad_s, c->idapbc_integral_tau_max_Nm,
        c->align_current_A, c->align_ramp_s, c->align_time_s,
        c->align_angle_e_rad, c->align_damping_ratio, c->align_i_q_max_A,
        c->align_settle_speed_e_rad_s, c->align_settle_time_s,
    };
    if (!mc_all_finite_f32(f, (uint32_t)(sizeof f / sizeof f[0]))) {
        return MC_ERR_NONFINITE;
    }
    mc_status_t st = mc_fault_limits_validate(&c->fault_limits);
    if (st != MC_OK) {
        return st;
    }
    /* Motor. */
    if (c->R_ohm < 0.0f || !(c->Ld_H > 0.0f) || !(c->Lq_H > 0.0f) ||
        !(c->psi_Wb > 0.0f) || c->pole_pairs < 1u ||
        c->pole_pairs > MC_CFG_POLE_PAIRS_MAX || !(c->J_kgm2 > 0.0f) ||
        c->B_Nms < 0.0f) {
        return MC_ERR_PARAM;
    }
    /* Timing. */
    if (c->f_pwm_hz < MC_CFG_F_PWM_MIN_HZ || c->f_pwm_hz > MC_CFG_F_PWM_MAX_HZ ||
        c->speed_loop_decimation < 1u ||
        c->speed_loop_decimation > MC_CFG_DECIMATION_MAX ||
        c->calib_samples < 1u || c->calib_samples > MC_CFG_CALIB_SAMPLES_MAX ||
        c->isr_overrun_limit < 1u ||
        c->isr_overrun_limit > MC_CFG_OVERRUN_LIMIT_MAX) {
        return MC_ERR_PARAM;
    }
    const float Ts = 1.0f / c->f_pwm_hz;
    const float Ts_slow = Ts * (float)c->speed_loop_decimation;
    /* Encoder: the count must move by less than cpr/2 per sample at the
     * speed limit, i.e. omega_max Ts < pi. */
    if (c->encoder_cpr < MC_CFG_CPR_MIN || c->encoder_cpr > MC_CFG_CPR_MAX ||
        fabsf(c->encoder_offset_e_rad) > MC_TWO_PI_F ||
        !(c->pll_bandwidth_rad_s > 0.0f) ||
        c->pll_bandwidth_rad_s * Ts > MC_CFG_PLL_WTS_MAX) {
        return MC_ERR_PARAM;
    }
    /* Loop design. */
    if (!(c->current_bandwidth_rad_s > 0.0f) ||
        c->current_bandwidth_rad_s * Ts > MC_CFG_CURRENT_WTS_MAX ||
        !(c->speed_bandwidth_rad_s > 0.0f) ||
        c->speed_bandwidth_rad_s >
            MC_CFG_SPEED_TO_CURRENT_MAX * c->current_bandwidth_rad_s ||
        c->speed_bandwidth_rad_s * Ts_slow > MC_CFG_SPEED_WTS_MAX ||
        c->speed_bandwidth_rad_s >
            MC_CFG_SPEED_TO_PLL_MAX * c->pll_bandwidth_rad_s ||
        !(c->position_kp_per_s > 0.0f) ||
        c->position_kp_per_s > c->speed_bandwidth_rad_s ||
        !(c->modulation_margin > 0.0f) || c->modulation_margin > 1.0f) {
        return MC_ERR_PARAM;
    }
    /* Limits. */
    if (!(c->i_max_A > 0.0f) || !(c->i_max_A < c->fault_limits.i_trip_A) ||
        !(c->omega_max_rad_s > 0.0f) || c->omega_max_rad_s * Ts >= MC_PI_F ||
        !(c->i_offset_max_A > 0.0f)) {
        return MC_ERR_PARAM;
    }
    return validate_sensorless(c);
}
