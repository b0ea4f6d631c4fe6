/*
 * The sensorless estimators' steps (mc/est_flux_pll.h, mc/est_flux_ii.h)
 * around their one finiteness test per sample:
 * - a rotor at rest at the aligned angle: no fault, finite estimates;
 * - a NaN current is NONFINITE alone, the telemetry and the position keep
 *   the last sample's values, a held sample reports a finite position
 *   (a latched fault can be cleared), and hold + start restart cleanly;
 * - a non-finite speed stage after a finite observer step is NONFINITE
 *   with ESTIMATE for an implausible |rho_hat| (as the checked steps
 *   reported it), and a finite implausible |rho_hat| or estimate is
 *   ESTIMATE with the estimates published.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "mc/config.h"
#include "mc/delay_comp.h"
#include "mc/est_flux_ii.h"
#include "mc/est_flux_pll.h"
#include "mc/faults.h"

#define HOLD_RAD 0.5f

/* The step's sine and cosine (mc/estimator.h) are those of the angle it
 * reports: against double sin/cos of that angle, within the polynomial's
 * error, the angle's own (the observer's atan2 when they come from its
 * flux vector) and a few float roundings. */
static void check_sincos(float theta_e_rad, const mc_est_sincos_t *sc)
{
    const double tol = MC_SINCOS_MAX_ABS_ERR + MC_ATAN2_MAX_ERR_RAD + 8.0 * FLT_EPSILON;
    assert_true(fabs(sc->sin_e - sin((double)theta_e_rad)) <= tol);
    assert_true(fabs(sc->cos_e - cos((double)theta_e_rad)) <= tol);
}

/* One estimator behind a uniform interface. */
typedef struct {
    uint32_t (*step)(void *est, const mc_est_input_t *in, mc_telemetry_t *t);
    void (*hold)(void *est, float theta_e_rad);
    uint32_t (*start)(void *est, float theta_e_rad, const mc_est_input_t *in);
    mc_flux_front_t *(*front)(void *est);
    float *(*speed_state)(void *est); /* a state of the speed stage */
    mc_estimate_bounds_t *(*bounds)(void *est);
} est_ops_t;

/* The interface for estimator `name` (instance type mc_est_<name>_t) with
 * `speed_state` a float state of its speed stage and `speed` the member of
 * that stage. */
#define EST_OPS(name, speed, speed_state)                                                          \
    static uint32_t name##_step(void *est, const mc_est_input_t *in, mc_telemetry_t *t)            \
    {                                                                                              \
        mc_est_sincos_t sc;                                                                        \
        const uint32_t faults = mc_est_##name##_step(est, in, t, &sc);                             \
        check_sincos(t->theta_e_rad, &sc);                                                         \
        return faults;                                                                             \
    }                                                                                              \
    static void name##_hold(void *est, float theta_e_rad)                                          \
    {                                                                                              \
        mc_est_##name##_hold(est, theta_e_rad);                                                    \
    }                                                                                              \
    static uint32_t name##_start(void *est, float theta_e_rad, const mc_est_input_t *in)           \
    {                                                                                              \
        return mc_est_##name##_start(est, theta_e_rad, in);                                        \
    }                                                                                              \
    static mc_flux_front_t *name##_front(void *est)                                                \
    {                                                                                              \
        return &((mc_est_##name##_t *)est)->front;                                                 \
    }                                                                                              \
    static float *name##_speed_state(void *est)                                                    \
    {                                                                                              \
        return &((mc_est_##name##_t *)est)->speed.speed_state;                                     \
    }                                                                                              \
    static mc_estimate_bounds_t *name##_bounds(void *est)                                          \
    {                                                                                              \
        return &((mc_est_##name##_t *)est)->speed.bounds;                                          \
    }                                                                                              \
    static const est_ops_t name##_ops = { name##_step,  name##_hold,        name##_start,          \
                                          name##_front, name##_speed_state, name##_bounds }

EST_OPS(flux_pll, pll, tau_L_Nm);
EST_OPS(flux_ii, ii, omega_comp_rad_s);

typedef struct {
    mc_est_flux_pll_t pll;
    mc_est_flux_ii_t ii;
    mc_applied_voltage_f32_t av;
    mc_est_input_t in;
} fixture_t;

static void *init(fixture_t *fx, const est_ops_t *ops)
{
    mc_config_t cfg;
    mc_config_init_default(&cfg);
    mc_timing_t tm;
    assert_int_equal(mc_timing_init(&tm, &cfg.timing, 1.0f / cfg.timing.f_pwm_Hz, 1.5f), MC_OK);
    assert_int_equal(mc_applied_voltage_init_f32(&fx->av, 1.5f), MC_OK);
    fx->in = (mc_est_input_t){ .v_applied = &fx->av, .theta_e_hold_rad = HOLD_RAD };
    if (ops == &flux_pll_ops) {
        assert_int_equal(mc_est_flux_pll_init(&fx->pll, &cfg, &tm), MC_OK);
        return &fx->pll;
    }
    assert_int_equal(mc_est_flux_ii_init(&fx->ii, &cfg, &tm), MC_OK);
    return &fx->ii;
}

/* ALIGN at HOLD_RAD (a held sample), then RUN with the rotor at rest
 * there (no current, no voltage) for n samples, each without a fault. */
static void restart_and_run(const est_ops_t *ops, void *est, fixture_t *fx, mc_telemetry_t *t,
                            int n)
{
    ops->hold(est, HOLD_RAD);
    fx->in.running = false;
    fx->in.i_alpha_A = 0.0f;
    fx->in.i_beta_A = 0.0f;
    assert_int_equal(ops->step(est, &fx->in, t), MC_FAULT_NONE);
    assert_true(t->theta_e_rad == HOLD_RAD);
    assert_true(t->theta_m_rad == HOLD_RAD / 3.0f);
    assert_int_equal(ops->start(est, HOLD_RAD, &fx->in), MC_FAULT_NONE);
    fx->in.running = true;
    for (int k = 0; k < n; k++) {
        assert_int_equal(ops->step(est, &fx->in, t), MC_FAULT_NONE);
    }
    assert_near(t->theta_e_rad, HOLD_RAD, 1e-5);
    assert_near(t->theta_m_rad, HOLD_RAD / 3.0f, 1e-5);
    assert_near(t->omega_m_rad_s, 0.0, 1e-3);
    assert_near(t->tau_L_hat_Nm, 0.0, 1e-3);
    assert_near(t->flux_ratio_sq, 1.0, 1e-5);
}

static void check_faults(const est_ops_t *ops)
{
    fixture_t fx;
    void *est = init(&fx, ops);
    mc_telemetry_t t;
    memset(&t, 0, sizeof t);
    restart_and_run(ops, est, &fx, &t, 100);

    /* a NaN current: NONFINITE alone, nothing published */
    mc_telemetry_t before = t;
    const float theta_m = ops->front(est)->theta_m_rad;
    fx.in.i_alpha_A = NAN;
    assert_int_equal(ops->step(est, &fx.in, &t), MC_FAULT_NONFINITE);
    assert_memory_equal(&before, &t, sizeof t);
    assert_true(ops->front(est)->theta_m_rad == theta_m);
    /* FAULT (held): a finite position; then a clean restart */
    fx.in.running = false;
    fx.in.i_alpha_A = 0.0f;
    assert_int_equal(ops->step(est, &fx.in, &t), MC_FAULT_NONE);
    assert_true(t.theta_m_rad == theta_m);
    restart_and_run(ops, est, &fx, &t, 100);

    /* a non-finite speed stage after a finite observer step */
    *ops->speed_state(est) = INFINITY;
    assert_int_equal(ops->step(est, &fx.in, &t), MC_FAULT_NONFINITE);
    restart_and_run(ops, est, &fx, &t, 10);
    const float ratio_max_sq = ops->front(est)->ratio_max_sq;
    *ops->speed_state(est) = NAN;
    ops->front(est)->ratio_max_sq = 0.5f; /* |rho_hat|^2 = 1 implausible */
    assert_int_equal(ops->step(est, &fx.in, &t), MC_FAULT_NONFINITE | MC_FAULT_ESTIMATE);
    ops->front(est)->ratio_max_sq = ratio_max_sq;

    /* finite and implausible: ESTIMATE, the estimates published; a flux
     * below ratio_min on every sample (it guards the sine and cosine's
     * division), one above ratio_max and estimates out of their bounds
     * on a slow tick (the plausibility test), not between */
    restart_and_run(ops, est, &fx, &t, 10);
    const float ratio_min_sq = ops->front(est)->ratio_min_sq;
    ops->front(est)->ratio_min_sq = 2.0f;
    assert_int_equal(ops->step(est, &fx.in, &t), MC_FAULT_ESTIMATE);
    ops->front(est)->ratio_min_sq = ratio_min_sq;
    restart_and_run(ops, est, &fx, &t, 10);
    ops->front(est)->ratio_max_sq = 0.5f;
    t.flux_ratio_sq = 0.0f;
    assert_int_equal(ops->step(est, &fx.in, &t), MC_FAULT_NONE);
    assert_near(t.flux_ratio_sq, 1.0, 1e-5);
    fx.in.slow_tick = true;
    t.flux_ratio_sq = 0.0f;
    assert_int_equal(ops->step(est, &fx.in, &t), MC_FAULT_ESTIMATE);
    assert_near(t.flux_ratio_sq, 1.0, 1e-5);
    ops->front(est)->ratio_max_sq = ratio_max_sq;
    ops->bounds(est)->omega_m_max_rad_s = 1e-30f;
    fx.in.i_beta_A = 1.0f; /* a torque: the speed estimate moves */
    fx.in.slow_tick = false;
    assert_int_equal(ops->step(est, &fx.in, &t), MC_FAULT_NONE);
    fx.in.slow_tick = true;
    t.theta_m_rad = NAN;
    assert_int_equal(ops->step(est, &fx.in, &t), MC_FAULT_ESTIMATE);
    assert_true(isfinite(t.theta_m_rad) && t.omega_m_rad_s != 0.0f);
}

static void test_flux_pll(void **state)
{
    (void)state;
    check_faults(&flux_pll_ops);
}

static void test_flux_ii(void **state)
{
    (void)state;
    check_faults(&flux_ii_ops);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flux_pll),
        cmocka_unit_test(test_flux_ii),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
