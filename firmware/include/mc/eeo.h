/*
 * Position regulator of paper 000: internal model (7), saturated control
 * (12) and enhanced extended observer (13), fed by the rotor angle only.
 * float32 per-period step; gain design at init (double).
 *
 * Plant in the paper's normal form (6) (MECHANICAL angle theta):
 *   xi1 = n_p (theta - theta*), xi2 = omega, xi3 = j omega' (N m),
 *   xi1' = g2 xi2, xi2' = g3 xi3, xi3' = q(.) + b v_q,
 *   g2 = n_p, g3 = 1/j, b = lambda_m n_p / L,
 * v_d = 0 and v = Park^-1(xi1) (0, v_q) (5)-(6): the caller rotates v_q
 * with the electrical angle n_p theta (the angle itself, not the error).
 *
 * Internal model (7): eta' = F eta + G v_q, v_q = Gamma eta + u_bar, F in
 * companion form with characteristic polynomial f(s) (Hurwitz), G = e_n,
 * Gamma = f - s_coef so that F + G Gamma is the companion matrix of the
 * exosystem's polynomial s(s) (same eigenvalues as S of (1)). Paper:
 * f = (s+1)^3, s(s) = s (s^2 + 1) (bias + sinusoid at 1 rad/s), which
 * gives the printed Gamma = (1 2 3). Discretised exactly (ZOH of u_bar):
 *   eta_{k+1} = eta_k + D eta_k + E u_bar_k,
 *   D = exp((F + G Gamma) Ts) - I,  E = int_0^Ts exp((F + G Gamma) t) G dt,
 * so the discrete internal model keeps exactly the eigenvalues exp(s_i Ts)
 * (D is stored instead of exp(.) to keep float32 resolution near 1).
 *
 * Saturated control (12): u_bar = sat_N((-sigma_hat + K xi_hat) / b_bar).
 *
 * Observer (13), in the chain form y = xi1, x = (xi1, xi2, xi3, sigma):
 *   x' = A x + e3 b_bar u_bar + l (y - x1),
 *   A = [0 g2 0 0; 0 0 g3 0; 0 0 0 1; 0 0 0 0],
 *   l = (kappa a3, kappa^2 a2, kappa^3 a1, kappa^4 a0).
 * The error polynomial is s^4 + l1 s^3 + g2 l2 s^2 + g2 g3 l3 s
 * + g2 g3 l4. Paper gains (kappa = 1e3, a = (33.61, 33.61, 135483,
 * 48604)): l1 = 4.86e7 1/s, the fastest eigenvalue is about -4.86e7 rad/s.
 * Forward Euler needs Ts < 2 / 4.86e7 = 41 ns; (reported elsewhere, not
 * re-tested here) exact discretisation with y
 * held over the step is unstable from about 2 us. Hence:
 *
 * Backward-Euler discretisation (derivation). With h = Ts, y_k the
 * measurement at t_k and u_p the input applied over (t_{k-1}, t_k]:
 *   x_k = x_{k-1} + h (A x_k + e3 u_p + l (y_k - C x_k)),   C = e1^T
 *   <=> (I - h A + h l C) x_k = x_{k-1} + h e3 u_p + h l y_k.
 * Let M = I - h A (upper bidiagonal, unit diagonal, so M^-1 is exact by
 * back substitution) and p = M^-1 (x_{k-1} + h e3 u_p), the prediction of
 * the chain with the previous input:
 *   p4 = sigma_{k-1},  p3 = xi3_{k-1} + h (u_p + p4),
 *   p2 = xi2_{k-1} + h g3 p3,  p1 = xi1_{k-1} + h g2 p2.
 * Then M x_k + h l C x_k = M p + h l y_k, i.e. x_k = p + w (y_k - C x_k)
 * with w = h M^-1 l:
 *   w4 = h l4,  w3 = h l3 + h w4,  w2 = h l2 + h g3 w3,  w1 = h l1 + h g2 w2.
 * Taking C of both sides, y_k - C x_k = (y_k - p1) / (1 + w1), so
 *   x_k = p + m (y_k - p1),   m = w / (1 + w1)        (correct)
 * every state is corrected by its own gain times the single innovation
 * y_k - p1. All w_i > 0, so 1 + w1 > 1 and m1 in (0, 1). The discrete
 * error dynamics are e_k = (I - h (A - l C))^-1 e_{k-1}, eigenvalues
 * 1 / (1 - h lambda_i) with lambda_i those of A - l C: inside the unit
 * circle for every h > 0 (A-stability), whatever the spread of the
 * lambda_i; nothing is subtracted from a large number, so it works in
 * float32 (tests/unit/firmware/control/test_eeo_discrete.c: spectral
 * radius of the observer error and of the full linear loop for Ts from
 * 10 us to 5 ms; forward Euler at 50 us as the counter-example).
 * g3 may change between steps (Remark 2): mc_eeo_set_g3_f32() recomputes m.
 * float32 form: y_k - p1 = (y_k - y_{k-1}) - r_{k-1} - h g2 p2 with
 * r = xi1_hat - y (stored; r_k = -(1 - m1) e_k) and y_k - y_{k-1} from the
 * exact integer count increment: the innovation is never the difference
 * of two large rounded numbers (m4 ~ 3e5 would amplify that rounding).
 *
 * Per period (mc_eeo_step_f32): predict with the input of the last
 * interval, correct with y_k = g2 theta_err_k, then (12), v_q = Gamma eta
 * + u_bar clamped to the drive's limit +-v_q_max_V (v_dc / sqrt(3) after
 * SVPWM with v_d = 0); the applied value u_bar_app = v_q_app - Gamma eta
 * drives both the observer's next prediction (b_bar u_bar_app) and the
 * internal model, so a clamped voltage does not wind up eta (it then
 * follows eta' = F eta + G v_q_app, F Hurwitz).
 *
 * Start-up (mc_eeo_reset_f32): xi1_hat(0) = g2 theta_err(0) (matched), the
 * other states zero. With xi1_hat(0) = 0 the first innovation is the whole
 * initial error and the observer peaks to hundreds of kV (N = 1e7 of the
 * paper never acts); the matched start removes that peak (test_eeo_loop.c).
 *
 * Angle error input: theta - theta* must be formed before any float32
 * rounding. The step takes an integer count difference (int32, formed in
 * integers from a multi-turn int64 position, mc_eeo_counts_*), times the
 * radians-per-count scale given at init; float32 sees only the (small)
 * error, exact up to 2^24 counts.
 *
 * Units: V, s, rad (mechanical), N m, kg m^2; g3 in 1/(kg m^2),
 * b_bar in N m / (V s), sigma in N m / s.
 */
#ifndef MC_EEO_H
#define MC_EEO_H

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "mc/clamp.h"
#include "mc/compiler.h"
#include "mc/status.h"

#define MC_EEO_NW_MAX  6u /* largest internal-model order */
#define MC_EEO_N_CHAIN 4u /* observer chain: xi1, xi2, xi3, sigma */
#define MC_EEO_REC_MAX 8u /* largest n of the Appendix A recursion */

/* ---- gain design (Appendix A), double, design time ------------------- */

/* Recursion of Section 6 / Appendix A for a chain of length n
 * (2 <= n <= MC_EEO_REC_MAX): y = g1 x1, x_i' = g_{i+1} x_{i+1}. Arrays
 * are indexed g[i - 1] = g_i. b_0 = 1 and for k = 1 .. n-1,
 * d = b_{k-1} ... b_0,
 *   b_k = (L_k (max{g_r^max, r = n-k+2..n} sqrt(k) + d k g_{n-k+1}^max)
 *          + d g_{n-k+1}^max) / g_{n-k}^min     (max of an empty set: 0)
 * and a_{n-1} = b_{n-1}, a_i = a_{i+1} b_i (a_0 = b_{n-1} ... b_0).
 * Used: g_min[0 .. n-2], g_max[1 .. n-1] (finite, > 0), L[0 .. n-2]
 * (L_1 .. L_{n-1}, finite, > 0). Writes a[0 .. n-1] = a_0 .. a_{n-1};
 * optional b[0 .. n-1] = b_0 .. b_{n-1} (NULL to skip).
 * Note: the paper assumes b_k >= 1 in its bound; its own numbers give
 * b1 = 2.48e-4. The formula is applied as printed (it reproduces the
 * printed a). MC_ERR_NONFINITE / MC_ERR_PARAM, outputs untouched.
 * Interrupt context: no. */
mc_status_t mc_eeo_gain_recursion(uint32_t n, const double *g_min,
                                  const double *g_max, const double *L,
                                  double *a, double *b);

/* Gamma placing the eigenvalues of F + G Gamma (7): f and s are the
 * monic characteristic polynomials of F and of S, low order first
 * (s^n + c[n-1] s^(n-1) + ... + c[0]); Gamma_i = f_i - s_i. F must be
 * Hurwitz (Routh test); 1 <= n <= MC_EEO_NW_MAX. Interrupt context: no. */
mc_status_t mc_eeo_gamma_place(uint32_t n, const double *f_coef,
                               const double *s_coef, double *gamma);

/* True if the monic polynomial (coefficients low order first, order n,
 * 1 <= n <= MC_EEO_NW_MAX) is Hurwitz (Routh, strict). Interrupt
 * context: no. */
bool mc_eeo_poly_is_hurwitz(uint32_t n, const double *coef);

/* ZOH of x' = M x + g u over Ts, M the companion matrix of the monic
 * polynomial coef (order n): D = exp(M Ts) - I (n x n, row major) and
 * E = int_0^Ts exp(M t) g dt with g = e_n. Scaling and squaring on
 * exp(.) - I. MC_ERR_PARAM if ||M|| Ts > 1e3. Interrupt context: no. */
mc_status_t mc_eeo_companion_zoh(uint32_t n, const double *coef, double Ts_s,
                                 double *D, double *E);

/* Backward-Euler correction gains m (see above) for h = Ts, continuous
 * gains l[0..3] and g2, g3: w = h M^-1 l, m = w / (1 + w1).
 * MC_ERR_PARAM for non-positive or non-finite inputs. Interrupt context:
 * no (double). */
mc_status_t mc_eeo_be_gains(double Ts_s, double g2, double g3, const double *l,
                            double *m);

/* ---- the regulator ----------------------------------------------------- */

typedef struct {
    float Ts_s;          /* period, (0, 0.1] s */
    uint32_t pole_pairs; /* n_p = g2, 1 .. 1000 */
    float rad_per_count; /* mechanical rad per encoder count, > 0 */
    /* Appendix A bounds (Section 6: g1min = g4max = 1, g2 = n_p) */
    float g1_min;          /* > 0 */
    float g3_min_per_kgm2; /* 0 < g3_min <= g3_max */
    float g3_max_per_kgm2;
    float g3_per_kgm2; /* g3 the observer uses, in [g3_min, g3_max] */
    float g4_max;      /* > 0 */
    float L_k[3];      /* L_1..L_3 > 0 */
    float kappa;       /* high gain, > 0 */
    /* control (12) */
    float b_bar_Nm_per_Vs; /* nonzero, |b - b_bar| < |b_bar| */
    float K[3];            /* on (xi1, xi2, xi3); xi3 polynomial Hurwitz */
    float N_V;             /* sat_N level, > 0 */
    float v_q_max_V;       /* drive limit on |v_q|, > 0 */
    /* internal model (7): orders 0 (none) .. MC_EEO_NW_MAX */
    uint32_t n_w;
    float f_coef[MC_EEO_NW_MAX]; /* F's polynomial, Hurwitz */
    float s_coef[MC_EEO_NW_MAX]; /* S's polynomial */
    /* periods between computing v_q and its taking effect beyond the
     * nominal hold over the next period: 0 or 1 */
    uint32_t input_delay_steps;
} mc_eeo_params_t;

typedef struct {
    /* design */
    float h_s;         /* Ts */
    float g2;          /* n_p */
    float g3_per_kgm2; /* g3 in use */
    float g3_min_per_kgm2, g3_max_per_kgm2;
    float h_g2, h_g3;        /* h g2, h g3 (the chain's prediction) */
    float h_l[2];            /* h l1, h l2 (backward-Euler gains) */
    float w34[2];            /* w3, w4 (g3-free: computed once) */
    float y_per_count;       /* n_p rad_per_count */
    float l[MC_EEO_N_CHAIN]; /* continuous gains of (13) */
    float m[MC_EEO_N_CHAIN]; /* backward-Euler correction gains */
    float m1c;               /* 1 - m1 = 1 / (1 + w1) */
    float b_bar, inv_b_bar, K[3], N_V, v_q_max_V;
    uint32_t n_w, delay;
    float D[MC_EEO_NW_MAX * MC_EEO_NW_MAX];
    float E[MC_EEO_NW_MAX];
    float gamma[MC_EEO_NW_MAX];
    /* state */
    float x[MC_EEO_N_CHAIN]; /* xi1_hat (rad), xi2_hat (rad/s), xi3_hat
                                (N m), sigma_hat (N m/s) */
    float r1;                /* xi1_hat - y of the last step (rad) */
    int32_t last_err_counts; /* err_counts of the last step */
    /* internal model (V units of v_q) and its compensated-sum residual,
     * double-buffered: the step reads half im_sel and writes the other,
     * which becomes the state only when the step succeeds (no copy) */
    float eta[2][MC_EEO_NW_MAX];
    float eta_c[2][MC_EEO_NW_MAX];
    uint32_t im_sel;
    float u_hist[2]; /* b_bar u_bar_app of the last two steps */
} mc_eeo_f32_t;

typedef struct {
    float v_q_V;    /* applied (clamped) q voltage; v_d = 0 */
    float u_bar_V;  /* u_bar after sat_N, before the drive clamp */
    bool sat_N;     /* sat_N of (12) acted */
    bool v_limited; /* the drive clamp acted */
} mc_eeo_out_t;

/* Paper 000 Section 6 defaults for a motor with inertia j and the given
 * period/encoder (g3 = 1/j +- 1e4, b_bar = 20, K = (-1 -3 -3),
 * N = 1e7, kappa = 1e3, L_k = 1, F = (s+1)^3, S = s (s^2 + 1), no extra
 * delay); v_q_max_V must still be set by the caller. Interrupt context:
 * no. */
void mc_eeo_params_paper000(mc_eeo_params_t *p, float Ts_s, uint32_t pole_pairs,
                            float j_kgm2, float rad_per_count);

/* Validate every field and design (recursion, Gamma, ZOH, backward-Euler
 * gains). On error *ctl is untouched. Leaves the states at zero: call
 * mc_eeo_reset_f32 before the first step. Interrupt context: no. */
mc_status_t mc_eeo_init_f32(mc_eeo_f32_t *ctl, const mc_eeo_params_t *p);

/* Start-up: states zero except xi1_hat = g2 theta_err (matched start)
 * when matched is true (xi1_hat = 0 otherwise: the paper's all-zero
 * start). Interrupt context: yes. */
mc_status_t mc_eeo_reset_f32(mc_eeo_f32_t *ctl, int32_t err_counts,
                             bool matched);

/* Change g3 (1/(kg m^2)) used by the observer, within the design bounds
 * [g3_min, g3_max]: recomputes m in float32 (bounded, one guarded
 * division). MC_ERR_NONFINITE / MC_ERR_RANGE, nothing changed.
 * Interrupt context: yes. */
mc_status_t mc_eeo_set_g3_f32(mc_eeo_f32_t *ctl, float g3_per_kgm2);

/* One period: err_counts = position - reference in encoder counts
 * (theta - theta*, formed in integers). Writes *out. Non-finite
 * intermediate: MC_ERR_NONFINITE, state and *out untouched.
 * Interrupt context: yes. */
mc_status_t mc_eeo_step_f32(mc_eeo_f32_t *ctl, int32_t err_counts,
                            mc_eeo_out_t *out);

/* The computation of mc_eeo_set_g3_f32 for a g3 in [g3_min, g3_max] (the
 * caller checks or clamps it), inline for the ISR: true with m, m1c and
 * g3 set, or false with nothing changed when 1 + w1 is not in
 * [1, FLT_MAX] (the division's guard; a NaN g3 lands here).
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool mc_eeo_set_g3_core_f32(mc_eeo_f32_t *ctl,
                                                  float g3_per_kgm2)
{
    /* backward-Euler gains (above): w = h M^-1 l, m = w / (1 + w1);
     * w4, w3, h l1, h l2 and h g2 do not depend on g3 */
    const float h_g3 = ctl->h_s * g3_per_kgm2;
    const float w4 = ctl->w34[1];
    const float w3 = ctl->w34[0];
    const float w2 = ctl->h_l[1] + h_g3 * w3;
    const float w1 = ctl->h_l[0] + ctl->h_g2 * w2;
    const float den = 1.0f + w1; /* > 1 for the positive terms above */
    if (!(den >= 1.0f && den <= FLT_MAX)) {
        return false;
    }
    const float inv = 1.0f / den;
    ctl->m[0] = w1 * inv;
    ctl->m[1] = w2 * inv;
    ctl->m[2] = w3 * inv;
    ctl->m[3] = w4 * inv;
    ctl->m1c = inv;
    ctl->g3_per_kgm2 = g3_per_kgm2;
    ctl->h_g3 = h_g3;
    return true;
}

/* Gamma eta of the step (n_w = ctl->n_w; a constant lets the compiler
 * unroll). Interrupt context: yes. */
MC_STATIC_FORCEINLINE float mc_eeo_gamma_eta_f32(const mc_eeo_f32_t *ctl,
                                                 uint32_t n_w)
{
    const float *eta = ctl->eta[ctl->im_sel];
    float gamma_eta = 0.0f;
#pragma GCC unroll 6
    for (uint32_t i = 0; i < n_w; ++i) {
        gamma_eta += ctl->gamma[i] * eta[i];
    }
    return gamma_eta;
}

/* The internal model's update of the step: eta_{k+1} = eta_k + D eta_k
 * + E u_app (exact ZOH) with its compensated sum, from half im_sel into
 * the other; returns the new values times 0 summed (mc/finite.h).
 * n_w = ctl->n_w (a constant lets the compiler unroll). Interrupt
 * context: yes. */
MC_STATIC_FORCEINLINE float mc_eeo_im_step_f32(mc_eeo_f32_t *ctl, float u_app,
                                               uint32_t n_w)
{
    const float *eta = ctl->eta[ctl->im_sel];
    const float *eta_c = ctl->eta_c[ctl->im_sel];
    float *eta_next = ctl->eta[ctl->im_sel ^ 1u];
    float *eta_c_next = ctl->eta_c[ctl->im_sel ^ 1u];
    float acc = 0.0f;
#pragma GCC unroll 6
    for (uint32_t i = 0; i < n_w; ++i) {
        float d = ctl->E[i] * u_app;
#pragma GCC unroll 6
        for (uint32_t j = 0; j < n_w; ++j) {
            d += ctl->D[i * n_w + j] * eta[j];
        }
        /* compensated sum: the increments are O(Ts) of eta, so plain
         * float32 accumulation would drift (the bias mode integrates) */
        const float y_c = d - eta_c[i];
        const float t_c = eta[i] + y_c;
        const float c_next = (t_c - eta[i]) - y_c;
        eta_c_next[i] = c_next;
        eta_next[i] = t_c;
        acc += t_c * 0.0f + c_next * 0.0f;
    }
    return acc;
}

/* The step of mc_eeo_step_f32, inline for the ISR: true with the new
 * state and *out, or false with state and *out untouched when an
 * intermediate is not finite. One finiteness test: u_hat, v_q, b_bar
 * u_bar_app, r1 and the new eta, eta_c times 0 summed (mc/finite.h);
 * u_hat covers the new chain estimate x (each reaches it through a
 * finite gain: inf * 0 and inf - inf are NaN). Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool
mc_eeo_step_core_f32(mc_eeo_f32_t *ctl, int32_t err_counts, mc_eeo_out_t *out)
{
    const float h = ctl->h_s;
    /* y_k = g2 (theta - theta*), exact integer error times the scale */
    const float y = (float)err_counts * ctl->y_per_count;
    /* (13), backward Euler: predict the chain with the input of the last
     * interval ... */
    const float u_p = ctl->u_hist[ctl->delay];
    const float p4 = ctl->x[3];
    const float p3 = ctl->x[2] + h * (u_p + p4);
    const float p2 = ctl->x[1] + ctl->h_g3 * p3;
    /* p1 = xi1_{k-1} + dp1; the innovation y_k - p1 is formed from the
     * exact integer increment of y and the small stored residual
     * r = xi1_hat - y (no difference of two large float32 numbers, whose
     * rounding the gain m4 ~ 3e5 would amplify) */
    const float dp1 = ctl->h_g2 * p2;
    const int64_t dc = (int64_t)err_counts - (int64_t)ctl->last_err_counts;
    /* the increment as a float: from int32 (one instruction) when it fits,
     * which rounds like the int64 conversion */
    const float dc_f = (dc >= (int64_t)INT32_MIN && dc <= (int64_t)INT32_MAX)
                           ? (float)(int32_t)dc
                           : (float)dc;
    const float dy = dc_f * ctl->y_per_count;
    /* ... then correct every state by its gain times one innovation */
    const float e = dy - ctl->r1 - dp1;
    const float r1 = -ctl->m1c * e; /* xi1_k - y_k = (m1 - 1) e */
    const float x0 = y + r1;
    const float x1 = p2 + ctl->m[1] * e;
    const float x2 = p3 + ctl->m[2] * e;
    const float x3 = p4 + ctl->m[3] * e;
    /* (12): u_bar = sat_N((-sigma + K xi) / b_bar) */
    const float u_hat = ctl->inv_b_bar * (-x3 + ctl->K[0] * x0 +
                                          ctl->K[1] * x1 + ctl->K[2] * x2);
    const float n_v = ctl->N_V;
    const bool sat_n = fabsf(u_hat) > n_v;
    const float u_bar = mc_clamp_sym_f32(u_hat, n_v);
    /* (7): v_q = Gamma eta + u_bar, clamped to the drive's limit */
    const uint32_t n_w = ctl->n_w;
    /* the drive's order 3 (paper 000, mc/ctl_eeo.h) as straight-line
     * code, the same operations */
    const float gamma_eta = (n_w == 3u) ? mc_eeo_gamma_eta_f32(ctl, 3u)
                                        : mc_eeo_gamma_eta_f32(ctl, n_w);
    const float v_sum = gamma_eta + u_bar;
    const float v_max = ctl->v_q_max_V;
    const bool lim = fabsf(v_sum) > v_max;
    const float v_q = mc_clamp_sym_f32(v_sum, v_max);
    const float u_app = v_q - gamma_eta; /* what the plant really got */
    /* eta_{k+1} = eta_k + D eta_k + E u_bar_app (exact ZOH), into the
     * spare half */
    const float acc_im = (n_w == 3u) ? mc_eeo_im_step_f32(ctl, u_app, 3u)
                                     : mc_eeo_im_step_f32(ctl, u_app, n_w);
    const float bu = ctl->b_bar * u_app;
    if (!((acc_im + u_hat * 0.0f + v_q * 0.0f + bu * 0.0f + r1 * 0.0f) ==
          0.0f)) {
        return false;
    }
    ctl->x[0] = x0;
    ctl->x[1] = x1;
    ctl->x[2] = x2;
    ctl->x[3] = x3;
    ctl->r1 = r1;
    ctl->last_err_counts = err_counts;
    ctl->im_sel ^= 1u;
    ctl->u_hist[1] = ctl->u_hist[0];
    ctl->u_hist[0] = bu;
    out->v_q_V = v_q;
    out->u_bar_V = u_bar;
    out->sat_N = sat_n;
    out->v_limited = lim;
    return true;
}

/* ---- multi-turn position in integer counts ---------------------------- */

typedef struct {
    int64_t pos_counts; /* unwrapped multi-turn position */
    uint32_t last_raw;  /* last single-turn reading, 0 .. cpr-1 */
    uint32_t cpr;       /* counts per revolution, >= 4 */
} mc_eeo_counts_t;

/* Start at raw (single-turn reading) = position raw. MC_ERR_PARAM for
 * cpr < 4 or raw >= cpr. Interrupt context: yes. */
mc_status_t mc_eeo_counts_init(mc_eeo_counts_t *c, uint32_t cpr, uint32_t raw);

/* Unwrap: adds the shortest signed step from the last reading (|step|
 * < cpr/2 per call required). MC_ERR_RANGE for raw >= cpr.
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE mc_status_t mc_eeo_counts_update(mc_eeo_counts_t *c,
                                                       uint32_t raw)
{
    if (raw >= c->cpr) {
        return MC_ERR_RANGE;
    }
    int64_t d = (int64_t)raw - (int64_t)c->last_raw;
    const int64_t cpr = (int64_t)c->cpr;
    /* shortest signed step: d in [-cpr/2, cpr/2) */
    if (d >= cpr / 2) {
        d -= cpr;
    } else if (d < -(cpr / 2)) {
        d += cpr;
    }
    c->pos_counts += d;
    c->last_raw = raw;
    return MC_OK;
}

/* err = pos - ref in int32; MC_ERR_RANGE (err saturated) if the
 * difference does not fit. Interrupt context: yes. */
MC_STATIC_FORCEINLINE mc_status_t mc_eeo_count_error(int64_t pos_counts,
                                                     int64_t ref_counts,
                                                     int32_t *err_counts)
{
    /* pos - ref without int64 overflow: compare before subtracting */
    if ((ref_counts < 0 && pos_counts > INT64_MAX + ref_counts) ||
        (ref_counts > 0 && pos_counts < INT64_MIN + ref_counts)) {
        *err_counts = (pos_counts > ref_counts) ? INT32_MAX : INT32_MIN;
        return MC_ERR_RANGE;
    }
    const int64_t d = pos_counts - ref_counts;
    if (d > (int64_t)INT32_MAX || d < (int64_t)INT32_MIN) {
        *err_counts = (d > 0) ? INT32_MAX : INT32_MIN;
        return MC_ERR_RANGE;
    }
    *err_counts = (int32_t)d;
    return MC_OK;
}

#endif /* MC_EEO_H */
