/*
 * Closed-loop speed control with a load-torque step (baseline FOC, encoder).
 *
 * Expectation (independent of the code): the speed PI is designed as
 * kp = J w_s / k_t, ki = kp w_s / 4; with an ideal current loop the load
 * disturbance T_L (step at t_L) gives the speed deviation
 *   dw(t) = -(T_L / J) (t - t_L) exp(-w_s (t - t_L) / 2)
 * (double pole at -w_s/2), peak -(T_L / J) (2 / w_s) / e at t_L + 2 / w_s.
 * The real loop adds lags: the current loop (first order, w_c = 50 w_s), the
 * encoder PLL speed output (w_pll^2 / (s + w_pll)^2, w_pll = 20 w_s) and the
 * slow-loop sampling (Ts_slow = 0.5 ms, ZOH: about Ts_slow / 2 delay). A
 * second expectation, a double-precision simulation of exactly that
 * continuous loop (written here from the design equations), predicts the
 * peak within 3 % and its time within 5 %; the ideal analytic peak is
 * checked within 10 %.
 * Integral action: the error returns to zero; it must stay inside
 * 0.05 rad/s (0.25 % of the set point) from t_L + 0.3 s on, where the
 * analytic deviation is 0.03 rad/s.
 */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sim_fixture.h"

#define OMEGA_REF_RAD_S 20.0
#define T_LOAD_NM       2.0
#define T_STEP_S        0.05 /* speed step */
#define T_LOAD_S        0.6  /* load step */
#define T_END_S         1.1

typedef struct {
    double dip;     /* most negative speed deviation, rad/s */
    double t_dip_s; /* its time after the load step */
} dip_t;

/* Reference loop with the designed lags, load step at t = 0 from
 * equilibrium (speed error 0): Euler, h = 1 us, 0.3 s. */
static dip_t reference_dip(const mc_config_t *fc, double T_L)
{
    const double J = (double)fc->motor.J_kgm2;
    const double k_t = 1.5 * (double)fc->motor.pole_pairs * (double)fc->motor.psi_Wb;
    const double w_s = (double)fc->foc_pi.speed_bandwidth_rad_s;
    const double w_c = (double)fc->current.bandwidth_rad_s;
    const double w_p = (double)fc->encoder.pll_bandwidth_rad_s;
    const double kp = J * w_s / k_t;
    const double ki = kp * w_s / 4.0;
    const double delay_s = 0.5 / (double)fc->timing.slow_loop_Hz;
    const double h = 1e-6;
    const size_t n_delay = (size_t)llround(delay_s / h);
    const size_t n = (size_t)(0.3 / h);
    double *iq_ref_hist = calloc(n_delay + 1u, sizeof *iq_ref_hist);
    assert_non_null(iq_ref_hist);
    /* deviations from the pre-load equilibrium */
    double w = 0.0, iq = 0.0, f1 = 0.0, f2 = 0.0, integ = 0.0;
    dip_t d = { 0.0, 0.0 };
    for (size_t k = 0; k < n; ++k) {
        const double e = -f2; /* reference - estimate */
        integ += ki * e * h;
        iq_ref_hist[k % (n_delay + 1u)] = kp * e + integ;
        const double iq_ref = (k >= n_delay) ? iq_ref_hist[(k - n_delay) % (n_delay + 1u)] : 0.0;
        const double dw = (k_t * iq - T_L) / J;
        const double diq = w_c * (iq_ref - iq);
        const double df1 = w_p * (w - f1);
        const double df2 = w_p * (f1 - f2);
        w += h * dw;
        iq += h * diq;
        f1 += h * df1;
        f2 += h * df2;
        if (w < d.dip) {
            d.dip = w;
            d.t_dip_s = (double)(k + 1u) * h;
        }
    }
    free(iq_ref_hist);
    return d;
}

static void test_speed_step_then_load_step(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    fixture_plant_config(&pc);
    /* Load: 0 until T_LOAD_S, then T_LOAD_NM (right-continuous step). */
    sim_profile_clear(&pc.load_torque_Nm);
    pc.load_torque_Nm.points[0] = (sim_profile_point_t){ T_LOAD_S, 0.0 };
    pc.load_torque_Nm.points[1] = (sim_profile_point_t){ T_LOAD_S, T_LOAD_NM };
    pc.load_torque_Nm.n_points = 2u;
    fixture_fw_config(&pc, &fc);
    const double J = (double)fc.motor.J_kgm2;
    const double w_s = (double)fc.foc_pi.speed_bandwidth_rad_s;

    mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    sim_engine_t *e = fixture_running(&pc, &fc, &cmd);
    fixture_run_until(e, &cmd, T_STEP_S);
    cmd.omega_m_ref_rad_s = (float)OMEGA_REF_RAD_S;

    double dip = 0.0, t_dip = 0.0, err_late_max = 0.0, err_pre_max = 0.0;
    double est_err_max = 0.0;
    while (sim_engine_time_s(e) < T_END_S) {
        assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_OK);
        const sim_trace_sample_t *s = sim_engine_last(e);
        assert_int_equal(s->fw.state, MC_STATE_RUN);
        const double err = s->plant.omega_m_rad_s - OMEGA_REF_RAD_S;
        if (s->t_s >= T_LOAD_S - 0.1 && s->t_s < T_LOAD_S) {
            err_pre_max = fmax(err_pre_max, fabs(err));
            est_err_max =
                fmax(est_err_max, fabs((double)s->fw.omega_m_rad_s - s->plant.omega_m_rad_s));
        }
        if (s->t_s >= T_LOAD_S && err < dip) {
            dip = err;
            t_dip = s->t_s - T_LOAD_S;
        }
        if (s->t_s >= T_LOAD_S + 0.3) {
            err_late_max = fmax(err_late_max, fabs(err));
        }
    }
    const double dip_expected = -(T_LOAD_NM / J) * (2.0 / w_s) / exp(1.0);
    const double t_dip_expected = 2.0 / w_s;
    printf("before load: max |speed error| %.4f rad/s, max |estimate error| "
           "%.4f rad/s\n",
           err_pre_max, est_err_max);
    printf("load step %.1f N m: dip %.3f rad/s at +%.1f ms (analytic %.3f at "
           "+%.1f ms)\n",
           T_LOAD_NM, dip, t_dip * 1e3, dip_expected, t_dip_expected * 1e3);
    printf("from +0.3 s: max |speed error| %.4f rad/s\n", err_late_max);
    const dip_t ref = reference_dip(&fc, T_LOAD_NM);
    printf("reference loop with the designed lags: dip %.3f rad/s at +%.1f "
           "ms\n",
           ref.dip, ref.t_dip_s * 1e3);

    /* Settled at the set point before the load step (integral action). */
    assert_true(err_pre_max < 0.05);
    assert_true(est_err_max < 0.05);
    assert_true(fabs(dip - dip_expected) <= 0.10 * fabs(dip_expected));
    assert_true(fabs(t_dip - t_dip_expected) <= 0.15 * t_dip_expected);
    assert_true(fabs(dip - ref.dip) <= 0.03 * fabs(ref.dip));
    assert_true(fabs(t_dip - ref.t_dip_s) <= 0.05 * ref.t_dip_s);
    assert_true(err_late_max < 0.05);
    /* The load is carried by i_q = T_L / k_t at the end. */
    const double k_t = 1.5 * (double)fc.motor.pole_pairs * (double)fc.motor.psi_Wb;
    const sim_trace_sample_t *s = sim_engine_last(e);
    assert_true(fabs(s->plant.i_q_A - T_LOAD_NM / k_t) < 0.02 * T_LOAD_NM / k_t);
    free(e);
}

/* Position mode (P outer loop, kp = 12.5 1/s, over the speed loop): a
 * 2 rad step settles with an overshoot below 10 % and zero steady-state
 * error up to the encoder resolution: from 1.0 s to 1.2 s after the step
 * the true position stays within one count (2 pi / 10000 rad) of the
 * reference (the speed PI's integral holds it; what remains is a
 * quantisation limit cycle). */
static void test_position_step(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    fixture_configs(&pc, &fc);
    mc_command_t cmd = { .enable = true, .mode = MC_MODE_POSITION };
    sim_engine_t *e = fixture_running(&pc, &fc, &cmd);
    const double theta0 = sim_engine_last(e)->plant.theta_m_rad;
    cmd.theta_m_ref_rad = (float)(theta0 + 2.0);
    const double t0 = sim_engine_time_s(e);
    double peak = 0.0, err_late = 0.0;
    while (sim_engine_time_s(e) < t0 + 1.2) {
        assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_OK);
        const sim_trace_sample_t *s = sim_engine_last(e);
        assert_int_equal(s->fw.state, MC_STATE_RUN);
        const double pos = s->plant.theta_m_rad - theta0;
        peak = fmax(peak, pos);
        if (s->t_s >= t0 + 1.0) {
            err_late = fmax(err_late, fabs(pos - 2.0));
        }
    }
    printf("position step 2 rad: overshoot %.5f rad, max |error| in "
           "[1.0, 1.2] s: %.6f rad\n",
           peak - 2.0, err_late);
    assert_true(peak - 2.0 < 0.2);
    assert_true(err_late < 2.0 * 3.14159265358979 / 10000.0);
    free(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_speed_step_then_load_step),
        cmocka_unit_test(test_position_step),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
