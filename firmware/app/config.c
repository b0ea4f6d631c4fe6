/* Default configuration and its validation (mc/config.h). Each block
 * checks its own parameters in its init; here: finiteness, the rules
 * between blocks, and the inits on a scratch instance. */
#include <math.h>

#include "app_internal.h"
#include "dispatch.h"
#include "mc/clarke.h"

/* The delay the validation designs with when the configuration leaves it
 * to the HAL (it enters only blocks that accept any valid delay). */
#define MC_CFG_NOMINAL_DELAY_PERIODS 1.0f

void mc_config_init_default(mc_config_t *cfg)
{
    *cfg = (mc_config_t){
        .controller = MC_CONTROLLER_FOC_PI,
        .estimator = MC_ESTIMATOR_ENCODER,
        /* Paper 001, Section 5 motor (non-salient: Ld = Lq = L). */
        .motor = { .R_ohm = 0.225f,
                   .Ld_H = 3.8e-3f,
                   .Lq_H = 3.8e-3f,
                   .psi_Wb = 0.17f,
                   .pole_pairs = 3u,
                   .J_kgm2 = 0.012f,
                   .B_Nm_s_rad = 0.0f },
        /* 20 kHz fast ISR, 2 kHz slow loop, 25.6 ms offset calibration
         * (512 samples); three consecutive overruns (mc/app.h, deadline);
         * the sample-to-apply delay of the HAL, compensated; the
         * telemetry of every ISR (an MCU build that does not need it
         * spares its stores in most ISRs). */
        .timing = { .f_pwm_Hz = 20000.0f,
                    .slow_loop_Hz = 2000.0f,
                    .calib_time_s = 0.0256f,
                    .isr_overrun_limit = 3u,
                    .delay_periods = 0.0f,
                    .delay_compensation = true,
                    .telemetry_every_isr = true },
        /* 10 A = 7.65 N m; 40 rad/s mech: back-EMF 20.4 V < 0.95*48/sqrt3. */
        .limits = { .i_max_A = 10.0f, .omega_max_rad_s = 40.0f },
        /* Trip at 2 i_max; 48 V bus within [20, 60] V; estimates: twice
         * the speed limit, twice the torque at i_max (7.65 N m).
         * Overspeed at 1.2 x the speed limit, 48 rad/s: the line back-EMF
         * there, sqrt(3) n_p psi w = 42.4 V, stays below the over-voltage
         * trip, so coasting (PWM off, the fault reaction) cannot charge the
         * bus above it (rule in mc_config_validate). Stall: above 0.7 i_max
         * below 1 rad/s for 0.5 s (the benchmark's largest current is
         * 1.5 A; the alignment runs 2 A at standstill, not in RUN). The
         * current-limit loop at 1.1 i_max, 11 A, below the trip, for at
         * most 0.1 s (the FOC's own current loop holds i_max within 4 %
         * when its angle is right: the limit loop acts only when the
         * controller is wrong). Thermal:
         * 5 A continuous, i_max for 2 s from cold (150 A^2 s). Sensor sum:
         * 1 A for 1 ms (20 samples; 10 mA RMS noise per phase makes a
         * 17 mA RMS sum). */
        .protection = { .i_trip_A = 20.0f,
                        .v_dc_max_V = 60.0f,
                        .v_dc_min_V = 20.0f,
                        .i_offset_max_A = 2.0f,
                        .estimate_omega_max_rad_s = 80.0f,
                        .estimate_tau_max_Nm = 15.0f,
                        .overspeed_rad_s = 48.0f,
                        .stall_current_A = 7.0f,
                        .stall_speed_rad_s = 1.0f,
                        .stall_time_s = 0.5f,
                        .current_limit_A = 11.0f,
                        .current_limit_time_s = 0.1f,
                        .i2t_continuous_A = 5.0f,
                        .i2t_peak_A = 10.0f,
                        .i2t_peak_time_s = 2.0f,
                        .current_sum_max_A = 1.0f,
                        .current_sum_time_s = 0.001f },
        /* Back-EMF plausibility (mc/emf_monitor.h): 20 ms filter, 0.1 s to
         * fault, 0.5 V floor, estimates checked above 3 electrical rad/s
         * (0.5 V on this motor); an encoder slip of more than 45 deg, a
         * back-EMF twice the encoder's, a sensorless back-EMF below half the
         * estimate's. */
        .emf_check = { .filter_s = 0.02f,
                       .check_time_s = 0.1f,
                       .min_V = 0.5f,
                       .min_speed_e_rad_s = 3.0f,
                       .angle_max_rad = 0.785398163f,
                       .ratio_low = 0.5f,
                       .ratio_high = 2.0f },
        /* Current loop 400 Hz (w_c Ts = 0.126). */
        .current = { .bandwidth_rad_s = 2513.0f, .modulation_margin = 0.95f },
        /* No dead time unless the board states one (the bench: the
         * plant's); compensated when it does, with a 0.2 A band: the
         * current ripple's amplitude on this motor, v_dc Ts / (4 L) =
         * 0.16 A at 48 V, inside which the ripple itself crosses zero. */
        .deadtime = { .dead_time_s = 0.0f,
                      .device_drop_V = 0.0f,
                      .current_band_A = 0.2f,
                      .compensation = true },
        /* Position 1/4 of the default speed-loop bandwidth. */
        .position = { .kp_per_s = 12.5f },
        /* 2 A (1.53 N m of alignment torque per electrical rad: omega_n
         * = sqrt(n_p kt I / J) = 19.6 rad/s), ramped over 0.1 s;
         * critically damped (k_d = 0.204 A per electrical rad/s), the
         * damping current limited to 2 A (|i| <= 2.83 A). Settled: below
         * 0.25 electrical rad/s for 0.2 s, i.e. |sin(delta)| <~ 2 * 0.25
         * / (19.6^2 * 0.2) = 6.5e-3 (phase 1: 10x looser, 0.065; see
         * mc/align.h); the critically damped rotor decays by
         * (1 + w_n t) e^(-w_n t) = 0.1 more during the 0.2 s hold. The
         * threshold sits above the speed estimate's noise with real
         * sensors: 10 mA RMS per phase and 12-bit converters move it by up
         * to 0.1 rad/s (its L di/dt term; at 0.1 or below it never
         * settles). Timeout 2 s: each phase needs about 0.6 s from 90 deg
         * away. */
        .align = { .current_A = 2.0f,
                   .ramp_s = 0.1f,
                   .timeout_s = 2.0f,
                   .angle_e_rad = 0.0f,
                   .damping_ratio = 1.0f,
                   .i_q_max_A = 2.0f,
                   .settle_speed_e_rad_s = 0.25f,
                   .settle_time_s = 0.2f },
    };
    mc_flux_obs_config_default(&cfg->flux_obs);
#define MC_X_DEFAULT(name, NAME) mc_ctl_##name##_config_default(&cfg->name);
    MC_CONTROLLERS(MC_X_DEFAULT)
#undef MC_X_DEFAULT
#define MC_X_DEFAULT(name, NAME) mc_est_##name##_config_default(&cfg->name);
    MC_ESTIMATORS(MC_X_DEFAULT)
#undef MC_X_DEFAULT
}

mc_estimator_info_t mc_config_estimator_info(const mc_config_t *cfg)
{
    mc_estimator_info_t info = { 0 };
    (void)mc_dispatch_estimator_info(cfg, &info);
    return info;
}

/* Every float of the configuration is finite (from the parameter table). */
static bool all_floats_finite(const mc_config_t *c)
{
    const unsigned char *base = (const unsigned char *)c;
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        for (const mc_param_t *p = b->params; p->name != NULL; ++p) {
            if (p->type == MC_PARAM_F32) {
                const float *x =
                    (const float *)(const void *)(base + b->offset + p->offset);
                if (!isfinite(*x)) {
                    return false;
                }
            }
        }
    }
    return true;
}

/* Rules between blocks. */
static mc_status_t cross_block_rules(const mc_config_t *c,
                                     const mc_estimator_info_t *est)
{
    const float i_max = c->limits.i_max_A;
    const mc_fault_limits_t *p = &c->protection;
    if (!(i_max < p->i_trip_A) || !(p->current_limit_A >= i_max)) {
        return MC_ERR_PARAM;
    }
    /* Overspeed above the speed limit, and low enough that the fault
     * reaction, coasting with the PWM off, cannot charge the bus to the
     * over-voltage trip: the diodes conduct once the line back-EMF peak
     * sqrt(3) n_p psi omega exceeds the bus. */
    const float e_line_V = MC_SQRT3_F * (float)c->motor.pole_pairs *
                           c->motor.psi_Wb * p->overspeed_rad_s;
    if (!(p->overspeed_rad_s > c->limits.omega_max_rad_s) ||
        !(e_line_V < p->v_dc_max_V)) {
        return MC_ERR_PARAM;
    }
    if (est->sensorless) {
        /* The ALIGN vector and its damping current within i_max. */
        const mc_align_config_t *a = &c->align;
        if (!(a->current_A < i_max) ||
            a->current_A * a->current_A + a->i_q_max_A * a->i_q_max_A >
                i_max * i_max) {
            return MC_ERR_PARAM;
        }
    }
    return MC_OK;
}

mc_status_t mc_config_validate(const mc_config_t *c)
{
    if (!all_floats_finite(c)) {
        return MC_ERR_NONFINITE;
    }
    mc_estimator_info_t est;
    if ((uint32_t)c->controller >= (uint32_t)MC_CONTROLLER_COUNT ||
        !mc_dispatch_estimator_info(c, &est)) {
        return MC_ERR_PARAM;
    }
    mc_status_t st = mc_motor_validate(&c->motor);
    if (st == MC_OK) {
        st = mc_fault_limits_validate(&c->protection);
    }
    if (st != MC_OK) {
        return st;
    }
    const float f_pwm = c->timing.f_pwm_Hz;
    const float Ts = (f_pwm > 0.0f) ? 1.0f / f_pwm : 0.0f;
    mc_timing_t tm;
    st = mc_timing_init(&tm, &c->timing, Ts, MC_CFG_NOMINAL_DELAY_PERIODS);
    if (st == MC_OK) {
        st = cross_block_rules(c, &est);
    }
    if (st != MC_OK) {
        return st;
    }
    mc_app_t scratch;
    return mc_app_configure(&scratch, c, &tm);
}
