/* Default configuration and its validation (see mc/app.h). */
#include <math.h>

#include "mc/angle.h"
#include "mc/app.h"

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
    };
}

mc_status_t mc_config_validate(const mc_config_t *c)
{
    const float f[] = {
        c->R_ohm, c->Ld_H, c->Lq_H, c->psi_Wb, c->J_kgm2, c->B_Nms,
        c->f_pwm_hz, c->encoder_offset_e_rad, c->pll_bandwidth_rad_s,
        c->current_bandwidth_rad_s, c->speed_bandwidth_rad_s,
        c->position_kp_per_s, c->modulation_margin, c->i_max_A,
        c->omega_max_rad_s, c->i_offset_max_A,
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
    /* Algorithm selection. */
    if (c->angle_source != MC_ANGLE_SOURCE_ENCODER ||
        c->controller != MC_CONTROLLER_FOC_PI) {
        return MC_ERR_PARAM;
    }
    return MC_OK;
}
