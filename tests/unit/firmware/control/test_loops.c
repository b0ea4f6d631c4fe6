/*
 * Baseline loops against independent double-precision
 * references: current-PI design and closed loop on an exactly discretised
 * R-L plant, decoupling feed-forward, circular voltage limit + anti-windup,
 * speed-loop load response vs the analytic design, position loop. (The
 * encoder tracker is tested in observers/test_encoder_tracker.c.)
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "mc/current_loop.h"
#include "mc/drive.h"
#include "mc/position_loop.h"
#include "mc/speed_loop.h"

#define TS 5e-5

static uint64_t rng = 0x9E3779B97F4A7C15u;
static double urand(double lo, double hi) /* xorshift64* */
{
    rng ^= rng >> 12;
    rng ^= rng << 25;
    rng ^= rng >> 27;
    const uint64_t r = rng * 2685821657736338717u;
    return lo + (hi - lo) * (double)(r >> 11) * (1.0 / 9007199254740992.0);
}

static mc_current_loop_params_t paper_params(float w_c)
{
    return (mc_current_loop_params_t){
        .cfg = { .bandwidth_rad_s = w_c, .modulation_margin = 0.95f },
        .R_ohm = 0.225f,
        .Ld_H = 3.8e-3f,
        .Lq_H = 3.8e-3f,
        .psi_Wb = 0.17f,
        .Ts_s = (float)TS,
    };
}

static void test_current_pi_design(void **state)
{
    (void)state;
    for (int i = 0; i < 1000; ++i) {
        const double R = urand(0.0, 5.0), L = urand(1e-5, 0.1);
        const double w = urand(10.0, 1e4);
        mc_current_pi_gains_t g;
        assert_int_equal(mc_current_pi_design_f32((float)R, (float)L, (float)w, &g), MC_OK);
        assert_near(g.kp_V_per_A, L * w, 1e-6 * L * w);
        assert_near(g.ki_V_per_As, R * w, 1e-6 * R * w + 1e-12);
    }
    mc_current_pi_gains_t g;
    assert_int_equal(mc_current_pi_design_f32(-0.1f, 1e-3f, 100.0f, &g), MC_ERR_PARAM);
    assert_int_equal(mc_current_pi_design_f32(0.1f, 0.0f, 100.0f, &g), MC_ERR_PARAM);
    assert_int_equal(mc_current_pi_design_f32(0.1f, 1e-3f, 0.0f, &g), MC_ERR_PARAM);
    assert_int_equal(mc_current_pi_design_f32(NAN, 1e-3f, 1.0f, &g), MC_ERR_NONFINITE);
}

/* Without delay the designed loop is first order: on the exact ZOH model
 * of L di/dt = -R i + v (locked rotor), the q step follows 1 - exp(-w_c t)
 * within 3 % of the step (backward-Euler PI at w_c Ts = 0.05), and the
 * rise time within 5 % of ln(9)/w_c. */
static void test_current_closed_loop_is_first_order(void **state)
{
    (void)state;
    const float w_c = 1000.0f;
    mc_current_loop_f32_t cl;
    const mc_current_loop_params_t p = paper_params(w_c);
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_OK);
    const double R = 0.225, L = 3.8e-3, a = exp(-R * TS / L);
    double i_q = 0.0, max_dev = 0.0, t10 = NAN, t90 = NAN;
    for (int k = 0; k < 400; ++k) {
        const double t = k * TS;
        const double ideal = 1.0 - exp(-(double)w_c * t);
        max_dev = fmax(max_dev, fabs(i_q - ideal));
        mc_current_loop_out_t out;
        assert_int_equal(
            mc_current_loop_step_f32(&cl, 0.0f, (float)i_q, 0.0f, 1.0f, 0.0f, 48.0f, &out), MC_OK);
        const double i_next = a * i_q + (1.0 - a) / R * (double)out.v_q_V;
        if (isnan(t10) && i_next >= 0.1) {
            t10 = t + TS * (0.1 - i_q) / (i_next - i_q);
        }
        if (isnan(t90) && i_next >= 0.9) {
            t90 = t + TS * (0.9 - i_q) / (i_next - i_q);
        }
        i_q = i_next;
    }
    assert_true(max_dev < 0.03);
    assert_near(t90 - t10, log(9.0) / w_c, 0.05 * log(9.0) / w_c);
    assert_near(i_q, 1.0, 1e-4);
}

/* Zero current error, fresh integrators: the output is exactly the
 * decoupling feed-forward v_d = -w Lq i_q, v_q = w (Ld i_d + psi). */
static void test_decoupling_feed_forward(void **state)
{
    (void)state;
    mc_current_loop_params_t p = paper_params(2000.0f);
    p.Ld_H = 3.0e-3f; /* salient, to tell Ld and Lq apart */
    mc_current_loop_f32_t cl;
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_OK);
    for (int i = 0; i < 2000; ++i) {
        const double w = urand(-150.0, 150.0), id = urand(-5.0, 5.0);
        const double iq = urand(-5.0, 5.0);
        mc_current_loop_reset_f32(&cl);
        mc_current_loop_out_t out;
        assert_int_equal(mc_current_loop_step_f32(&cl, (float)id, (float)iq, (float)id, (float)iq,
                                                  (float)w, 100.0f, &out),
                         MC_OK);
        const double vd = -w * 3.8e-3 * iq, vq = w * (3.0e-3 * id + 0.17);
        assert_near(out.v_d_V, vd, 1e-5 * (1.0 + fabs(vd)));
        assert_near(out.v_q_V, vq, 1e-5 * (1.0 + fabs(vq)));
        assert_false(out.saturated);
    }
}

/* Any errors: |v_dq| <= m v_dc / sqrt(3); d has priority; the integrators
 * do not wind up: after 2000 saturated samples the first sample with a
 * reversed error leaves the limit. */
static void test_voltage_limit_and_anti_windup(void **state)
{
    (void)state;
    mc_current_loop_f32_t cl;
    const mc_current_loop_params_t p = paper_params(2000.0f);
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_OK);
    const double v_max = 0.95 * 48.0 / sqrt(3.0);
    for (int i = 0; i < 5000; ++i) {
        mc_current_loop_out_t out;
        const float e_d = (float)urand(-50.0, 50.0), e_q = (float)urand(-50.0, 50.0);
        assert_int_equal(mc_current_loop_step_f32(&cl, 0.0f, 0.0f, e_d, e_q,
                                                  (float)urand(-100.0, 100.0), 48.0f, &out),
                         MC_OK);
        assert_true(hypot(out.v_d_V, out.v_q_V) <= v_max * (1.0 + 1e-5));
    }
    /* d priority: a huge d demand takes the whole circle. */
    mc_current_loop_reset_f32(&cl);
    mc_current_loop_out_t out;
    mc_current_loop_step_f32(&cl, 0.0f, 0.0f, 100.0f, 100.0f, 0.0f, 48.0f, &out);
    assert_near(out.v_d_V, v_max, 1e-4 * v_max);
    assert_true(fabs(out.v_q_V) <= 1.01e-4 * v_max); /* MC_CL_Q_ROOM_MIN */
    assert_true(out.saturated);
    /* Wind-up test on q: 2000 samples at +10 A error, then -0.1 A. */
    mc_current_loop_reset_f32(&cl);
    for (int k = 0; k < 2000; ++k) {
        mc_current_loop_step_f32(&cl, 0.0f, 0.0f, 0.0f, 10.0f, 0.0f, 48.0f, &out);
    }
    assert_near(out.v_q_V, v_max, 1e-4 * v_max);
    mc_current_loop_step_f32(&cl, 0.0f, 0.1f, 0.0f, 0.0f, 0.0f, 48.0f, &out);
    assert_true(out.v_q_V < v_max * (1.0 - 1e-3));
    assert_false(out.saturated);
    /* Bus voltage errors. */
    assert_int_equal(mc_current_loop_step_f32(&cl, 0, 0, 0, 0, 0, 0.0f, &out), MC_ERR_RANGE);
    assert_int_equal(mc_current_loop_step_f32(&cl, 0, 0, 0, 0, 0, NAN, &out), MC_ERR_NONFINITE);
}

/* Inputs of one step: i_d, i_q, i_d_ref, i_q_ref (A), omega_e (rad/s). */
enum { CL_IN_N = 5 };

/* Saturated integrators (both axes wound up to the +- limits) or reset
 * ones, for the propagation checks below. */
static void cl_state(mc_current_loop_f32_t *cl, int kind)
{
    mc_current_loop_reset_f32(cl);
    const float e = (kind == 1) ? 50.0f : -50.0f;
    for (int k = 0; kind != 0 && k < 50; ++k) {
        (void)mc_current_loop_step_unchecked_f32(cl, 0.0f, 0.0f, e, e, 0.0f, 48.0f);
    }
}

/* The unchecked step (the drive's ISR path) gives what the checked one
 * gives, bit for bit, saturated or not; a NaN or infinite current,
 * reference or speed gives a non-finite v_d or v_q, whatever the
 * integrators and the speed (the application checks them), and the
 * checked step reports it. */
static void test_current_loop_unchecked(void **state)
{
    (void)state;
    mc_current_loop_params_t p = paper_params(2000.0f);
    p.Ld_H = 3.0e-3f;
    mc_current_loop_f32_t checked;
    mc_current_loop_f32_t unchecked;
    assert_int_equal(mc_current_loop_init_f32(&checked, &p), MC_OK);
    unchecked = checked;
    int saturated = 0;
    for (int i = 0; i < 20000; ++i) {
        const float id = (float)urand(-10.0, 10.0), iq = (float)urand(-10.0, 10.0);
        const float e = (i % 2) ? 0.5f : 50.0f; /* small errors, saturating ones */
        const float id_ref = id + e * (float)urand(-1.0, 1.0);
        const float iq_ref = iq + e * (float)urand(-1.0, 1.0);
        const float w = (float)urand(-500.0, 500.0), v_dc = (float)urand(10.0, 100.0);
        mc_current_loop_out_t o;
        assert_int_equal(mc_current_loop_step_f32(&checked, id, iq, id_ref, iq_ref, w, v_dc, &o),
                         MC_OK);
        const mc_current_loop_out_t u =
            mc_current_loop_step_unchecked_f32(&unchecked, id, iq, id_ref, iq_ref, w, v_dc);
        assert_memory_equal(&u.v_d_V, &o.v_d_V, sizeof(float));
        assert_memory_equal(&u.v_q_V, &o.v_q_V, sizeof(float));
        assert_true(u.saturated == o.saturated);
        saturated += o.saturated;
    }
    assert_true(saturated > 2000 && saturated < 18000);

    const float bad[] = { NAN, INFINITY, -INFINITY };
    const float speeds[] = { 0.0f, 300.0f, -300.0f };
    for (int in = 0; in < CL_IN_N; ++in) {
        for (size_t b = 0; b < sizeof bad / sizeof bad[0]; ++b) {
            for (size_t w = 0; w < sizeof speeds / sizeof speeds[0]; ++w) {
                for (int kind = 0; kind < 3; ++kind) {
                    float x[CL_IN_N] = { 1.0f, 2.0f, 1.5f, 2.5f, speeds[w] };
                    x[in] = bad[b];
                    cl_state(&unchecked, kind);
                    const mc_current_loop_out_t u = mc_current_loop_step_unchecked_f32(
                        &unchecked, x[0], x[1], x[2], x[3], x[4], 48.0f);
                    assert_false(isfinite(u.v_d_V) && isfinite(u.v_q_V));
                    cl_state(&checked, kind);
                    mc_current_loop_out_t o;
                    assert_int_equal(
                        mc_current_loop_step_f32(&checked, x[0], x[1], x[2], x[3], x[4], 48.0f, &o),
                        MC_ERR_NONFINITE);
                }
            }
        }
    }
}

/* The current step on a checked bus: a non-finite current, reference or speed runs through to a
 * non-finite v_d or v_q (the application's output check). */
static void test_drive_current_step(void **state)
{
    (void)state;
    mc_drive_t d;
    memset(&d, 0, sizeof d);
    const mc_current_loop_params_t p = paper_params(2000.0f);
    assert_int_equal(mc_current_loop_init_f32(&d.current, &p), MC_OK);
    d.n_p = 4.0f;
    mc_telemetry_t t;
    memset(&t, 0, sizeof t);
    t.i_d_A = 0.5f;
    t.i_q_A = 1.0f;
    t.i_q_ref_A = 2.0f;
    t.omega_m_rad_s = 50.0f;
    t.v_dc_V = 48.0f;
    mc_drive_current_step(&d, &t);
    assert_true(isfinite(t.v_d_V) && isfinite(t.v_q_V) && t.v_q_V > 0.0f);

    const float bad[] = { NAN, INFINITY, -INFINITY };
    for (int in = 0; in < CL_IN_N; ++in) {
        for (size_t b = 0; b < sizeof bad / sizeof bad[0]; ++b) {
            mc_current_loop_reset_f32(&d.current);
            mc_telemetry_t tb = t;
            float *const x[CL_IN_N] = { &tb.i_d_A, &tb.i_q_A, &tb.i_d_ref_A, &tb.i_q_ref_A,
                                        &tb.omega_m_rad_s };
            *x[in] = bad[b];
            mc_drive_current_step(&d, &tb);
            assert_false(isfinite(tb.v_d_V) && isfinite(tb.v_q_V));
        }
    }
}

/* Speed loop on the ideal mechanics J dw/dt = k_t i_q - T_L (exact per
 * sample): the load-step dip matches the analytic design
 * -(T_L/J)(2/w_s)/e within 3 % (discretisation at w_s Ts = 0.025), the
 * error returns to zero, the output respects i_q_max. */
static void test_speed_loop_load_response(void **state)
{
    (void)state;
    const double J = 0.012, k_t = 0.765, w_s = 50.0, Ts = 5e-4, T_L = 2.0;
    const mc_speed_loop_params_t p = {
        .J_kgm2 = (float)J,
        .B_Nm_s_rad = 0.0f,
        .kt_Nm_per_A = (float)k_t,
        .bandwidth_rad_s = (float)w_s,
        .i_q_max_A = 10.0f,
        .Ts_s = (float)Ts,
    };
    mc_speed_loop_f32_t sl;
    assert_int_equal(mc_speed_loop_init_f32(&sl, &p), MC_OK);
    double w = 0.0, dip = 0.0;
    for (int k = 0; k < 2000; ++k) { /* 1 s */
        const float iq = mc_speed_loop_step_f32(&sl, 0.0f, (float)w);
        assert_true(fabsf(iq) <= 10.0f);
        w += Ts * (k_t * (double)iq - T_L) / J;
        dip = fmin(dip, w);
    }
    const double expected = -(T_L / J) * (2.0 / w_s) / exp(1.0);
    assert_near(dip, expected, 0.03 * fabs(expected));
    assert_true(fabs(w) < 1e-3);
    /* Saturation: a large error gives exactly the limit. */
    mc_speed_loop_reset_f32(&sl);
    assert_near(mc_speed_loop_step_f32(&sl, 1000.0f, 0.0f), 10.0f, 0.0f);
    assert_true(isnan(mc_speed_loop_step_f32(&sl, NAN, 0.0f)));
    /* every non-finite input gives NaN, from any integrator state */
    const float bad[] = { NAN, INFINITY, -INFINITY };
    for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
        for (int wound = 0; wound < 2; wound++) {
            mc_speed_loop_reset_f32(&sl);
            for (int k = 0; wound && k < 100; k++) {
                (void)mc_speed_loop_step_f32(&sl, 1000.0f, 0.0f);
            }
            mc_speed_loop_f32_t sl2 = sl;
            assert_true(isnan(mc_speed_loop_step_f32(&sl, bad[b], 0.0f)));
            assert_true(isnan(mc_speed_loop_step_f32(&sl2, 0.0f, bad[b])));
        }
    }
    /* A friction feed-forward gain B / k_t beyond float range is rejected
     * at init (finite inputs, infinite ratio), not a fault every step. */
    mc_speed_loop_params_t huge_b = p;
    huge_b.B_Nm_s_rad = 3e38f;
    huge_b.kt_Nm_per_A = 0.1f;
    assert_int_equal(mc_speed_loop_init_f32(&sl, &huge_b), MC_ERR_PARAM);
}

static void test_position_loop(void **state)
{
    (void)state;
    mc_position_loop_f32_t pl;
    assert_int_equal(mc_position_loop_init_f32(&pl, 12.5f, 40.0f), MC_OK);
    for (int i = 0; i < 1000; ++i) {
        const double r = urand(-10.0, 10.0), y = urand(-10.0, 10.0);
        const double expected = fmax(-40.0, fmin(40.0, 12.5 * (r - y)));
        assert_near(mc_position_loop_step_f32(&pl, (float)r, (float)y), expected,
                    1e-5 * (1.0 + fabs(expected)));
    }
    assert_true(isnan(mc_position_loop_step_f32(&pl, NAN, 0.0f)));
    assert_int_equal(mc_position_loop_init_f32(&pl, 0.0f, 1.0f), MC_ERR_PARAM);
}

/* The rate rules the blocks check themselves (mc/current_loop.h,
 * mc/speed_loop.h): w_c Ts <= MC_CURRENT_LOOP_WTS_MAX = 0.5 and
 * w_s Ts <= MC_SPEED_LOOP_WTS_MAX = 0.2 of the loop's own period. */
static void test_loop_rate_limits(void **state)
{
    (void)state;
    mc_current_loop_f32_t cl;
    mc_current_loop_params_t p = paper_params(10000.0f); /* w_c Ts = 0.5 */
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_OK);
    p.cfg.bandwidth_rad_s = 10100.0f; /* 0.505 */
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_ERR_PARAM);
    p.cfg.bandwidth_rad_s = 12000.0f; /* 0.6 */
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_ERR_PARAM);
    p = paper_params(2513.0f);
    p.cfg.modulation_margin = 1.0f;
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_OK);
    p.cfg.modulation_margin = 1.01f;
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_ERR_PARAM);
    p.cfg.modulation_margin = 0.0f;
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_ERR_PARAM);
    p.cfg.modulation_margin = NAN;
    assert_int_equal(mc_current_loop_init_f32(&cl, &p), MC_ERR_NONFINITE);

    mc_speed_loop_params_t s = {
        .J_kgm2 = 0.012f,
        .B_Nm_s_rad = 0.0f,
        .kt_Nm_per_A = 0.765f,
        .bandwidth_rad_s = 400.0f,
        .i_q_max_A = 10.0f,
        .Ts_s = 4.0e-4f,
    }; /* w_s Ts = 0.16 */
    mc_speed_loop_f32_t sl;
    assert_int_equal(mc_speed_loop_init_f32(&sl, &s), MC_OK);
    s.bandwidth_rad_s = 510.0f; /* 0.204 */
    assert_int_equal(mc_speed_loop_init_f32(&sl, &s), MC_ERR_PARAM);
    s.Ts_s = 3.9e-4f; /* 0.1989 */
    assert_int_equal(mc_speed_loop_init_f32(&sl, &s), MC_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_current_pi_design),
        cmocka_unit_test(test_current_closed_loop_is_first_order),
        cmocka_unit_test(test_decoupling_feed_forward),
        cmocka_unit_test(test_voltage_limit_and_anti_windup),
        cmocka_unit_test(test_current_loop_unchecked),
        cmocka_unit_test(test_drive_current_step),
        cmocka_unit_test(test_speed_loop_load_response),
        cmocka_unit_test(test_position_loop),
        cmocka_unit_test(test_loop_rate_limits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
