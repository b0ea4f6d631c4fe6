/* Metrics against synthetic signals whose metrics are known analytically or
 * by hand. */
#include "mc_test.h"

#include <math.h>

#include "sim/metrics.h"

#define N_MAX    20001
#define SENTINEL 12345.0

static double t_buf[N_MAX];
static double y_buf[N_MAX];
static double ref_buf[N_MAX];

static sim_signal_t sampled(size_t n)
{
    return (sim_signal_t){ .t = t_buf, .y = y_buf, .n = n };
}

/* First-order step from y0 to y1 with time constant tau, step at t = 0. */
static sim_signal_t first_order(double y0, double y1, double tau_s, double dt_s, size_t n)
{
    for (size_t k = 0; k < n; k++) {
        t_buf[k] = (double)k * dt_s;
        y_buf[k] = y1 + (y0 - y1) * exp(-t_buf[k] / tau_s);
    }
    return sampled(n);
}

/* Unit step response of wn^2 / (s^2 + 2 zeta wn s + wn^2), step at t_step. */
static sim_signal_t second_order(double zeta, double wn, double t_step_s, double dt_s, size_t n)
{
    double wd = wn * sqrt(1.0 - zeta * zeta);
    for (size_t k = 0; k < n; k++) {
        t_buf[k] = (double)k * dt_s;
        double tau = t_buf[k] - t_step_s;
        double decay = exp(-zeta * wn * tau);
        double phase = cos(wd * tau) + zeta / sqrt(1.0 - zeta * zeta) * sin(wd * tau);
        y_buf[k] = tau < 0.0 ? 0.0 : 1.0 - decay * phase;
    }
    return sampled(n);
}

/* Hand-made samples at t = 0, 1, 2, ... */
static sim_signal_t hand_made(const double *y, size_t n)
{
    for (size_t k = 0; k < n; k++) {
        t_buf[k] = (double)k;
        y_buf[k] = y[k];
    }
    return sampled(n);
}

static void first_order_rise_and_settling_match_analytic(void **state)
{
    (void)state;
    const double tau = 0.01;
    sim_signal_t sig = first_order(100.0, 500.0, tau, tau / 1000.0, 10001);
    sim_step_t step = { .t_step_s = 0.0, .y_initial = 100.0, .y_final = 500.0 };

    double rise = SENTINEL;
    assert_int_equal(sim_metrics_rise_time(&sig, &step, &rise), SIM_METRICS_OK);
    /* t90 - t10 = tau (ln 10 - ln(10/9)) = tau ln 9 (about 2.2 tau) */
    assert_true(fabs(rise - tau * log(9.0)) < 1e-4 * tau);

    double settle = SENTINEL;
    assert_int_equal(sim_metrics_settling_time(&sig, &step, 0.02, &settle), SIM_METRICS_OK);
    assert_true(fabs(settle - tau * log(50.0)) < 1e-4 * tau); /* exp(-t/tau) = 0.02 */
    assert_int_equal(sim_metrics_settling_time(&sig, &step, 0.05, &settle), SIM_METRICS_OK);
    assert_true(fabs(settle - tau * log(20.0)) < 1e-4 * tau);

    double overshoot = SENTINEL;
    assert_int_equal(sim_metrics_overshoot(&sig, &step, &overshoot), SIM_METRICS_OK);
    assert_true(overshoot == 0.0);
}

static void downward_step_is_measured_like_an_upward_one(void **state)
{
    (void)state;
    const double tau = 0.02;
    sim_signal_t sig = first_order(3.0, -1.0, tau, tau / 1000.0, 10001);
    sim_step_t step = { .t_step_s = 0.0, .y_initial = 3.0, .y_final = -1.0 };
    double rise = SENTINEL;
    double settle = SENTINEL;
    double overshoot = SENTINEL;
    assert_int_equal(sim_metrics_rise_time(&sig, &step, &rise), SIM_METRICS_OK);
    assert_true(fabs(rise - tau * log(9.0)) < 1e-4 * tau);
    assert_int_equal(sim_metrics_settling_time(&sig, &step, 0.02, &settle), SIM_METRICS_OK);
    assert_true(fabs(settle - tau * log(50.0)) < 1e-4 * tau);
    assert_int_equal(sim_metrics_overshoot(&sig, &step, &overshoot), SIM_METRICS_OK);
    assert_true(overshoot == 0.0);
}

static void second_order_overshoot_matches_analytic(void **state)
{
    (void)state;
    const double zeta = 0.3;
    const double wn = 100.0;
    /* Step at 5 ms: samples before it (at 0) must not count. */
    sim_signal_t sig = second_order(zeta, wn, 0.005, 1e-5, 20001);
    sim_step_t step = { .t_step_s = 0.005, .y_initial = 0.0, .y_final = 1.0 };
    double overshoot = SENTINEL;
    assert_int_equal(sim_metrics_overshoot(&sig, &step, &overshoot), SIM_METRICS_OK);
    double expected = 100.0 * exp(-zeta * MC_TEST_PI / sqrt(1.0 - zeta * zeta)); /* 37.23 % */
    assert_true(fabs(overshoot - expected) < 1e-3);

    /* 2 % settling: the response must stay in the band after it, and the
     * envelope bound 1 + exp(-zeta wn t)/sqrt(1-zeta^2) gives an upper bound. */
    double settle = SENTINEL;
    assert_int_equal(sim_metrics_settling_time(&sig, &step, 0.02, &settle), SIM_METRICS_OK);
    double envelope_bound = log(1.0 / (0.02 * sqrt(1.0 - zeta * zeta))) / (zeta * wn);
    assert_true(settle > 0.0 && settle <= envelope_bound);
    for (size_t k = 0; k < sig.n; k++) {
        if (sig.t[k] >= 0.005 + settle + 1e-5) {
            assert_true(fabs(sig.y[k] - 1.0) <= 0.02);
        }
    }
}

static void hand_made_samples_interpolate_crossings(void **state)
{
    (void)state;
    const double y[] = { 0.0, 0.5, 1.1, 0.97, 1.01, 1.0 };
    sim_signal_t sig = hand_made(y, 6);
    sim_step_t step = { .t_step_s = 0.0, .y_initial = 0.0, .y_final = 1.0 };
    double rise = SENTINEL;
    double settle = SENTINEL;
    double overshoot = SENTINEL;
    /* 10 % at t = 0.2; 90 % between (1, 0.5) and (2, 1.1): t = 1 + 0.4/0.6 */
    assert_int_equal(sim_metrics_rise_time(&sig, &step, &rise), SIM_METRICS_OK);
    assert_true(fabs(rise - (1.0 + 0.4 / 0.6 - 0.2)) < 1e-12);
    /* last sample outside 2 %: t = 3 (0.97); band edge 0.98 reached at 3.25 */
    assert_int_equal(sim_metrics_settling_time(&sig, &step, 0.02, &settle), SIM_METRICS_OK);
    assert_true(fabs(settle - 3.25) < 1e-12);
    assert_int_equal(sim_metrics_overshoot(&sig, &step, &overshoot), SIM_METRICS_OK);
    assert_true(fabs(overshoot - 10.0) < 1e-9);
}

/* y = 500 + offset + A sin(2 pi 50 t), 200 samples per period, ref = 500. */
static sim_signal_t sinusoid_about_reference(double amplitude, double offset, size_t n)
{
    const double f_hz = 50.0;
    const double dt = 1.0 / (200.0 * f_hz);
    for (size_t k = 0; k < n; k++) {
        t_buf[k] = (double)k * dt;
        ref_buf[k] = 500.0;
        y_buf[k] = 500.0 + offset + amplitude * sin(MC_TEST_TWO_PI * f_hz * t_buf[k]);
    }
    return sampled(n);
}

static void sinusoid_rms_fluctuation_and_offset(void **state)
{
    (void)state;
    const double amp = 9.5;
    sim_signal_t sig = sinusoid_about_reference(amp, 0.0, 4001);
    /* Ten whole periods, 2000 samples: [0, 0.2 - dt/2] */
    const double t1 = 0.2 - 0.5e-4;
    double rms = SENTINEL;
    assert_int_equal(sim_metrics_rms_error(&sig, ref_buf, 0.0, t1, &rms), SIM_METRICS_OK);
    assert_true(fabs(rms - amp / sqrt(2.0)) < 1e-9);

    double fluct = SENTINEL;
    double rate = SENTINEL;
    assert_int_equal(sim_metrics_fluctuation(&sig, 0.0, t1, &fluct, &rate), SIM_METRICS_OK);
    assert_true(fabs(fluct - amp) < 1e-9);
    /* (max - min) / (max + min) * 100 = 2 A / 1000 * 100 (paper 002 Case I PID: 1.9 %) */
    assert_true(fabs(rate - 2.0 * amp / 1000.0 * 100.0) < 1e-9);

    double offset = SENTINEL;
    assert_int_equal(sim_metrics_offset_error(&sig, ref_buf, 0.0, t1, &offset), SIM_METRICS_OK);
    assert_true(fabs(offset) < 1e-9);

    sig = sinusoid_about_reference(amp, -6.9, 4001);
    assert_int_equal(sim_metrics_offset_error(&sig, ref_buf, 0.0, t1, &offset), SIM_METRICS_OK);
    assert_true(fabs(offset - (-6.9)) < 1e-9);
    /* RMS of a constant offset plus a sinusoid: sqrt(c^2 + A^2/2) */
    assert_int_equal(sim_metrics_rms_error(&sig, ref_buf, 0.0, t1, &rms), SIM_METRICS_OK);
    assert_true(fabs(rms - sqrt(6.9 * 6.9 + amp * amp / 2.0)) < 1e-9);
}

static void window_selects_only_its_samples(void **state)
{
    (void)state;
    const double y[] = { 0.0, 10.0, -4.0, 2.0, 3.0, -50.0 };
    sim_signal_t sig = hand_made(y, 6);
    double peak = SENTINEL;
    double fluct = SENTINEL;
    assert_int_equal(sim_metrics_peak_abs(&sig, 1.0, 4.0, &peak), SIM_METRICS_OK);
    assert_true(peak == 10.0);
    assert_int_equal(sim_metrics_peak_abs(&sig, 1.5, 4.5, &peak), SIM_METRICS_OK);
    assert_true(peak == 4.0);
    assert_int_equal(sim_metrics_peak_abs(&sig, 0.0, 5.0, &peak), SIM_METRICS_OK);
    assert_true(peak == 50.0);
    assert_int_equal(sim_metrics_fluctuation(&sig, 2.0, 4.0, &fluct, NULL), SIM_METRICS_OK);
    assert_true(fluct == 3.5); /* (3 - (-4)) / 2 */
}

static void load_step_dip_found_at_its_peak(void **state)
{
    (void)state;
    /* y = ref - D x exp(1 - x), x = (t - t_step)/tau: largest deviation D at x = 1 */
    const double depth = 53.7;
    const double tau = 0.004;
    const double t_step = 0.1;
    const double dt = 1e-4;
    for (size_t k = 0; k < 3001; k++) {
        t_buf[k] = (double)k * dt;
        ref_buf[k] = 500.0;
        double x = (t_buf[k] - t_step) / tau;
        y_buf[k] = x <= 0.0 ? 500.0 : 500.0 - depth * x * exp(1.0 - x);
    }
    sim_signal_t sig = sampled(3001);
    double dip = SENTINEL;
    double t_dip = SENTINEL;
    assert_int_equal(sim_metrics_max_dip(&sig, ref_buf, t_step, 0.05, &dip, &t_dip),
                     SIM_METRICS_OK);
    assert_true(fabs(dip - depth) < 1e-9);
    assert_true(fabs(t_dip - (t_step + tau)) < dt / 2.0);
}

/* Recovery after a load step: y = ref + e_inf - D exp(-x / tau), x = t -
 * t_step, settles to the offset e_inf (a controller that keeps an offset,
 * like paper 002's HDOBC). |y - ref - e_inf| = D exp(-x / tau) enters the
 * band b at x = tau ln(D / b) and stays: with D = 60, b = 10, tau = 5 ms,
 * 8.9588 ms. A later single excursion beyond the band moves the answer to
 * its end; a response that ends outside the band never recovers; one never
 * outside recovers at once. */
static void load_step_recovery_time_matches_analytic(void **state)
{
    (void)state;
    const double D = 60.0, tau = 0.005, t_step = 0.1, dt = 1e-4, band = 10.0, e_inf = -6.0;
    for (size_t k = 0; k < 2001; k++) {
        t_buf[k] = (double)k * dt;
        ref_buf[k] = 500.0;
        const double x = t_buf[k] - t_step;
        y_buf[k] = x < 0.0 ? 500.0 : 500.0 + e_inf - D * exp(-x / tau);
    }
    sim_signal_t sig = sampled(2001);
    double rec = SENTINEL;
    double settled = SENTINEL;
    assert_int_equal(sim_metrics_recovery_time(&sig, ref_buf, t_step, 0.1, band, &rec, &settled),
                     SIM_METRICS_OK);
    assert_true(fabs(settled - e_inf) < 1e-4);
    assert_true(fabs(rec - tau * log(D / band)) < 1e-6);

    /* an excursion of +12 at samples x = 30.0 and 30.1 ms: back in the band
     * (linear interpolation) at x = 30.1 ms + dt (12 - 10) / 12 */
    const size_t k30 = (size_t)llround((t_step + 0.030) / dt);
    y_buf[k30] = y_buf[k30 + 1] = 500.0 + e_inf + 12.0;
    const double y_next = y_buf[k30 + 2] - 500.0 - e_inf; /* about -1e-1 */
    assert_int_equal(sim_metrics_recovery_time(&sig, ref_buf, t_step, 0.1, band, &rec, NULL),
                     SIM_METRICS_OK);
    const double want = 0.0301 + dt * (12.0 - band) / (12.0 - y_next);
    assert_true(fabs(rec - want) < 1e-9);

    /* ends outside the band: a ramp away from the reference */
    for (size_t k = 0; k < 2001; k++) {
        y_buf[k] = 500.0 - 1000.0 * fmax(0.0, t_buf[k] - t_step);
    }
    rec = SENTINEL;
    assert_int_equal(sim_metrics_recovery_time(&sig, ref_buf, t_step, 0.1, band, &rec, NULL),
                     SIM_METRICS_ERR_NOT_REACHED);
    assert_true(rec == SENTINEL);
    /* never outside */
    for (size_t k = 0; k < 2001; k++) {
        y_buf[k] = 500.0 + 0.5 * sin(100.0 * t_buf[k]);
    }
    assert_int_equal(sim_metrics_recovery_time(&sig, ref_buf, t_step, 0.1, band, &rec, NULL),
                     SIM_METRICS_OK);
    assert_true(rec == 0.0);
    assert_int_equal(sim_metrics_recovery_time(&sig, ref_buf, t_step, 0.1, 0.0, &rec, NULL),
                     SIM_METRICS_ERR_ARGUMENT);
    assert_int_equal(sim_metrics_recovery_time(&sig, NULL, t_step, 0.1, band, &rec, NULL),
                     SIM_METRICS_ERR_ARGUMENT);
    assert_int_equal(sim_metrics_recovery_time(&sig, ref_buf, 0.5, 0.1, band, &rec, NULL),
                     SIM_METRICS_ERR_EMPTY);
}

static void degenerate_inputs_give_error_codes(void **state)
{
    (void)state;
    sim_signal_t sig = first_order(0.0, 1.0, 0.01, 1e-4, 1001);
    sim_step_t zero = { .t_step_s = 0.0, .y_initial = 1.0, .y_final = 1.0 };
    sim_step_t late = { .t_step_s = 1.0, .y_initial = 0.0, .y_final = 1.0 };
    sim_step_t ok = { .t_step_s = 0.0, .y_initial = 0.0, .y_final = 1.0 };
    sim_step_t too_high = { .t_step_s = 0.0, .y_initial = 0.0, .y_final = 2.0 };
    double out = SENTINEL;

    assert_int_equal(sim_metrics_rise_time(&sig, &zero, &out), SIM_METRICS_ERR_ZERO_STEP);
    assert_int_equal(sim_metrics_overshoot(&sig, &zero, &out), SIM_METRICS_ERR_ZERO_STEP);
    assert_int_equal(sim_metrics_settling_time(&sig, &late, 0.02, &out), SIM_METRICS_ERR_EMPTY);
    /* reaches only 50 % of a step to 2: no 90 % crossing, never settles */
    assert_int_equal(sim_metrics_rise_time(&sig, &too_high, &out), SIM_METRICS_ERR_NOT_REACHED);
    assert_int_equal(sim_metrics_settling_time(&sig, &too_high, 0.02, &out),
                     SIM_METRICS_ERR_NOT_REACHED);
    assert_int_equal(sim_metrics_settling_time(&sig, &ok, 0.0, &out), SIM_METRICS_ERR_ARGUMENT);
    assert_int_equal(sim_metrics_peak_abs(&sig, 0.2, 0.1, &out), SIM_METRICS_ERR_ARGUMENT);
    assert_int_equal(sim_metrics_peak_abs(&sig, 0.05001, 0.05009, &out), SIM_METRICS_ERR_EMPTY);
    assert_int_equal(sim_metrics_rms_error(&sig, NULL, 0.0, 0.1, &out), SIM_METRICS_ERR_ARGUMENT);
    assert_int_equal(sim_metrics_max_dip(&sig, sig.y, 0.0, -1.0, &out, NULL),
                     SIM_METRICS_ERR_ARGUMENT);

    sim_signal_t empty = { .t = t_buf, .y = y_buf, .n = 0 };
    assert_int_equal(sim_metrics_peak_abs(&empty, 0.0, 1.0, &out), SIM_METRICS_ERR_ARGUMENT);

    /* symmetric about zero: fluctuation rate has a zero denominator */
    const double sym[] = { -1.0, 1.0, -1.0 };
    sim_signal_t s = hand_made(sym, 3);
    double fluct = SENTINEL;
    assert_int_equal(sim_metrics_fluctuation(&s, 0.0, 2.0, &fluct, &out),
                     SIM_METRICS_ERR_ZERO_STEP);
    assert_true(fluct == SENTINEL);

    /* non-finite sample, time not increasing */
    const double y_nan[] = { 0.0, NAN, 1.0 };
    s = hand_made(y_nan, 3);
    assert_int_equal(sim_metrics_peak_abs(&s, 0.0, 2.0, &out), SIM_METRICS_ERR_ARGUMENT);
    const double y_ok[] = { 0.0, 1.0, 2.0 };
    s = hand_made(y_ok, 3);
    t_buf[2] = t_buf[1];
    assert_int_equal(sim_metrics_peak_abs(&s, 0.0, 2.0, &out), SIM_METRICS_ERR_ARGUMENT);

    assert_true(out == SENTINEL); /* never written on failure */
    assert_string_equal(sim_metrics_status_str(SIM_METRICS_ERR_EMPTY), "no sample in the window");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(first_order_rise_and_settling_match_analytic),
        cmocka_unit_test(downward_step_is_measured_like_an_upward_one),
        cmocka_unit_test(second_order_overshoot_matches_analytic),
        cmocka_unit_test(hand_made_samples_interpolate_crossings),
        cmocka_unit_test(sinusoid_rms_fluctuation_and_offset),
        cmocka_unit_test(window_selects_only_its_samples),
        cmocka_unit_test(load_step_dip_found_at_its_peak),
        cmocka_unit_test(load_step_recovery_time_matches_analytic),
        cmocka_unit_test(degenerate_inputs_give_error_codes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
