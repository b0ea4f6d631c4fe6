/*
 * Back-EMF monitor and its checks (mc/emf_monitor.h) against an exact
 * non-salient machine trajectory synthesised in double precision:
 *   theta_e(t) = theta0 + w t,  i(t) = I [cos(theta + phi); sin(theta + phi)],
 *   v(t) = R i + L di/dt + psi w [-sin theta; cos theta],
 * the monitor fed i(t_k) and the mean of v over [t_{k-1}, t_k], integrated
 * exactly: with x = w Ts / 2, theta_mid the angle at the middle of the
 * interval and s = sin(x)/x,
 *   mean R i   = R I s [cos(theta_mid + phi); sin(theta_mid + phi)],
 *   mean L i'  = L (i_k - i_{k-1}) / Ts,
 *   mean e     = psi w s [-sin theta_mid; cos theta_mid].
 * Motor: paper 001 (R 0.225 ohm, L 3.8 mH, psi 0.17 Wb), 20 kHz; thresholds:
 * the drive's defaults (firmware/app/config.c): 20 ms filter, 0.1 s check
 * time (n_required = 2000 samples), e_min 0.5 V, speed floor 3 rad/s
 * (electrical), angle_max 45 deg, ratio_low 0.5, ratio_high 2.
 */
#include "mc_test.h"

#include <float.h>
#include <math.h>
#include <string.h>

#include "mc/emf_monitor.h"
#include "paper001_motor.h"

#define TS       P001_TS_S
#define TAU_S    0.02
#define N_REQ    2000 /* check_time / Ts = 0.1 s * 20 kHz */
#define E_MIN_V  0.5
#define W_MIN    3.0
#define ANGLE_MX (MC_TEST_PI / 4.0)
#define R_LOW    0.5
#define R_HIGH   2.0
#define SETTLE   6000                /* 0.3 s = 15 filter time constants */
#define U_F32    (0.5 * FLT_EPSILON) /* unit roundoff of float, 2^-24 */

/* The monitor's nominal motor, also the synthetic machine (in double, the
 * same float values). */
#define M_R   ((double)(float)P001_R_OHM)
#define M_L   ((double)(float)P001_L_H)
#define M_PSI ((double)(float)P001_FLUX_WB)

static mc_emf_monitor_params_t motor_params(void)
{
    return (mc_emf_monitor_params_t){
        .R_ohm = (float)P001_R_OHM,
        .L_H = (float)P001_L_H,
        .psi_Wb = (float)P001_FLUX_WB,
        .Ts_s = (float)TS,
        .filter_s = (float)TAU_S,
        .decimation = 1u,
    };
}

static mc_emf_check_config_t default_thresholds(void)
{
    return (mc_emf_check_config_t){
        .filter_s = (float)TAU_S,
        .check_time_s = 0.1f,
        .min_V = (float)E_MIN_V,
        .min_speed_e_rad_s = (float)W_MIN,
        .angle_max_rad = 0.785398163f,
        .ratio_low = (float)R_LOW,
        .ratio_high = (float)R_HIGH,
    };
}

static void check_init(mc_emf_check_f32_t *chk)
{
    const mc_emf_check_config_t c = default_thresholds();
    const mc_emf_monitor_params_t p = motor_params();
    assert_int_equal(mc_emf_check_init_f32(chk, &c, &p), MC_OK);
}

/* ---- the synthetic machine ---------------------------------------------- */

typedef struct {
    double I, phi, theta0, w; /* current amplitude, angle, start, speed */
} traj_t;

typedef struct {
    float i[2], v[2]; /* what the monitor gets */
    double theta;     /* the rotor's electrical angle at t_k */
} sample_t;

static double sinc(double x)
{
    return (fabs(x) < 1e-8) ? 1.0 - x * x / 6.0 : sin(x) / x;
}

/* Sample k of a trajectory (the mean voltage over [t_{k-1}, t_k]). */
static sample_t machine(const traj_t *tr, long k)
{
    const double x = 0.5 * tr->w * TS;
    const double th = tr->theta0 + tr->w * TS * (double)k;
    const double th_mid = th - x;
    const double s = sinc(x);
    /* i_k - i_{k-1} = I [cos a - cos b; sin a - sin b], product form */
    const double di[2] = { -2.0 * tr->I * sin(th_mid + tr->phi) * sin(x),
                           2.0 * tr->I * cos(th_mid + tr->phi) * sin(x) };
    const double v[2] = {
        M_R * tr->I * s * cos(th_mid + tr->phi) + M_L * di[0] / TS -
            M_PSI * tr->w * s * sin(th_mid),
        M_R * tr->I * s * sin(th_mid + tr->phi) + M_L * di[1] / TS +
            M_PSI * tr->w * s * cos(th_mid),
    };
    return (sample_t){
        .i = { (float)(tr->I * cos(th + tr->phi)), (float)(tr->I * sin(th + tr->phi)) },
        .v = { (float)v[0], (float)v[1] },
        .theta = th,
    };
}

/* Stopped machine: theta and the current held at sample k_stop's values
 * (v = R i exactly: constant current, no back-EMF). */
static sample_t machine_stopped(const traj_t *tr, long k_stop)
{
    const double th = tr->theta0 + tr->w * TS * (double)k_stop;
    const double i[2] = { tr->I * cos(th + tr->phi), tr->I * sin(th + tr->phi) };
    return (sample_t){
        .i = { (float)i[0], (float)i[1] },
        .v = { (float)(M_R * i[0]), (float)(M_R * i[1]) },
        .theta = th,
    };
}

/* The estimate enters as the sine and cosine of its angle at t_k (what the
 * fast ISR has from its Park transform), rounded to float. */
static bool enc_step(mc_emf_check_f32_t *chk, const sample_t *s, double theta_est, double w_est)
{
    return mc_emf_check_encoder_f32(chk, s->i[0], s->i[1], s->v[0], s->v[1], (float)sin(theta_est),
                                    (float)cos(theta_est), (float)w_est);
}

static bool sl_step(mc_emf_check_f32_t *chk, const sample_t *s, double theta_est, double w_est)
{
    return mc_emf_check_sensorless_f32(chk, s->i[0], s->i[1], s->v[0], s->v[1],
                                       (float)sin(theta_est), (float)cos(theta_est), (float)w_est);
}

/* ---- the filtered vectors, read in double ------------------------------- */

typedef struct {
    double meas, pred, angle; /* |e_meas|, |e_pred|, angle between, rad */
    double diff;              /* |e_meas - e_pred| */
} vecs_t;

static vecs_t vecs(const mc_emf_monitor_f32_t *m)
{
    const double mx = m->e_meas_V[0], my = m->e_meas_V[1];
    const double px = m->e_pred_V[0], py = m->e_pred_V[1];
    return (vecs_t){
        .meas = hypot(mx, my),
        .pred = hypot(px, py),
        .angle = fabs(atan2(mx * py - my * px, mx * px + my * py)),
        .diff = hypot(mx - px, my - py),
    };
}

/* The documented conditions (mc/emf_monitor.h), evaluated independently in
 * double on the monitor's filtered vectors. */
static bool enc_condition(const vecs_t *v, double w_est)
{
    const bool slipped =
        fabs(w_est) > W_MIN && v->meas > E_MIN_V && v->pred > E_MIN_V && v->angle > ANGLE_MX;
    const bool frozen = v->meas * v->meas > R_HIGH * R_HIGH * v->pred * v->pred + E_MIN_V * E_MIN_V;
    return slipped || frozen;
}

static bool sl_condition(const vecs_t *v, double w_est)
{
    const bool slipped =
        fabs(w_est) > W_MIN && v->meas > E_MIN_V && v->pred > E_MIN_V && v->angle > ANGLE_MX;
    return slipped ||
           (fabs(w_est) > W_MIN && v->meas * v->meas < R_LOW * R_LOW * v->pred * v->pred);
}

/* ---- (a) agreement ------------------------------------------------------- */

/* Bound on |e_meas - e_pred| (filtered, V) for a trajectory. Per sample,
 * per component:
 *  T1 trapezoid vs exact mean of R i: R I (s - cos x) <= R I (w Ts)^2 / 12;
 *  T2 mean back-EMF vs its value at theta_mid: psi |w| (1 - s)
 *     <= psi |w| (w Ts)^2 / 24;
 *  T3 theta_mid by the first-order rotation (s - d c, c + d s), d = w Ts/2:
 *     off by |(1 - cos d, d - sin d)| <= d^2 / 2: psi |w| (w Ts)^2 / 8;
 *  Q1 the float currents: half an ulp each, differentiated: 2 u I L / Ts;
 *  Q2 the float voltage: u v_max (v_max = R I + L I |w| + psi |w|);
 *  Q3 the monitor's arithmetic: 4 roundings of terms <= 2 v_max: 8 u v_max;
 *  P1 e_pred: sin, cos in float (u each), the rotation's products and sums
 *     (4 u), psi omega in float (2 u): psi |w| 8 u.
 * The low-pass is a convex combination (weights a (1-a)^j, sum < 1), so
 * the filtered difference is within the per-sample bound; each filter's
 * own rounding (u |y| per update plus 2 u a |x - y|) accumulates to at most
 * (u E + 4 u a E) / a with E >= |y| (a = T / (T + tau), T the period of
 * the steps: Ts, or N Ts decimated): twice that, for the two filters. Vector norm: sqrt(2) times
 * the component bound. */
static double agreement_tol_V(const traj_t *tr, double T_step)
{
    const double w = fabs(tr->w), wt = w * TS;
    const double a = T_step / (T_step + TAU_S);
    const double v_max = M_R * tr->I + M_L * tr->I * w + M_PSI * w;
    const double e_max = M_PSI * w + M_R * tr->I * wt * wt + 2.0 * U_F32 * tr->I * M_L / TS;
    const double per_sample = M_R * tr->I * wt * wt / 12.0 + M_PSI * w * wt * wt / 24.0 +
                              M_PSI * w * wt * wt / 8.0 + 2.0 * U_F32 * tr->I * M_L / TS +
                              9.0 * U_F32 * v_max + M_PSI * w * 8.0 * U_F32;
    const double filt = 2.0 * (U_F32 * e_max + 4.0 * U_F32 * a * e_max) / a;
    return sqrt(2.0) * (per_sample + filt);
}

/* (a) The encoder's angle and speed are the machine's: e_meas and e_pred
 * agree within the derived bound at every sample, the filtered e_pred
 * reaches the low-pass of psi w, and neither check fires. Motoring,
 * field weakening, reverse, just above the speed floor, standstill. */
static void test_exact_trajectory_agrees(void **state)
{
    (void)state;
    const traj_t cases[] = {
        { 5.0, 0.5 * MC_TEST_PI, 0.3, 120.0 },    /* 40 rad/s mech, i_q */
        { 10.0, 0.65 * MC_TEST_PI, -2.0, 144.0 }, /* overspeed, with i_d < 0 */
        { 8.0, -0.5 * MC_TEST_PI, 1.0, -60.0 },   /* reverse */
        { 10.0, 0.5 * MC_TEST_PI, 0.0, 4.0 },     /* just above the floor */
        { 10.0, 1.0, 0.5, 0.0 },                  /* standstill, DC current */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        const traj_t *tr = &cases[c];
        mc_emf_check_f32_t enc, sl;
        check_init(&enc);
        check_init(&sl);
        const double tol = agreement_tol_V(tr, TS);
        double worst = 0.0, worst_angle = 0.0;
        for (long k = 0; k < 3 * SETTLE; ++k) {
            const sample_t s = machine(tr, k);
            if (enc_step(&enc, &s, s.theta, tr->w) || sl_step(&sl, &s, s.theta, tr->w)) {
                fail_msg("case %zu: a check fired at sample %ld", c, k);
            }
            const vecs_t v = vecs(&enc.mon);
            worst = fmax(worst, v.diff);
            assert_near(v.diff, 0.0, tol);
            assert_near(v.meas, v.pred, tol);
            if (v.pred > 10.0 * tol) {
                worst_angle = fmax(worst_angle, v.angle);
                assert_near(v.angle, 0.0, tol / (v.pred - tol));
            }
        }
        /* e_pred settled at the low-pass of psi w: |H| = 1 / |1 + j w tau|.
         * The backward-Euler filter (a = Ts / (Ts + tau), so (1 - a)/a =
         * tau/Ts) has 1/H = 1 + (tau/Ts)(1 - cos wTs) + j (tau/Ts) sin wTs:
         * real part larger by dr <= w tau (w Ts)/2, imaginary part smaller
         * by di <= w tau (w Ts)^2 / 6, so |H| is lower by at most (dr +
         * dr^2/2 + w tau di) / (1 + (w tau)^2); the first-order rotation
         * makes the input longer by d^2/2 (d = w Ts / 2); the start-up
         * transient exp(-15); float 1e-6. The sum is the tolerance. */
        const double wt = tr->w * TAU_S, th = fabs(tr->w) * TS;
        const double expected = M_PSI * fabs(tr->w) / sqrt(1.0 + wt * wt);
        const double dr = fabs(wt) * th / 2.0, di = fabs(wt) * th * th / 6.0;
        const double rel = (dr + dr * dr / 2.0 + fabs(wt) * di) / (1.0 + wt * wt) + th * th / 8.0 +
                           exp(-15.0) + 1e-6;
        const vecs_t v = vecs(&enc.mon);
        print_message("case %zu: |e_meas - e_pred| <= %.3g V (tol %.3g), angle <= %.3g rad, "
                      "|e_pred| = %.5f V (expected %.5f +- %.2g)\n",
                      c, worst, tol, worst_angle, v.pred, expected, rel * expected);
        assert_near(v.pred, expected, rel * expected);
    }
}

/* ---- onset times of the continuous model -------------------------------- */

/* The filtered vectors after an event at s = 0, in the frame of the settled
 * e_meas (magnitude M = psi |w| / |1 + j w tau|): z = e_pred / e_meas and
 * m = |e_meas| / M as functions of s. First s (fine grid, Ts/64) at which
 * the condition holds, checked to hold from there to s_end (the premise of
 * a single run of consecutive samples). */
typedef enum { EV_SLIP, EV_FREEZE, EV_STOP } event_t;

static double onset_time(event_t ev, double w, double delta, double s_end, bool sensorless)
{
    const double M = M_PSI * fabs(w) / sqrt(1.0 + w * TAU_S * w * TAU_S);
    double onset = NAN;
    for (double s = 0.0; s <= s_end; s += TS / 64.0) {
        const double d = exp(-s / TAU_S);
        double zr, zi, meas = M, pred;
        double w_est = w;
        if (ev == EV_SLIP) { /* z = e^{j D} + (1 - e^{j D}) d e^{-j w s} */
            zr = cos(delta) + d * ((1.0 - cos(delta)) * cos(w * s) - sin(delta) * sin(w * s));
            zi = sin(delta) + d * (-(1.0 - cos(delta)) * sin(w * s) - sin(delta) * cos(w * s));
            pred = M * hypot(zr, zi);
        } else if (ev == EV_FREEZE) { /* e_pred decays, input 0 */
            zr = d * cos(w * s);
            zi = -d * sin(w * s);
            pred = M * d;
            w_est = 0.0;
        } else { /* EV_STOP: e_meas decays in its last direction, e_pred
                    keeps turning with the estimate: z = e^{j w s} / d */
            zr = cos(w * s);
            zi = sin(w * s);
            meas = M * d;
            pred = M;
        }
        const vecs_t v = { .meas = meas, .pred = pred, .angle = fabs(atan2(zi, zr)) };
        const bool cond = sensorless ? sl_condition(&v, w_est) : enc_condition(&v, w_est);
        if (cond && isnan(onset)) {
            onset = s;
        }
        if (!cond && !isnan(onset)) {
            fail_msg("premise: the condition drops again at s = %g", s);
        }
    }
    return onset;
}

/* Window of the first counted sample m (0-based, counted from the first
 * sample of the event) for a continuous onset time t_c: the event's first
 * sample already enters the filter, so sample m holds m + 1 updates:
 * m_c = ceil(t_c / Ts) - 1. The backward-Euler pole tau / (tau + Ts)
 * decays slower than exp(-Ts / tau) by Ts^2 / (2 tau^2) per update: at
 * most t_c / (2 tau) < 0.5 sample of delay here; the grid: one sample.
 * Window [m_c - 1, m_c + 1]. */
static void assert_onset_window(long m_onset, double t_c)
{
    const long m_c = (long)ceil(t_c / TS) - 1;
    print_message("  onset at sample %ld after the event, analytic %.2f (window [%ld, %ld])\n",
                  m_onset, t_c / TS - 1.0, m_c - 1, m_c + 1);
    assert_true(t_c < TAU_S);
    assert_true(m_onset >= m_c - 1 && m_onset <= m_c + 1);
}

/* Run the encoder (or sensorless) check from the settled state through an
 * event at sample SETTLE; returns the first sample (after the event) at
 * which it fired, or -1; checks "exactly n_required": the independent
 * condition held on the N_REQ samples up to the firing one, and not on the
 * one before. */
typedef struct {
    long fire, onset;
} fire_t;

static fire_t run_check(const traj_t *tr, event_t ev, double delta, long n_after, bool sensorless)
{
    mc_emf_check_f32_t chk;
    check_init(&chk);
    long run_start = -1;
    for (long k = 0; k < SETTLE + n_after; ++k) {
        const sample_t s = machine(tr, k);
        double th_est = s.theta, w_est = tr->w;
        if (k >= SETTLE && ev == EV_SLIP) {
            th_est += delta;
        } else if (k >= SETTLE && ev == EV_FREEZE) {
            th_est = machine(tr, SETTLE - 1).theta;
            w_est = 0.0;
        }
        const bool fired =
            sensorless ? sl_step(&chk, &s, th_est, w_est) : enc_step(&chk, &s, th_est, w_est);
        const vecs_t v = vecs(&chk.mon);
        const bool cond = sensorless ? sl_condition(&v, w_est) : enc_condition(&v, w_est);
        if (k < SETTLE) {
            assert_false(fired);
            assert_false(cond);
        }
        if (!cond) {
            run_start = -1;
        } else if (run_start < 0) {
            run_start = k;
        }
        if (fired) {
            /* exactly N_REQ consecutive samples of the condition */
            assert_true(run_start >= 0);
            assert_int_equal(k - run_start + 1, N_REQ);
            return (fire_t){ .fire = k - SETTLE, .onset = run_start - SETTLE };
        }
    }
    return (fire_t){ .fire = -1, .onset = run_start < 0 ? -1 : run_start - SETTLE };
}

/* An estimate offset by 90 or 180 deg electrical appearing on the settled
 * monitor fires the check exactly N_REQ samples after the condition starts
 * to hold, the start within the window derived from the filter time
 * constant; 30 deg (below angle_max = 45 deg: the angle stays below it,
 * transient peak 34 deg at -60 rad/s, the magnitudes equal) never fires in
 * 0.5 s. */
static void assert_slip_cases(bool sensorless)
{
    const double speeds[] = { 20.0, -60.0 };
    const double offsets_deg[] = { 90.0, 180.0 };
    for (size_t i = 0; i < 2; ++i) {
        const traj_t tr = { 5.0, 0.5 * MC_TEST_PI, 0.7, speeds[i] };
        for (size_t j = 0; j < 2; ++j) {
            const double delta = offsets_deg[j] * MC_TEST_PI / 180.0;
            print_message("%s, w = %g rad/s, offset %g deg:\n",
                          sensorless ? "sensorless" : "encoder", speeds[i], offsets_deg[j]);
            const double t_c = onset_time(EV_SLIP, speeds[i], delta, 0.5, sensorless);
            const fire_t f = run_check(&tr, EV_SLIP, delta, 2 * N_REQ, sensorless);
            assert_true(f.fire >= 0);
            assert_onset_window(f.onset, t_c);
            assert_int_equal(f.fire, f.onset + N_REQ - 1);
        }
        const double d30 = MC_TEST_PI / 6.0;
        assert_true(isnan(onset_time(EV_SLIP, speeds[i], d30, 0.5, sensorless)));
        const fire_t f = run_check(&tr, EV_SLIP, d30, 10000, sensorless);
        assert_int_equal(f.fire, -1);
        assert_int_equal(f.onset, -1);
    }
}

/* (b) An encoder slip (assert_slip_cases). At 20 rad/s the 90 deg case
 * trips on the angle, at -60 rad/s first on the magnitude ratio (the
 * rotating transient of e_pred shrinks it). */
static void test_encoder_slip_fires(void **state)
{
    (void)state;
    assert_slip_cases(false);
}

/* (c) A frozen encoder (angle held, speed 0) while the machine turns: e_pred
 * decays, e_meas does not, the ratio_high branch (the slip branch needs
 * |omega| above the floor) fires after exactly N_REQ samples, the start
 * where |e_meas|^2 > 4 |e_pred|^2 + e_min^2 in the continuous model. */
static void test_encoder_freeze_fires(void **state)
{
    (void)state;
    const double speeds[] = { 60.0, -120.0 };
    for (size_t i = 0; i < 2; ++i) {
        const traj_t tr = { 5.0, 0.5 * MC_TEST_PI, -1.2, speeds[i] };
        print_message("frozen encoder, w = %g rad/s:\n", speeds[i]);
        const double t_c = onset_time(EV_FREEZE, speeds[i], 0.0, 0.5, false);
        const fire_t f = run_check(&tr, EV_FREEZE, 0.0, 2 * N_REQ, false);
        assert_true(f.fire >= 0);
        assert_onset_window(f.onset, t_c);
        assert_int_equal(f.fire, f.onset + N_REQ - 1);
    }
}

/* (d) Sensorless check, machine at standstill (constant current 4 A, v = R
 * i: e = 0) while the estimate claims w: from the first sample with history
 * (sample 1) e_pred is a psi |w| > 0 and e_meas is the float residual of
 * v - R i (< 1e-6 V), so the condition holds from sample 1 and the check
 * fires at sample N_REQ exactly. Below the speed floor (and at it: "above"
 * is strict) it never fires. */
static void test_sensorless_standstill(void **state)
{
    (void)state;
    const traj_t still = { 4.0, 0.4, 0.0, 0.0 };
    const double w_claims[] = { 60.0, -60.0, 2000.0 };
    for (size_t i = 0; i < sizeof w_claims / sizeof w_claims[0]; ++i) {
        mc_emf_check_f32_t chk;
        check_init(&chk);
        long fired_at = -1;
        for (long k = 0; k <= N_REQ + 10 && fired_at < 0; ++k) {
            const sample_t s = machine(&still, k);
            if (sl_step(&chk, &s, 1.0 + w_claims[i] * TS * (double)k, w_claims[i])) {
                fired_at = k;
            }
        }
        assert_int_equal(fired_at, N_REQ);
    }
    const double w_low[] = { 0.99 * W_MIN, -0.99 * W_MIN, W_MIN, -W_MIN };
    for (size_t i = 0; i < sizeof w_low / sizeof w_low[0]; ++i) {
        mc_emf_check_f32_t chk;
        check_init(&chk);
        for (long k = 0; k < 5 * N_REQ; ++k) {
            const sample_t s = machine(&still, k);
            assert_false(sl_step(&chk, &s, w_low[i] * TS * (double)k, w_low[i]));
        }
    }
}

/* (d) The machine stops while a locked sensorless estimate keeps turning:
 * e_meas decays as exp(-t/tau) in its last direction, e_pred keeps its
 * magnitude and turns on: the condition starts at t_c = min(tau
 * ln(1/ratio_low), angle_max / |w|) (the ratio or the angle, whichever
 * comes first; window as above) and the check fires exactly N_REQ samples
 * later. */
static void test_sensorless_loss_of_lock(void **state)
{
    (void)state;
    const double speeds[] = { 60.0, -30.0 };
    for (size_t i = 0; i < 2; ++i) {
        const traj_t tr = { 3.0, 0.5 * MC_TEST_PI, 2.0, speeds[i] };
        mc_emf_check_f32_t chk;
        check_init(&chk);
        long run_start = -1, fired_at = -1;
        for (long k = 0; k < SETTLE + 2 * N_REQ && fired_at < 0; ++k) {
            const sample_t s = (k < SETTLE) ? machine(&tr, k) : machine_stopped(&tr, SETTLE - 1);
            const double th_est = machine(&tr, k).theta; /* keeps turning */
            const bool fired = sl_step(&chk, &s, th_est, tr.w);
            const vecs_t v = vecs(&chk.mon);
            const bool cond = sl_condition(&v, tr.w);
            if (k < SETTLE) {
                assert_false(fired || cond);
            }
            if (!cond) {
                run_start = -1;
            } else if (run_start < 0) {
                run_start = k;
            }
            if (fired) {
                fired_at = k;
            }
        }
        print_message("machine stops, estimate at %g rad/s:\n", speeds[i]);
        const double t_c = onset_time(EV_STOP, speeds[i], 0.0, 0.5, true);
        assert_near(t_c, fmin(TAU_S * log(1.0 / R_LOW), ANGLE_MX / fabs(speeds[i])), TS / 64.0);
        assert_true(fired_at >= 0);
        assert_onset_window(run_start - SETTLE, t_c);
        assert_int_equal(fired_at - run_start + 1, N_REQ);
    }
}

/* (d) A sensorless estimate that turns 90 or 180 deg away from the
 * machine's angle (an observer out of lock at speed) fires the sensorless
 * check on its angle branch (assert_slip_cases). An estimate that stops
 * while the machine turns (the encoder's frozen case) is below the speed
 * floor: the sensorless check never fires on it (near standstill a
 * sensorless estimate has nothing to follow). */
static void test_sensorless_angle(void **state)
{
    (void)state;
    assert_slip_cases(true);
    const double speeds[] = { 20.0, -60.0 };
    for (size_t i = 0; i < 2; ++i) {
        const traj_t tr = { 5.0, 0.5 * MC_TEST_PI, 0.7, speeds[i] };
        const fire_t f = run_check(&tr, EV_FREEZE, 0.0, 10000, true);
        assert_int_equal(f.fire, -1);
        assert_int_equal(f.onset, -1);
    }
}

/* (e) Reset clears the history (the first sample after it is not
 * differenced against the last one before) and the filters and the
 * persistence: the standstill case of (d) one sample before it would fire,
 * reset, then a current step that stale history would turn into an L di/dt
 * spike: the vectors stay exactly zero on that sample, and the check fires
 * N_REQ samples after the reset, not on the next one. */
static void test_reset_clears_history_and_persistence(void **state)
{
    (void)state;
    const traj_t still = { 4.0, 0.4, 0.0, 0.0 };
    const traj_t still2 = { 9.0, -2.0, 0.0, 0.0 };
    const double w = 60.0;
    mc_emf_check_f32_t chk;
    check_init(&chk);
    long k = 0;
    for (; k < N_REQ; ++k) {
        const sample_t s = machine(&still, k);
        assert_false(sl_step(&chk, &s, w * TS * (double)k, w));
    }
    /* without a reset, the next sample fires (the control experiment) */
    mc_emf_check_f32_t copy = chk;
    const sample_t s_next = machine(&still, k);
    assert_true(sl_step(&copy, &s_next, w * TS * (double)k, w));

    mc_emf_check_reset_f32(&chk);
    for (long j = 0; j <= N_REQ + 5; ++j, ++k) {
        const sample_t s = machine(&still2, k);
        const bool fired = sl_step(&chk, &s, w * TS * (double)k, w);
        if (j == 0) {
            assert_true(mc_emf_monitor_meas_sq_f32(&chk.mon) == 0.0f);
            assert_true(mc_emf_monitor_pred_sq_f32(&chk.mon) == 0.0f);
        }
        assert_int_equal(fired, j >= N_REQ);
    }

    /* The bare monitor: reset zeroes the vectors and the next sample only
     * records the history. */
    mc_emf_monitor_f32_t m;
    const mc_emf_monitor_params_t p = motor_params();
    assert_int_equal(mc_emf_monitor_init_f32(&m, &p), MC_OK);
    const traj_t tr = { 5.0, 1.0, 0.0, 100.0 };
    for (long j = 0; j < 100; ++j) {
        const sample_t s = machine(&tr, j);
        mc_emf_monitor_step_f32(&m, s.i[0], s.i[1], s.v[0], s.v[1], (float)sin(s.theta),
                                (float)cos(s.theta), 100.0f);
    }
    assert_true(mc_emf_monitor_meas_sq_f32(&m) > 1.0f);
    mc_emf_monitor_reset_f32(&m);
    assert_true(mc_emf_monitor_meas_sq_f32(&m) == 0.0f && mc_emf_monitor_pred_sq_f32(&m) == 0.0f);
    mc_emf_monitor_step_f32(&m, -7.0f, 3.0f, 1.0f, 2.0f, 0.6f, 0.8f, 100.0f);
    assert_true(mc_emf_monitor_meas_sq_f32(&m) == 0.0f && mc_emf_monitor_pred_sq_f32(&m) == 0.0f);
    /* the next one is differenced against (-7, 3): e_meas = v - R i_mean -
     * L di / Ts with di = 0 here, times the filter gain a (values < 0.01 V,
     * a handful of float roundings: < 1e-8 V) */
    mc_emf_monitor_step_f32(&m, -7.0f, 3.0f, 1.0f, 2.0f, 0.6f, 0.8f, 0.0f);
    const double a = TS / (TS + TAU_S);
    assert_near(m.e_meas_V[0], a * (1.0 - M_R * -7.0), 1e-8);
    assert_near(m.e_meas_V[1], a * (2.0 - M_R * 3.0), 1e-8);
}

/* ---- (g) decimated, as the application runs it --------------------------- */

#define DEC_N 10 /* the slow tick: 2 kHz at 20 kHz */

/* A step on every DEC_N-th sample (k % DEC_N == 0), this sample's
 * currents remembered on every sample. */
static bool dec_step(mc_emf_check_f32_t *chk, const sample_t *s, double theta_est, double w_est,
                     long k)
{
    const bool fired = (k % DEC_N == 0) && enc_step(chk, s, theta_est, w_est);
    mc_emf_monitor_remember_f32(&chk->mon, s->i[0], s->i[1]);
    return fired;
}

/* (g) Decimated by DEC_N (steps at T = DEC_N Ts, each over the one
 * interval before it): on the exact trajectory e_meas and e_pred agree
 * within the per-interval bound (the filter's term at T), |e_pred| settles
 * at the backward-Euler low-pass at T of a vector turning w T per step,
 * |H| = 1 / |1 + q (1 - cos wT) + j q sin wT|, q = tau / T; a 90 deg slip
 * fires after exactly N_REQ / DEC_N consecutive steps of the condition,
 * its onset within the continuous model's window counted in steps. */
static void test_decimated(void **state)
{
    (void)state;
    mc_emf_monitor_params_t p = motor_params();
    p.decimation = DEC_N;
    const mc_emf_check_config_t c = default_thresholds();
    const double T = DEC_N * TS;
    const long n_req = N_REQ / DEC_N;
    const traj_t tr = { 5.0, 0.5 * MC_TEST_PI, 0.7, 20.0 };
    mc_emf_check_f32_t chk;
    assert_int_equal(mc_emf_check_init_f32(&chk, &c, &p), MC_OK);
    assert_int_equal(chk.n_required, (uint32_t)n_req);
    const double tol = agreement_tol_V(&tr, T);
    for (long k = 0; k < 3 * SETTLE; ++k) {
        const sample_t s = machine(&tr, k);
        assert_false(dec_step(&chk, &s, s.theta, tr.w, k));
        assert_near(vecs(&chk.mon).diff, 0.0, tol);
    }
    const double wT = tr.w * T, q = TAU_S / T, th = fabs(tr.w) * TS;
    const double expected = M_PSI * fabs(tr.w) / hypot(1.0 + q * (1.0 - cos(wT)), q * sin(wT));
    print_message("decimated: |e_pred| = %.6f V (expected %.6f)\n", vecs(&chk.mon).pred, expected);
    assert_near(vecs(&chk.mon).pred, expected, (th * th / 8.0 + 1e-5) * expected);

    /* the slip, from a settled monitor at sample SETTLE (a step) */
    const double delta = 0.5 * MC_TEST_PI;
    const double t_c = onset_time(EV_SLIP, tr.w, delta, 0.5, false);
    assert_int_equal(mc_emf_check_init_f32(&chk, &c, &p), MC_OK);
    long run_start = -1, fire = -1;
    for (long k = 0; k < SETTLE + 2 * N_REQ && fire < 0; ++k) {
        const sample_t s = machine(&tr, k);
        const double th_est = s.theta + (k >= SETTLE ? delta : 0.0);
        const bool fired = dec_step(&chk, &s, th_est, tr.w, k);
        if (k % DEC_N != 0) {
            continue;
        }
        const vecs_t v = vecs(&chk.mon);
        const bool cond = enc_condition(&v, tr.w);
        assert_true(k >= SETTLE || (!cond && !fired));
        run_start = !cond ? -1 : (run_start < 0 ? (k - SETTLE) / DEC_N : run_start);
        if (fired) {
            fire = (k - SETTLE) / DEC_N;
        }
    }
    const long m_c = (long)ceil(t_c / T) - 1;
    print_message("decimated slip: onset at step %ld (window [%ld, %ld]), fired at step %ld\n",
                  run_start, m_c - 1, m_c + 1, fire);
    assert_true(run_start >= m_c - 1 && run_start <= m_c + 1);
    assert_int_equal(fire, run_start + n_req - 1);
}

/* (f) Init: the monitor's parameters (finite; R >= 0, L > 0, psi > 0,
 * Ts > 0, decimation N in [1, 1000], filter >= N Ts; *m untouched on
 * error) and the thresholds (finite;
 * filter in [Ts, 1], check time > 0 and at least one sample and at most
 * 1e6, e_min > 0, speed floor > 0, angle_max in (0, pi/2], ratio_low in
 * (0, 1), ratio_high > 1). */
static void test_init_rejects(void **state)
{
    (void)state;
    const mc_emf_monitor_params_t p0 = motor_params();
    const struct {
        size_t off;
        float value;
        mc_status_t expected;
    } mp[] = {
#define MP(f) offsetof(mc_emf_monitor_params_t, f)
        { MP(R_ohm), NAN, MC_ERR_NONFINITE },
        { MP(L_H), INFINITY, MC_ERR_NONFINITE },
        { MP(psi_Wb), NAN, MC_ERR_NONFINITE },
        { MP(Ts_s), -INFINITY, MC_ERR_NONFINITE },
        { MP(filter_s), NAN, MC_ERR_NONFINITE },
        { MP(R_ohm), -0.01f, MC_ERR_PARAM },
        { MP(L_H), 0.0f, MC_ERR_PARAM },
        { MP(psi_Wb), 0.0f, MC_ERR_PARAM },
        { MP(psi_Wb), -0.17f, MC_ERR_PARAM },
        { MP(Ts_s), 0.0f, MC_ERR_PARAM },
        { MP(filter_s), 4.9e-5f, MC_ERR_PARAM }, /* < Ts */
        { MP(filter_s), (float)TS, MC_OK },      /* = Ts */
        { MP(R_ohm), 0.0f, MC_OK },
#undef MP
    };
    for (size_t i = 0; i < sizeof mp / sizeof mp[0]; ++i) {
        mc_emf_monitor_params_t p = p0;
        memcpy((unsigned char *)&p + mp[i].off, &mp[i].value, sizeof(float));
        mc_emf_monitor_f32_t m, pattern;
        memset(&m, 0x5a, sizeof m);
        memset(&pattern, 0x5a, sizeof pattern);
        const mc_status_t got = mc_emf_monitor_init_f32(&m, &p);
        if (got != mp[i].expected) {
            fail_msg("monitor case %zu: got %d, expected %d", i, (int)got, (int)mp[i].expected);
        }
        if (got != MC_OK) {
            assert_memory_equal(&m, &pattern, sizeof m);
        }
    }
    /* decimation N in [1, 1000], the filter at least N Ts */
    const struct {
        uint32_t n;
        float filter_s;
        mc_status_t expected;
    } dc[] = {
        { 0u, (float)TAU_S, MC_ERR_PARAM },
        { 1000u, 0.05f, MC_OK },
        { 1001u, 1.0f, MC_ERR_PARAM },
        { 10u, (float)(10.0 * TS), MC_OK },
        { 10u, (float)(9.9 * TS), MC_ERR_PARAM },
    };
    for (size_t i = 0; i < sizeof dc / sizeof dc[0]; ++i) {
        mc_emf_monitor_params_t p = p0;
        p.decimation = dc[i].n;
        p.filter_s = dc[i].filter_s;
        mc_emf_monitor_f32_t m;
        assert_int_equal(mc_emf_monitor_init_f32(&m, &p), dc[i].expected);
    }
    /* decimated, the check time counts steps: at least one */
    {
        mc_emf_monitor_params_t p = p0;
        p.decimation = 10u;
        mc_emf_check_config_t c = default_thresholds();
        mc_emf_check_f32_t chk;
        c.check_time_s = (float)(9.0 * TS);
        assert_int_equal(mc_emf_check_init_f32(&chk, &c, &p), MC_ERR_PARAM);
        c.check_time_s = (float)(10.0 * TS);
        assert_int_equal(mc_emf_check_init_f32(&chk, &c, &p), MC_OK);
        assert_int_equal(chk.n_required, 1u);
    }

    const mc_emf_check_config_t c0 = default_thresholds();
    const struct {
        size_t off;
        float value;
        mc_status_t expected;
    } cc[] = {
#define CC(f) offsetof(mc_emf_check_config_t, f)
        { CC(filter_s), NAN, MC_ERR_NONFINITE },
        { CC(check_time_s), INFINITY, MC_ERR_NONFINITE },
        { CC(min_V), NAN, MC_ERR_NONFINITE },
        { CC(min_speed_e_rad_s), NAN, MC_ERR_NONFINITE },
        { CC(angle_max_rad), NAN, MC_ERR_NONFINITE },
        { CC(ratio_low), -INFINITY, MC_ERR_NONFINITE },
        { CC(ratio_high), INFINITY, MC_ERR_NONFINITE },
        { CC(filter_s), 1.01f, MC_ERR_PARAM },
        { CC(filter_s), 1.0f, MC_OK },
        { CC(filter_s), 4.9e-5f, MC_ERR_PARAM }, /* < Ts */
        { CC(filter_s), (float)TS, MC_OK },
        { CC(check_time_s), 0.0f, MC_ERR_PARAM },
        { CC(check_time_s), -0.1f, MC_ERR_PARAM },
        { CC(check_time_s), 2.4e-5f, MC_ERR_PARAM }, /* half a sample */
        { CC(check_time_s), (float)TS, MC_OK },      /* one sample */
        { CC(check_time_s), 51.0f, MC_ERR_PARAM },   /* 1.02e6 samples */
        { CC(check_time_s), 49.0f, MC_OK },          /* 0.98e6 samples */
        { CC(min_V), 0.0f, MC_ERR_PARAM },
        { CC(min_V), -0.5f, MC_ERR_PARAM },
        { CC(min_speed_e_rad_s), 0.0f, MC_ERR_PARAM },
        { CC(angle_max_rad), 0.0f, MC_ERR_PARAM },
        { CC(angle_max_rad), -0.5f, MC_ERR_PARAM },
        { CC(angle_max_rad), 1.5709f, MC_ERR_PARAM }, /* > pi/2 */
        { CC(angle_max_rad), 1.5707f, MC_OK },
        { CC(ratio_low), 0.0f, MC_ERR_PARAM },
        { CC(ratio_low), 1.0f, MC_ERR_PARAM },
        { CC(ratio_low), 0.999f, MC_OK },
        { CC(ratio_high), 1.0f, MC_ERR_PARAM },
        { CC(ratio_high), 0.5f, MC_ERR_PARAM },
        { CC(ratio_high), 1.001f, MC_OK },
#undef CC
    };
    for (size_t i = 0; i < sizeof cc / sizeof cc[0]; ++i) {
        mc_emf_check_config_t c = c0;
        memcpy((unsigned char *)&c + cc[i].off, &cc[i].value, sizeof(float));
        mc_emf_check_f32_t chk;
        const mc_status_t got = mc_emf_check_init_f32(&chk, &c, &p0);
        if (got != cc[i].expected) {
            fail_msg("check case %zu: got %d, expected %d", i, (int)got, (int)cc[i].expected);
        }
    }
    /* The motor / timing of p reach the monitor's validation (p's own
     * filter_s is replaced by the threshold block's). */
    mc_emf_check_f32_t chk;
    mc_emf_monitor_params_t p = p0;
    p.psi_Wb = 0.0f;
    assert_int_equal(mc_emf_check_init_f32(&chk, &c0, &p), MC_ERR_PARAM);
    p = p0;
    p.L_H = NAN;
    assert_int_equal(mc_emf_check_init_f32(&chk, &c0, &p), MC_ERR_NONFINITE);
    p = p0;
    p.filter_s = 0.0f;
    assert_int_equal(mc_emf_check_init_f32(&chk, &c0, &p), MC_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_trajectory_agrees),
        cmocka_unit_test(test_decimated),
        cmocka_unit_test(test_encoder_slip_fires),
        cmocka_unit_test(test_encoder_freeze_fires),
        cmocka_unit_test(test_sensorless_standstill),
        cmocka_unit_test(test_sensorless_loss_of_lock),
        cmocka_unit_test(test_sensorless_angle),
        cmocka_unit_test(test_reset_clears_history_and_persistence),
        cmocka_unit_test(test_init_rejects),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
