/*
 * Configuration validation (each rule, with the expected error code, in the
 * block where it lives), the compatibility of controllers and estimators,
 * and the per-sample protection checks against an independent expectation.
 *
 * Rules of an estimator's or a controller's blocks are checked only when
 * that estimator / controller is selected (mc/config.h), so each case
 * selects what makes its rule apply; a few "_off" cases show that a rule of
 * an unselected block does not apply (the same value passes).
 */
#include "mc_test.h"

#include <math.h>
#include <string.h>

#include "mc/app.h"

typedef void (*mutate_fn)(mc_config_t *c);

#define MUT(name, stmt)                                                                            \
    static void name(mc_config_t *c)                                                               \
    {                                                                                              \
        stmt;                                                                                      \
    }
#define SENSORLESS (c->estimator = MC_ESTIMATOR_FLUX_II)
#define NAM        (c->estimator = MC_ESTIMATOR_FLUX_PLL)
#define PAPER      (c->controller = MC_CONTROLLER_IDAPBC, c->estimator = MC_ESTIMATOR_FLUX_II)

/* Motor (mc_motor_validate). */
MUT(r_neg, c->motor.R_ohm = -0.1f)
MUT(r_nan, c->motor.R_ohm = NAN)
MUT(ld_zero, c->motor.Ld_H = 0.0f)
MUT(lq_inf, c->motor.Lq_H = INFINITY)
MUT(psi_zero, c->motor.psi_Wb = 0.0f)
MUT(pp_zero, c->motor.pole_pairs = 0u)
MUT(pp_big, c->motor.pole_pairs = 65u)
MUT(j_zero, c->motor.J_kgm2 = 0.0f)
MUT(b_neg, c->motor.B_Nm_s_rad = -1e-3f)
/* Timing (mc_timing_init). */
MUT(fpwm_low, c->timing.f_pwm_Hz = 500.0f)
MUT(fpwm_high, c->timing.f_pwm_Hz = 2e5f)
MUT(slow_zero, c->timing.slow_loop_Hz = 0.0f)           /* was decimation 0 */
MUT(slow_above_pwm, c->timing.slow_loop_Hz = 30000.0f)  /* N < 1 */
MUT(slow_not_divisor, c->timing.slow_loop_Hz = 3000.0f) /* N = 6.67 */
MUT(calib_zero, c->timing.calib_time_s = 0.0f)          /* was calib_samples 0 */
MUT(calib_short, c->timing.calib_time_s = 1e-5f)        /* round(0.2) = 0 */
MUT(calib_long, c->timing.calib_time_s = 3.3f)          /* 66000 > 65536 */
MUT(overrun_zero, c->timing.isr_overrun_limit = 0u)
MUT(overrun_big, c->timing.isr_overrun_limit = 101u)
MUT(delay_big, c->timing.delay_periods = 2.0f)
MUT(delay_small, c->timing.delay_periods = 0.4f)
MUT(delay_neg, c->timing.delay_periods = -1.0f)
/* Encoder estimator (the default). */
MUT(cpr_small, c->encoder.counts_per_rev = 2u)
MUT(cpr_big, c->encoder.counts_per_rev = MC_ENCODER_CPR_MAX + 1u)
MUT(offset_big, c->encoder.offset_e_rad = 7.0f)
MUT(pll_fast, c->encoder.pll_bandwidth_rad_s = 20000.0f) /* w Ts = 1 */
MUT(wmax_alias, c->limits.omega_max_rad_s = 70000.0f)    /* w Ts > pi */
/* ... not validated with a sensorless estimator. */
MUT(cpr_small_off, (SENSORLESS, c->encoder.counts_per_rev = 2u))
MUT(pll_fast_off, (SENSORLESS, c->encoder.pll_bandwidth_rad_s = 20000.0f))
/* Current loop, setpoint stage. */
MUT(wc_fast, c->current.bandwidth_rad_s = 12000.0f) /* w_c Ts = 0.6 */
MUT(margin_big, c->current.modulation_margin = 1.01f)
MUT(margin_zero, c->current.modulation_margin = 0.0f)
MUT(kp_pos_zero, c->position.kp_per_s = 0.0f)
MUT(imax_trip, c->limits.i_max_A = 20.0f) /* not < trip */
MUT(wmax_zero, c->limits.omega_max_rad_s = 0.0f)
/* FOC_PI controller (the default). */
MUT(ws_slow_loop, c->foc_pi.speed_bandwidth_rad_s = 500.0f) /* w Ts_slow 0.25 */
MUT(ws_vs_wc, (c->current.bandwidth_rad_s = 1000.0f,
               c->foc_pi.speed_bandwidth_rad_s = 300.0f)) /* > w_c / 5 */
MUT(ws_vs_wc_ok, (c->current.bandwidth_rad_s = 1500.0f,
                  c->foc_pi.speed_bandwidth_rad_s = 300.0f))   /* = w_c / 5 */
MUT(ws_vs_pll, c->encoder.pll_bandwidth_rad_s = 90.0f)         /* w_s > w_pll/2 */
MUT(kp_pos_big, c->position.kp_per_s = 60.0f)                  /* > w_s */
MUT(nam_ws_vs_pll, (NAM, c->flux_pll.bandwidth_rad_s = 90.0f)) /* w_s > /2 */
/* Protection (mc_fault_limits_validate: every estimator). */
MUT(offmax_zero, c->protection.i_offset_max_A = 0.0f)
MUT(trip_zero, c->protection.i_trip_A = 0.0f)
MUT(vdc_order, c->protection.v_dc_min_V = 70.0f)
MUT(vdc_nan, c->protection.v_dc_max_V = NAN)
MUT(est_w_zero, c->protection.estimate_omega_max_rad_s = 0.0f)
MUT(est_tau_zero, c->protection.estimate_tau_max_Nm = 0.0f)
/* Protection: the supervision and current-limit fields (mc/faults.h,
 * mc/supervisor.h) and the rules between blocks (config.c). */
MUT(cl_below_imax, c->protection.current_limit_A = 9.99f) /* < limits.i_max_A = 10 */
MUT(cl_at_imax, c->protection.current_limit_A = 10.0f)
MUT(cl_below_trip, c->protection.current_limit_A = 19.99f)
MUT(cl_at_trip, c->protection.current_limit_A = 20.0f) /* not < i_trip_A */
MUT(cl_zero, c->protection.current_limit_A = 0.0f)
MUT(cl_nan, c->protection.current_limit_A = NAN)
MUT(cl_time_zero, c->protection.current_limit_time_s = 0.0f)
MUT(cl_time_short, c->protection.current_limit_time_s = 2e-4f) /* round(0.4) = 0 */
MUT(cl_time_one, c->protection.current_limit_time_s = 5e-4f)   /* one slow tick */
MUT(cl_time_nan, c->protection.current_limit_time_s = NAN)
MUT(os_zero, c->protection.overspeed_rad_s = 0.0f)
MUT(os_at_wmax, c->protection.overspeed_rad_s = 40.0f) /* = limits.omega_max_rad_s */
MUT(os_above_wmax, c->protection.overspeed_rad_s = 40.01f)
MUT(os_inf, c->protection.overspeed_rad_s = INFINITY)
/* Line back-EMF sqrt(3) n_p psi w_os against the over-voltage trip: the
 * boundary from the configuration's own motor and bus (default: 60 V /
 * (sqrt(3) 3 0.17 Wb) = 67.92 rad/s); 1e-6 either side is beyond the float
 * rounding of w_os (6e-8) and of the product (3 roundings, 1.8e-7). */
#define OS_BOUNDARY(c)                                                                             \
    ((double)(c)->protection.v_dc_max_V /                                                          \
     (sqrt(3.0) * (double)(c)->motor.pole_pairs * (double)(c)->motor.psi_Wb))
MUT(os_bemf_at_vdc, c->protection.overspeed_rad_s = (float)(OS_BOUNDARY(c) * (1.0 + 1e-6)))
MUT(os_bemf_below_vdc, c->protection.overspeed_rad_s = (float)(OS_BOUNDARY(c) * (1.0 - 1e-6)))
MUT(os_bemf_higher_bus, (c->protection.v_dc_max_V = 80.0f,
                         c->protection.overspeed_rad_s = (float)(OS_BOUNDARY(c) * (1.0 - 1e-6))))
MUT(os_bemf_higher_psi,
    (c->motor.psi_Wb = 0.25f, c->protection.overspeed_rad_s = 48.0f)) /* 62.4 V > 60 V */
MUT(stall_i_zero, c->protection.stall_current_A = 0.0f)
MUT(stall_w_zero, c->protection.stall_speed_rad_s = 0.0f)
MUT(stall_t_zero, c->protection.stall_time_s = 0.0f)
MUT(stall_t_short, c->protection.stall_time_s = 2e-4f) /* round(0.4) = 0 ticks */
MUT(stall_t_one, c->protection.stall_time_s = 5e-4f)   /* one slow tick */
MUT(i2t_cont_zero, c->protection.i2t_continuous_A = 0.0f)
MUT(i2t_peak_eq, c->protection.i2t_peak_A = 5.0f) /* = i2t_continuous_A */
MUT(i2t_peak_below, c->protection.i2t_peak_A = 4.0f)
MUT(i2t_peak_above, c->protection.i2t_peak_A = 5.01f)
MUT(i2t_time_zero, c->protection.i2t_peak_time_s = 0.0f)
MUT(i2t_peak_nan, c->protection.i2t_peak_A = NAN)
MUT(sum_max_zero, c->protection.current_sum_max_A = 0.0f)
MUT(sum_time_zero, c->protection.current_sum_time_s = 0.0f)
MUT(sum_time_short, c->protection.current_sum_time_s = 2e-4f) /* round(0.4) = 0 */
/* Dead-time compensation (mc/deadtime_comp.h): the error per period as a
 * duty, t_d f + v_f / v_dc_min, at most 0.1 (20 kHz, v_dc_min 20 V). */
MUT(dt_ok, c->deadtime.dead_time_s = 1e-6f)
MUT(dt_neg, c->deadtime.dead_time_s = -1e-6f)
MUT(dt_big, c->deadtime.dead_time_s = 6e-6f)                                          /* 0.12 */
MUT(dt_drop_big, (c->deadtime.dead_time_s = 4e-6f, c->deadtime.device_drop_V = 0.5f)) /* 0.105 */
MUT(dt_band_zero, c->deadtime.current_band_A = 0.0f)
MUT(dt_band_nan, c->deadtime.current_band_A = NAN)
/* Selection. */
MUT(est_bad, c->estimator = (mc_estimator_t)5)
MUT(est_count, c->estimator = MC_ESTIMATOR_COUNT)
MUT(ctrl_bad, c->controller = (mc_controller_t)5)
MUT(ctrl_count, c->controller = MC_CONTROLLER_COUNT)
/* Sensorless front end and estimators. */
MUT(gamma_nan, c->flux_obs.gamma = NAN)                     /* any estimator */
MUT(gamma_unstable, (SENSORLESS, c->flux_obs.gamma = 1e6f)) /* Ts gamma psi^2 > 1 */
MUT(gamma_unstable_off, c->flux_obs.gamma = 1e6f)           /* encoder */
MUT(rho_min_1, (SENSORLESS, c->flux_obs.ratio_min = 1.0f))
MUT(rho_min_0, (NAM, c->flux_obs.ratio_min = 0.0f))
MUT(rho_max_1, (SENSORLESS, c->flux_obs.ratio_max = 1.0f))
MUT(a1_zero, (SENSORLESS, c->flux_ii.a1 = 0.0f))
MUT(a2_neg, (SENSORLESS, c->flux_ii.a2 = -1.0f))
MUT(a1_zero_off, (NAM, c->flux_ii.a1 = 0.0f)) /* flux_ii not selected */
MUT(pll_bw_zero, (NAM, c->flux_pll.bandwidth_rad_s = 0.0f))
MUT(pll_bw_zero_off, (SENSORLESS, c->flux_pll.bandwidth_rad_s = 0.0f))
/* IDA-PBC controller. */
MUT(r_damp_neg, (PAPER, c->idapbc.r_ohm = -0.1f))
MUT(int_pole_zero, (PAPER, c->idapbc.integral_pole_rad_s = 0.0f))
MUT(int_tau_zero, (PAPER, c->idapbc.integral_tau_max_Nm = 0.0f))
MUT(r_damp_neg_off, (SENSORLESS, c->idapbc.r_ohm = -0.1f)) /* foc_pi */
/* ALIGN (sensorless only). */
MUT(align_i_big, (SENSORLESS, c->align.current_A = 10.0f)) /* not < i_max */
MUT(align_i_zero, (SENSORLESS, c->align.current_A = 0.0f))
MUT(align_ramp_long, (SENSORLESS, c->align.ramp_s = 2.5f)) /* > timeout */
MUT(align_time_zero, (SENSORLESS, c->align.timeout_s = 0.0f, c->align.ramp_s = 0.0f))
MUT(align_time_long, (SENSORLESS, c->align.timeout_s = 10.5f)) /* > 10 s */
MUT(align_angle_big, (SENSORLESS, c->align.angle_e_rad = 7.0f))
MUT(align_zeta_zero, (SENSORLESS, c->align.damping_ratio = 0.0f))
MUT(align_zeta_big, (SENSORLESS, c->align.damping_ratio = 11.0f))
MUT(align_iq_zero, (SENSORLESS, c->align.i_q_max_A = 0.0f))
MUT(align_iq_big, (SENSORLESS, c->align.i_q_max_A = 9.9f)) /* hypot(2, 9.9) > i_max */
MUT(align_speed_zero, (SENSORLESS, c->align.settle_speed_e_rad_s = 0.0f))
MUT(align_hold_short, (SENSORLESS, c->align.settle_time_s = 1e-5f)) /* < Ts */
MUT(align_hold_long, (SENSORLESS, c->align.settle_time_s = 2.0f))   /* not < timeout */
MUT(align_zeta_nan, c->align.damping_ratio = NAN)                   /* any estimator */
MUT(align_i_big_off, c->align.current_A = 10.0f)                    /* encoder: no ALIGN */
MUT(align_angle_big_off, c->align.angle_e_rad = 7.0f)

static const struct {
    const char *name;
    mutate_fn f;
    mc_status_t expected;
} cases[] = {
#define CASE(fn, st)                                                                               \
    {                                                                                              \
#fn, fn, st                                                                                \
    }
    CASE(r_neg, MC_ERR_PARAM),
    CASE(r_nan, MC_ERR_NONFINITE),
    CASE(ld_zero, MC_ERR_PARAM),
    CASE(lq_inf, MC_ERR_NONFINITE),
    CASE(psi_zero, MC_ERR_PARAM),
    CASE(pp_zero, MC_ERR_PARAM),
    CASE(pp_big, MC_ERR_PARAM),
    CASE(j_zero, MC_ERR_PARAM),
    CASE(b_neg, MC_ERR_PARAM),
    CASE(fpwm_low, MC_ERR_PARAM),
    CASE(fpwm_high, MC_ERR_PARAM),
    CASE(slow_zero, MC_ERR_PARAM),
    CASE(slow_above_pwm, MC_ERR_PARAM),
    CASE(slow_not_divisor, MC_ERR_PARAM),
    CASE(calib_zero, MC_ERR_PARAM),
    CASE(calib_short, MC_ERR_PARAM),
    CASE(calib_long, MC_ERR_PARAM),
    CASE(overrun_zero, MC_ERR_PARAM),
    CASE(overrun_big, MC_ERR_PARAM),
    CASE(delay_big, MC_ERR_PARAM),
    CASE(delay_small, MC_ERR_PARAM),
    CASE(delay_neg, MC_ERR_PARAM),
    CASE(cpr_small, MC_ERR_PARAM),
    CASE(cpr_big, MC_ERR_PARAM),
    CASE(offset_big, MC_ERR_PARAM),
    CASE(pll_fast, MC_ERR_PARAM),
    CASE(wmax_alias, MC_ERR_PARAM),
    CASE(cpr_small_off, MC_OK),
    CASE(pll_fast_off, MC_OK),
    CASE(wc_fast, MC_ERR_PARAM),
    CASE(margin_big, MC_ERR_PARAM),
    CASE(margin_zero, MC_ERR_PARAM),
    CASE(kp_pos_zero, MC_ERR_PARAM),
    CASE(imax_trip, MC_ERR_PARAM),
    CASE(wmax_zero, MC_ERR_PARAM),
    CASE(ws_slow_loop, MC_ERR_PARAM),
    CASE(ws_vs_wc, MC_ERR_PARAM),
    CASE(ws_vs_wc_ok, MC_OK),
    CASE(ws_vs_pll, MC_ERR_PARAM),
    CASE(kp_pos_big, MC_ERR_PARAM),
    CASE(nam_ws_vs_pll, MC_ERR_PARAM),
    CASE(offmax_zero, MC_ERR_PARAM),
    CASE(trip_zero, MC_ERR_PARAM),
    CASE(vdc_order, MC_ERR_PARAM),
    CASE(vdc_nan, MC_ERR_NONFINITE),
    CASE(est_w_zero, MC_ERR_PARAM),
    CASE(est_tau_zero, MC_ERR_PARAM),
    CASE(cl_below_imax, MC_ERR_PARAM),
    CASE(cl_at_imax, MC_OK),
    CASE(cl_below_trip, MC_OK),
    CASE(cl_at_trip, MC_ERR_PARAM),
    CASE(cl_zero, MC_ERR_PARAM),
    CASE(cl_nan, MC_ERR_NONFINITE),
    CASE(cl_time_zero, MC_ERR_PARAM),
    CASE(cl_time_short, MC_ERR_PARAM),
    CASE(cl_time_one, MC_OK),
    CASE(cl_time_nan, MC_ERR_NONFINITE),
    CASE(dt_ok, MC_OK),
    CASE(dt_neg, MC_ERR_PARAM),
    CASE(dt_big, MC_ERR_PARAM),
    CASE(dt_drop_big, MC_ERR_PARAM),
    CASE(dt_band_zero, MC_ERR_PARAM),
    CASE(dt_band_nan, MC_ERR_NONFINITE),
    CASE(os_zero, MC_ERR_PARAM),
    CASE(os_at_wmax, MC_ERR_PARAM),
    CASE(os_above_wmax, MC_OK),
    CASE(os_inf, MC_ERR_NONFINITE),
    CASE(os_bemf_at_vdc, MC_ERR_PARAM),
    CASE(os_bemf_below_vdc, MC_OK),
    CASE(os_bemf_higher_bus, MC_OK),
    CASE(os_bemf_higher_psi, MC_ERR_PARAM),
    CASE(stall_i_zero, MC_ERR_PARAM),
    CASE(stall_w_zero, MC_ERR_PARAM),
    CASE(stall_t_zero, MC_ERR_PARAM),
    CASE(stall_t_short, MC_ERR_PARAM),
    CASE(stall_t_one, MC_OK),
    CASE(i2t_cont_zero, MC_ERR_PARAM),
    CASE(i2t_peak_eq, MC_ERR_PARAM),
    CASE(i2t_peak_below, MC_ERR_PARAM),
    CASE(i2t_peak_above, MC_OK),
    CASE(i2t_time_zero, MC_ERR_PARAM),
    CASE(i2t_peak_nan, MC_ERR_NONFINITE),
    CASE(sum_max_zero, MC_ERR_PARAM),
    CASE(sum_time_zero, MC_ERR_PARAM),
    CASE(sum_time_short, MC_ERR_PARAM),
    CASE(est_bad, MC_ERR_PARAM),
    CASE(est_count, MC_ERR_PARAM),
    CASE(ctrl_bad, MC_ERR_PARAM),
    CASE(ctrl_count, MC_ERR_PARAM),
    CASE(gamma_nan, MC_ERR_NONFINITE),
    CASE(gamma_unstable, MC_ERR_PARAM),
    CASE(gamma_unstable_off, MC_OK),
    CASE(rho_min_1, MC_ERR_PARAM),
    CASE(rho_min_0, MC_ERR_PARAM),
    CASE(rho_max_1, MC_ERR_PARAM),
    CASE(a1_zero, MC_ERR_PARAM),
    CASE(a2_neg, MC_ERR_PARAM),
    CASE(a1_zero_off, MC_OK),
    CASE(pll_bw_zero, MC_ERR_PARAM),
    CASE(pll_bw_zero_off, MC_OK),
    CASE(r_damp_neg, MC_ERR_PARAM),
    CASE(int_pole_zero, MC_ERR_PARAM),
    CASE(int_tau_zero, MC_ERR_PARAM),
    CASE(r_damp_neg_off, MC_OK),
    CASE(align_i_big, MC_ERR_PARAM),
    CASE(align_i_zero, MC_ERR_PARAM),
    CASE(align_ramp_long, MC_ERR_PARAM),
    CASE(align_time_zero, MC_ERR_PARAM),
    CASE(align_time_long, MC_ERR_PARAM),
    CASE(align_angle_big, MC_ERR_PARAM),
    CASE(align_zeta_zero, MC_ERR_PARAM),
    CASE(align_zeta_big, MC_ERR_PARAM),
    CASE(align_iq_zero, MC_ERR_PARAM),
    CASE(align_iq_big, MC_ERR_PARAM),
    CASE(align_speed_zero, MC_ERR_PARAM),
    CASE(align_hold_short, MC_ERR_PARAM),
    CASE(align_hold_long, MC_ERR_PARAM),
    CASE(align_zeta_nan, MC_ERR_NONFINITE),
    CASE(align_i_big_off, MC_OK),
    CASE(align_angle_big_off, MC_OK),
#undef CASE
};

static void test_default_config_is_valid(void **state)
{
    (void)state;
    mc_config_t c;
    mc_config_init_default(&c);
    assert_int_equal(mc_config_validate(&c), MC_OK);
    assert_int_equal(c.controller, MC_CONTROLLER_FOC_PI);
    assert_int_equal(c.estimator, MC_ESTIMATOR_ENCODER);
    /* Paper 001 motor (Section 5). */
    assert_near(c.motor.R_ohm, 0.225, 1e-7);
    assert_near(c.motor.Ld_H, 3.8e-3, 1e-9);
    assert_near(c.motor.Lq_H, 3.8e-3, 1e-9);
    assert_near(c.motor.psi_Wb, 0.17, 1e-7);
    assert_int_equal(c.motor.pole_pairs, 3u);
    assert_near(c.motor.J_kgm2, 0.012, 1e-8);
    /* 20 kHz, 2 kHz slow loop, the HAL's delay (0). */
    assert_near(c.timing.f_pwm_Hz, 20000.0, 0.0);
    assert_near(c.timing.slow_loop_Hz, 2000.0, 0.0);
    assert_near(c.timing.delay_periods, 0.0, 0.0);
}

static void test_each_invalid_field_is_rejected(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        mc_config_t c;
        mc_config_init_default(&c);
        cases[i].f(&c);
        const mc_status_t got = mc_config_validate(&c);
        if (got != cases[i].expected) {
            fail_msg("case %s: got %d, expected %d", cases[i].name, (int)got,
                     (int)cases[i].expected);
        }
    }
}

/* The back-EMF checks' thresholds (mc/emf_monitor.h: filter in [Ts, 1] s,
 * check time of at least one sample and at most 1e6, e_min > 0, speed
 * floor > 0, angle_max in (0, pi/2], ratio_low in (0, 1), ratio_high > 1)
 * with each estimator that uses them: every one in the list (the encoder:
 * slip and freeze; flux_ii and flux_pll: loss of lock). */
static void test_emf_check_fields_per_estimator(void **state)
{
    (void)state;
    const struct {
        size_t off;
        float value;
        mc_status_t expected;
    } f[] = {
#define EMF(x) offsetof(mc_emf_check_config_t, x)
        { EMF(filter_s), 1.01f, MC_ERR_PARAM },
        { EMF(filter_s), 4.9e-4f, MC_ERR_PARAM }, /* < the slow tick, 0.5 ms */
        { EMF(filter_s), 5e-4f, MC_OK },
        { EMF(filter_s), 1.0f, MC_OK },
        { EMF(check_time_s), 0.0f, MC_ERR_PARAM },
        { EMF(check_time_s), 2e-4f, MC_ERR_PARAM },  /* < one tick */
        { EMF(check_time_s), 501.0f, MC_ERR_PARAM }, /* 1.002e6 ticks */
        { EMF(check_time_s), 5e-4f, MC_OK },
        { EMF(min_V), 0.0f, MC_ERR_PARAM },
        { EMF(min_speed_e_rad_s), 0.0f, MC_ERR_PARAM },
        { EMF(min_speed_e_rad_s), -3.0f, MC_ERR_PARAM },
        { EMF(angle_max_rad), 0.0f, MC_ERR_PARAM },
        { EMF(angle_max_rad), 1.5709f, MC_ERR_PARAM }, /* > pi/2 */
        { EMF(angle_max_rad), 1.5707f, MC_OK },
        { EMF(ratio_low), 0.0f, MC_ERR_PARAM },
        { EMF(ratio_low), 1.0f, MC_ERR_PARAM },
        { EMF(ratio_high), 1.0f, MC_ERR_PARAM },
        { EMF(ratio_high), 1.001f, MC_OK },
        { EMF(min_V), NAN, MC_ERR_NONFINITE },
        { EMF(ratio_high), INFINITY, MC_ERR_NONFINITE },
#undef EMF
    };
    for (int e = 0; e < (int)MC_ESTIMATOR_COUNT; ++e) {
        mc_config_t c;
        mc_config_init_default(&c);
        c.estimator = (mc_estimator_t)e;
        assert_int_equal(mc_config_validate(&c), MC_OK);
        for (size_t i = 0; i < sizeof f / sizeof f[0]; ++i) {
            mc_config_init_default(&c);
            c.estimator = (mc_estimator_t)e;
            memcpy((unsigned char *)&c.emf_check + f[i].off, &f[i].value, sizeof(float));
            const mc_status_t got = mc_config_validate(&c);
            if (got != f[i].expected) {
                fail_msg("%s, emf_check case %zu: got %d, expected %d",
                         mc_estimator_name((mc_estimator_t)e), i, (int)got, (int)f[i].expected);
            }
        }
    }
}

static mc_status_t validate_with(mc_controller_t ctl, mc_estimator_t est, float w_s_rad_s)
{
    mc_config_t c;
    mc_config_init_default(&c);
    c.controller = ctl;
    c.estimator = est;
    if (w_s_rad_s > 0.0f) {
        c.foc_pi.speed_bandwidth_rad_s = w_s_rad_s;
    }
    return mc_config_validate(&c);
}

/* Which controller works with which estimator (defaults otherwise). */
static void test_controller_estimator_compatibility(void **state)
{
    (void)state;
    /* IDA-PBC needs tau_hat: the encoder has none. */
    assert_int_equal(validate_with(MC_CONTROLLER_IDAPBC, MC_ESTIMATOR_ENCODER, 0.0f), MC_ERR_PARAM);
    assert_int_equal(validate_with(MC_CONTROLLER_IDAPBC, MC_ESTIMATOR_FLUX_II, 0.0f), MC_OK);
    assert_int_equal(validate_with(MC_CONTROLLER_IDAPBC, MC_ESTIMATOR_FLUX_PLL, 0.0f), MC_OK);
    /* The baseline FOC works with every estimator. */
    for (int e = 0; e < (int)MC_ESTIMATOR_COUNT; ++e) {
        if (validate_with(MC_CONTROLLER_FOC_PI, (mc_estimator_t)e, 0.0f) != MC_OK) {
            fail_msg("foc_pi + %s rejected", mc_estimator_name((mc_estimator_t)e));
        }
    }
}

/* FOC_PI: w_s <= half the estimator's speed bandwidth. flux_pll states its
 * PLL bandwidth (default 100 rad/s: w_s = 50 is the limit); flux_ii states
 * none, the encoder its PLL (1000 rad/s). */
static void test_foc_pi_speed_bandwidth_vs_estimator(void **state)
{
    (void)state;
    mc_config_t c;
    mc_config_init_default(&c);
    assert_near(c.flux_pll.bandwidth_rad_s, 100.0, 0.0);
    assert_near(c.foc_pi.speed_bandwidth_rad_s, 50.0, 0.0);
    assert_int_equal(validate_with(MC_CONTROLLER_FOC_PI, MC_ESTIMATOR_FLUX_PLL, 50.0f), MC_OK);
    assert_int_equal(validate_with(MC_CONTROLLER_FOC_PI, MC_ESTIMATOR_FLUX_PLL, 60.0f),
                     MC_ERR_PARAM);
    assert_int_equal(validate_with(MC_CONTROLLER_FOC_PI, MC_ESTIMATOR_FLUX_II, 60.0f), MC_OK);
    assert_int_equal(validate_with(MC_CONTROLLER_FOC_PI, MC_ESTIMATOR_ENCODER, 60.0f), MC_OK);
    /* The same rule scales with the PLL bandwidth. */
    c.estimator = MC_ESTIMATOR_FLUX_PLL;
    c.foc_pi.speed_bandwidth_rad_s = 60.0f;
    c.flux_pll.bandwidth_rad_s = 120.0f;
    assert_int_equal(mc_config_validate(&c), MC_OK);
    c.flux_pll.bandwidth_rad_s = 119.0f;
    assert_int_equal(mc_config_validate(&c), MC_ERR_PARAM);
}

/* mc_config_estimator_info: what each estimator states. */
static void test_estimator_info(void **state)
{
    (void)state;
    mc_config_t c;
    mc_config_init_default(&c);
    mc_estimator_info_t i = mc_config_estimator_info(&c);
    assert_false(i.sensorless);
    assert_false(i.provides_load);
    assert_int_equal(i.encoder_cpr, c.encoder.counts_per_rev);
    assert_near(i.speed_bandwidth_rad_s, c.encoder.pll_bandwidth_rad_s, 0.0);
    c.estimator = MC_ESTIMATOR_FLUX_II;
    i = mc_config_estimator_info(&c);
    assert_true(i.sensorless);
    assert_true(i.provides_load);
    assert_int_equal(i.encoder_cpr, 0u);
    assert_near(i.speed_bandwidth_rad_s, 0.0, 0.0);
    c.estimator = MC_ESTIMATOR_FLUX_PLL;
    i = mc_config_estimator_info(&c);
    assert_true(i.sensorless);
    assert_true(i.provides_load);
    assert_int_equal(i.encoder_cpr, 0u);
    assert_near(i.speed_bandwidth_rad_s, c.flux_pll.bandwidth_rad_s, 0.0);
    c.estimator = MC_ESTIMATOR_COUNT;
    i = mc_config_estimator_info(&c);
    assert_false(i.sensorless);
    assert_false(i.provides_load);
    assert_int_equal(i.encoder_cpr, 0u);
    assert_near(i.speed_bandwidth_rad_s, 0.0, 0.0);
}

/* Grid over the three currents and bus voltages: the mask of
 * mc_faults_check_sample and of its fast-ISR form equals the rule written
 * out independently here; the form for comparators in hardware
 * (mc_faults_check_bus_fast) gives no cause while the bus is within its
 * limits, whatever the currents, and the whole mask otherwise. */
static void test_fault_check_sample_grid(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = { .i_trip_A = 20.0f, .v_dc_max_V = 60.0f, .v_dc_min_V = 20.0f };
    const float currents[] = { -30.0f, -20.0f, -19.9f, 0.0f, 19.9f, 20.0f, 20.1f, NAN, INFINITY };
    const float volts[] = { -1.0f, 0.0f, 19.9f, 20.0f, 48.0f, 60.0f, 60.1f, NAN, -INFINITY };
    const size_t nc = sizeof currents / sizeof currents[0];
    for (size_t n = 0; n < nc * nc * nc; ++n) {
        const float i3[3] = { currents[n % nc], currents[(n / nc) % nc], currents[n / (nc * nc)] };
        for (size_t v = 0; v < sizeof volts / sizeof volts[0]; ++v) {
            for (int uv = 0; uv < 2; ++uv) {
                uint32_t exp_mask = 0u;
                for (int k = 0; k < 3; ++k) {
                    const double x = (double)i3[k];
                    if (x != x || x - x != 0.0) {
                        exp_mask |= MC_FAULT_NONFINITE;
                    } else if (fabs(x) > 20.0) {
                        exp_mask |= MC_FAULT_OVERCURRENT;
                    }
                }
                const double vd = (double)volts[v];
                const bool bus_fault = vd != vd || vd - vd != 0.0 || vd > 60.0 || (uv && vd < 20.0);
                if (vd != vd || vd - vd != 0.0) {
                    exp_mask |= MC_FAULT_NONFINITE;
                } else {
                    if (vd > 60.0) {
                        exp_mask |= MC_FAULT_DC_OVERVOLTAGE;
                    }
                    if (uv && vd < 20.0) {
                        exp_mask |= MC_FAULT_DC_UNDERVOLTAGE;
                    }
                }
                assert_int_equal(
                    mc_faults_check_sample(&lim, i3[0], i3[1], i3[2], volts[v], uv != 0), exp_mask);
                assert_int_equal(mc_faults_check_sample_fast(&lim, i3, volts[v], uv != 0),
                                 exp_mask);
                assert_int_equal(mc_faults_check_bus_fast(&lim, i3, volts[v], uv != 0),
                                 bus_fault ? exp_mask : 0u);
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_config_is_valid),
        cmocka_unit_test(test_each_invalid_field_is_rejected),
        cmocka_unit_test(test_emf_check_fields_per_estimator),
        cmocka_unit_test(test_controller_estimator_compatibility),
        cmocka_unit_test(test_foc_pi_speed_bandwidth_vs_estimator),
        cmocka_unit_test(test_estimator_info),
        cmocka_unit_test(test_fault_check_sample_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
