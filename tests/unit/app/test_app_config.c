/*
 * Configuration validation (each rule, with the expected error code) and
 * the per-sample protection checks against an independent expectation.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>

#include "mc/app.h"

typedef void (*mutate_fn)(mc_config_t *c);

#define MUT(name, stmt) static void name(mc_config_t *c) { stmt; }
MUT(r_neg, c->R_ohm = -0.1f)
MUT(r_nan, c->R_ohm = NAN)
MUT(ld_zero, c->Ld_H = 0.0f)
MUT(lq_inf, c->Lq_H = INFINITY)
MUT(psi_zero, c->psi_Wb = 0.0f)
MUT(pp_zero, c->pole_pairs = 0u)
MUT(pp_big, c->pole_pairs = 65u)
MUT(j_zero, c->J_kgm2 = 0.0f)
MUT(b_neg, c->B_Nms = -1e-3f)
MUT(fpwm_low, c->f_pwm_hz = 500.0f)
MUT(fpwm_high, c->f_pwm_hz = 2e5f)
MUT(dec_zero, c->speed_loop_decimation = 0u)
MUT(calib_zero, c->calib_samples = 0u)
MUT(overrun_zero, c->isr_overrun_limit = 0u)
MUT(cpr_small, c->encoder_cpr = 2u)
MUT(offset_big, c->encoder_offset_e_rad = 7.0f)
MUT(pll_fast, c->pll_bandwidth_rad_s = 20000.0f)          /* w Ts = 1 */
MUT(wc_fast, c->current_bandwidth_rad_s = 12000.0f)      /* w_c Ts = 0.6 */
MUT(ws_vs_wc, c->speed_bandwidth_rad_s = 600.0f)         /* > w_c / 5 */
MUT(ws_vs_pll, c->pll_bandwidth_rad_s = 90.0f)           /* w_s > w_pll/2 */
MUT(kp_pos_big, c->position_kp_per_s = 60.0f)            /* > w_s */
MUT(margin_big, c->modulation_margin = 1.01f)
MUT(margin_zero, c->modulation_margin = 0.0f)
MUT(imax_trip, c->i_max_A = 20.0f)                       /* not < trip */
MUT(wmax_zero, c->omega_max_rad_s = 0.0f)
MUT(wmax_alias, c->omega_max_rad_s = 70000.0f)           /* w Ts > pi */
MUT(offmax_zero, c->i_offset_max_A = 0.0f)
MUT(trip_zero, c->fault_limits.i_trip_A = 0.0f)
MUT(vdc_order, c->fault_limits.v_dc_min_V = 70.0f)
MUT(vdc_nan, c->fault_limits.v_dc_max_V = NAN)
MUT(src_bad, c->angle_source = (mc_angle_source_t)5)
MUT(ctrl_bad, c->controller = (mc_controller_t)5)
/* Sensorless fields. */
MUT(idapbc_encoder, c->controller = MC_CONTROLLER_IDAPBC) /* needs flux obs */
MUT(nam_ws_vs_pll, (c->angle_source = MC_ANGLE_SOURCE_FLUX_OBSERVER,
                    c->sensorless_pll_bandwidth_rad_s = 90.0f)) /* w_s > /2 */
MUT(gamma_nan, c->flux_obs_gamma = NAN)
MUT(gamma_unstable, c->flux_obs_gamma = 1e6f)   /* Ts > 1/(gamma psi^2) */
MUT(a1_zero, c->speed_obs_a1 = 0.0f)
MUT(est_w_zero, c->est_omega_max_rad_s = 0.0f)
MUT(est_tau_zero, c->est_tau_max_Nm = 0.0f)
MUT(rho_min_1, c->est_flux_ratio_min = 1.0f)
MUT(rho_max_1, c->est_flux_ratio_max = 1.0f)
MUT(delay_big, c->delay_periods = 2.0f)
MUT(r_damp_neg, c->idapbc_r_ohm = -0.1f)
MUT(align_i_big, c->align_current_A = 10.0f)    /* not < i_max */
MUT(align_ramp_long, c->align_ramp_s = 2.5f)    /* > align_time_s */
MUT(align_time_zero, (c->align_time_s = 0.0f, c->align_ramp_s = 0.0f))
MUT(align_angle_big, c->align_angle_e_rad = 7.0f)
MUT(align_zeta_zero, c->align_damping_ratio = 0.0f)
MUT(align_zeta_big, c->align_damping_ratio = 11.0f)
MUT(align_iq_zero, c->align_i_q_max_A = 0.0f)
MUT(align_iq_big, c->align_i_q_max_A = 9.9f)  /* hypot(2, 9.9) > i_max */
MUT(align_speed_zero, c->align_settle_speed_e_rad_s = 0.0f)
MUT(align_hold_short, c->align_settle_time_s = 1e-5f)  /* < Ts */
MUT(align_hold_long, c->align_settle_time_s = 2.0f)    /* not < timeout */
MUT(align_zeta_nan, c->align_damping_ratio = NAN)

static const struct {
    mutate_fn f;
    mc_status_t expected;
} cases[] = {
    { r_neg, MC_ERR_PARAM }, { r_nan, MC_ERR_NONFINITE },
    { ld_zero, MC_ERR_PARAM }, { lq_inf, MC_ERR_NONFINITE },
    { psi_zero, MC_ERR_PARAM }, { pp_zero, MC_ERR_PARAM },
    { pp_big, MC_ERR_PARAM }, { j_zero, MC_ERR_PARAM },
    { b_neg, MC_ERR_PARAM }, { fpwm_low, MC_ERR_PARAM },
    { fpwm_high, MC_ERR_PARAM }, { dec_zero, MC_ERR_PARAM },
    { calib_zero, MC_ERR_PARAM }, { overrun_zero, MC_ERR_PARAM },
    { cpr_small, MC_ERR_PARAM }, { offset_big, MC_ERR_PARAM },
    { pll_fast, MC_ERR_PARAM }, { wc_fast, MC_ERR_PARAM },
    { ws_vs_wc, MC_ERR_PARAM }, { ws_vs_pll, MC_ERR_PARAM },
    { kp_pos_big, MC_ERR_PARAM }, { margin_big, MC_ERR_PARAM },
    { margin_zero, MC_ERR_PARAM }, { imax_trip, MC_ERR_PARAM },
    { wmax_zero, MC_ERR_PARAM }, { wmax_alias, MC_ERR_PARAM },
    { offmax_zero, MC_ERR_PARAM }, { trip_zero, MC_ERR_PARAM },
    { vdc_order, MC_ERR_PARAM }, { vdc_nan, MC_ERR_NONFINITE },
    { src_bad, MC_ERR_PARAM }, { ctrl_bad, MC_ERR_PARAM },
    { idapbc_encoder, MC_ERR_PARAM }, { nam_ws_vs_pll, MC_ERR_PARAM },
    { gamma_nan, MC_ERR_NONFINITE }, { gamma_unstable, MC_ERR_PARAM },
    { a1_zero, MC_ERR_PARAM }, { est_w_zero, MC_ERR_PARAM },
    { est_tau_zero, MC_ERR_PARAM }, { rho_min_1, MC_ERR_PARAM },
    { rho_max_1, MC_ERR_PARAM }, { delay_big, MC_ERR_PARAM },
    { r_damp_neg, MC_ERR_PARAM }, { align_i_big, MC_ERR_PARAM },
    { align_ramp_long, MC_ERR_PARAM }, { align_time_zero, MC_ERR_PARAM },
    { align_angle_big, MC_ERR_PARAM }, { align_zeta_zero, MC_ERR_PARAM },
    { align_zeta_big, MC_ERR_PARAM }, { align_iq_zero, MC_ERR_PARAM },
    { align_iq_big, MC_ERR_PARAM }, { align_speed_zero, MC_ERR_PARAM },
    { align_hold_short, MC_ERR_PARAM }, { align_hold_long, MC_ERR_PARAM },
    { align_zeta_nan, MC_ERR_NONFINITE },
};

static void test_default_config_is_valid(void **state)
{
    (void)state;
    mc_config_t c;
    mc_config_init_default(&c);
    assert_int_equal(mc_config_validate(&c), MC_OK);
    /* Paper 001 motor (Section 5). */
    assert_float_equal(c.R_ohm, 0.225, 1e-7);
    assert_float_equal(c.Ld_H, 3.8e-3, 1e-9);
    assert_float_equal(c.psi_Wb, 0.17, 1e-7);
    assert_int_equal(c.pole_pairs, 3u);
    assert_float_equal(c.J_kgm2, 0.012, 1e-8);
}

static void test_each_invalid_field_is_rejected(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        mc_config_t c;
        mc_config_init_default(&c);
        cases[i].f(&c);
        if (mc_config_validate(&c) != cases[i].expected) {
            fail_msg("case %zu: got %d, expected %d", i,
                     (int)mc_config_validate(&c), (int)cases[i].expected);
        }
    }
}

/* Grid over currents and bus voltages: the mask equals the rule written
 * out independently here. */
static void test_fault_check_sample_grid(void **state)
{
    (void)state;
    const mc_fault_limits_t lim = { .i_trip_A = 20.0f, .v_dc_max_V = 60.0f,
                                    .v_dc_min_V = 20.0f };
    const float currents[] = { -30.0f, -20.0f, -19.9f, 0.0f, 19.9f, 20.0f,
                               20.1f, NAN, INFINITY };
    const float volts[] = { -1.0f, 0.0f, 19.9f, 20.0f, 48.0f, 60.0f, 60.1f,
                            NAN, -INFINITY };
    const size_t nc = sizeof currents / sizeof currents[0];
    for (size_t a = 0; a < nc; ++a) {
        for (size_t b = 0; b < nc; ++b) {
            for (size_t v = 0; v < sizeof volts / sizeof volts[0]; ++v) {
                for (int uv = 0; uv < 2; ++uv) {
                    const float i3[3] = { currents[a], currents[b], 0.5f };
                    uint32_t exp_mask = 0u;
                    for (int k = 0; k < 2; ++k) {
                        const double x = (double)i3[k];
                        if (x != x || x - x != 0.0) {
                            exp_mask |= MC_FAULT_NONFINITE;
                        } else if (fabs(x) > 20.0) {
                            exp_mask |= MC_FAULT_OVERCURRENT;
                        }
                    }
                    const double vd = (double)volts[v];
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
                    assert_int_equal(mc_faults_check_sample(&lim, i3, volts[v],
                                                            uv != 0),
                                     exp_mask);
                }
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_default_config_is_valid),
        cmocka_unit_test(test_each_invalid_field_is_rejected),
        cmocka_unit_test(test_fault_check_sample_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
