/*
 * Speed regulator family of paper 002: composite disturbance observer
 * based control (CDOBC) and its baselines GPIOBC (polynomial model only),
 * HDOBC (harmonic models only) and the noncascade PID. float32 per-period
 * step; design (double) at init and whenever the speed reference moves the
 * model frequencies (mc_cdobc_design_f64, slow context).
 *
 * Plant (3)-(5), MECHANICAL speed omega (rad/s), theta_e = n_p theta_m:
 *   x1 = omega* - omega,  x2 = pi_iq - i_q                             (4)
 *   x1' = b1 x2,  x2' = -a x2 + D - u_qi / L_q                        (5)(7)
 *   b1 = 3 n_p psi_f / (2 J),  a = B_v / J + R_s / L_q,
 * with D the lumped disturbance (x3 + x5 + x7 of (7)) and the voltage
 *   v_q = u_qd + u_qi,  u_qd = (2 B_v R_s / (3 n_p psi_f) + n_p psi_f
 *          + n_p L_d i_d) omega                                    (6)(10)
 * saturated to +-v_max_V; v_d from a PI on -i_d (i_d* = 0), +-v_max_V.
 *
 * Internal models (7), a list (mc_cdobc_models_t): harmonics of order k,
 * electrical (frequency k n_p |omega*|: k = 6 dead time, 1 and 2 current
 * sensor offset and gain errors) or mechanical (k |omega*|: k = Q
 * cogging), each x_h'' = -w^2 x_h; plus a polynomial of order N (N
 * integrators, x7^(N) = 0: load and the rest). Frequencies follow the
 * speed reference (Remark 3), floored at omega_min_rad_s so that no two
 * models collapse onto the polynomial at standstill.
 * Observer state w = (x2, x_h1, x_h1', ..., x7 .. x_{N+6}), order
 * n = 1 + 2 n_harm + N.
 *
 * Discretisation (mc/zoh.h): exact ZOH at Ts of the augmented model in
 * (nu, w), nu = -omega (so x1 = omega* + nu, and nu' = x1' for a constant
 * omega*), input the applied voltage v (the i_d coupling term of (6)
 * removed), with the back-EMF and friction terms that (6) cancels kept in
 * the model: x2' = -a x2 + D - (v - c_qd omega) / L_q, c_qd = 2 B_v R_s /
 * (3 n_p psi_f) + n_p psi_f. This is (5) exactly, also between samples,
 * where a held (6) no longer cancels c_qd omega(t). The discrete internal
 * models keep exactly the eigenvalues exp(+-j w Ts) and 1 (forward Euler
 * would detune them):
 *   nu_{k+1} = a_nn nu_k + c w_k + Bd1 v_k
 *   w_{k+1}  = a_wn nu_k + Ad w_k + Bd2 v_k.
 * Reduced-order observer (8) in discrete form, driven by nu = -omega, not
 * by x1 (a step of omega* does not enter the observer, so the estimates
 * do not peak; driven by x1, a 0 -> 500 rpm step would be a first command
 * of 580 V with the default design instead of 15 V):
 *   w_k = a_wn nu_{k-1} + Ad w_{k-1} + Bd2 v_{k-1}
 *         + Ld (nu_k - a_nn nu_{k-1} - c w_{k-1} - Bd1 v_{k-1})
 * with v the voltage actually applied (after saturation) over the last
 * period. One period of delay (duties computed at t_k act over (t_{k+1},
 * t_{k+2}]) is modelled: the control acts on the one-step prediction
 * (nu_p, x2p, dp) from (nu_k, w_k, v_k), x1p = omega* + nu_p:
 *   v = u_qd + u_qi,  u_qd = c_qd omega_p                      (6), (10)
 *   u_qi = k1 x1p + k2 x2p + f . dp                                    (9)
 * with f cancelling the modelled disturbance's effect on x2 over the
 * period it acts (f_j = -Ad[0][j] / Bd2[0]; the discrete form of
 * L_q (x3 + x5 + x7)); everything linear is folded into
 *   v = k1 omega* + g_nu nu_k + g . w_k + gu v_k.
 * Nominally the closed loop's eigenvalues are exactly the controller's,
 * the observer's and zeros (separation, delay included).
 *
 * Gains (Remark 6, bandwidth parameterisation), mc_cdobc_place.c:
 * controller poles at exp(-ctl_pole Ts) (double) on the ZOH (nu, x2)
 * model, (6) included; observer poles of Ad - Ld c at exp(p Ts) for
 *   MC_CDOBC_PLACE_LITERAL: every p = -obs_pole (the paper: -520);
 *   MC_CDOBC_PLACE_ROBUST: each harmonic pair at s^2 + 2 zeta w s + w^2
 *   (its own frequency, lightly damped), the other 1 + N at -obs_pole.
 * The literal design puts every observer pole far below the harmonic
 * frequencies it must notch (about 1257 and 1676 rad/s at 500 rpm):
 * mc_cdobc_est_error_gain shows the amplification this causes and
 * mc_cdobc_loop_radius its loss of robustness; ROBUST (zeta = 0.03) is the
 * default. Paper motor, 500 rpm, 10 kHz, N = 2 (test_cdobc_analysis.c):
 *   LITERAL CDOBC: |D - D_hat| / |d| 28 at 25 Hz, 47.5 peak at 49 Hz, 40
 *   at 67 Hz; HDOBC 304 at DC; closed loop unstable beyond J -2 % / +8 %,
 *   R -3 % / +6 %, L -3 % / +12 %, Kt -4 % / +2 %;
 *   ROBUST CDOBC: peak 1.41 (134.5 Hz); stable on the whole {0.8, 1,
 *   1.2}^4 grid of (J, R, L, Kt), spectral radius at most 0.9983.
 * zeta trades measurement noise, margin and convergence. A pair's
 * observer gain, and the encoder quantisation it passes into the voltage,
 * grows with zeta: on the host bench (Case I, 2500 lines, observer poles
 * -1000) the steady fluctuation is 1.72 rpm at 0.1, 1.30 at 0.03, 1.16 at
 * 0.01 (means of 8 starts). The grid margin shrinks as zeta falls (worst
 * radius 0.9949 at 0.1, 0.9983 at 0.03, 0.9994 at 0.01, all stable; 0.3
 * puts the corner J, R, L -20 %, Kt +20 % unstable), and a mode converges
 * with time constant 1 / (zeta w): 27 ms for 6e at 500 rpm at 0.03 (8 ms
 * at 0.1), 160 ms for a 1st electrical model, hence a pair's own zeta
 * (mc_cdobc_harm_t.zeta; the drive puts the current-sensor pairs at 0.5).
 * Placement: Ackermann's formula for the single-output pair in the delta
 * form ((Ad - I) / Ts, c / Ts), states scaled by W^level and time by W
 * (W = largest pole or model frequency), so the observability matrix is
 * well conditioned (see mc_cdobc_ackermann_f64).
 *
 * Re-design: the model frequencies, Ad, Ld and g depend on omega*; the
 * glue calls mc_cdobc_design_f64 + mc_cdobc_coef_f32 in a background
 * (slow) context when |omega*| has moved by more than a chosen step since
 * the last design and hands the result to mc_cdobc_set_coef_f32; the
 * observer state is kept across the swap. A detuned harmonic model
 * passes part of its disturbance (ROBUST default, 500 rpm: 1 % detuning
 * leaves 15 % of the 6th-electrical and 13 % of the Q-th mechanical
 * harmonic in the estimation error), so re-design when the reference
 * moves by about 0.1 %, or follow a ramp at the task's rate. Cost: one
 * (n + 2) x (n + 2) matrix exponential (at most 31 products, about
 * 31 (n + 2)^3 = 85k double multiply-adds for n = 12), two small
 * Ackermann solves: O(1e5) double operations, a few ms of soft double on
 * a Cortex-M4F; never in the ISR.
 *
 * Per-period cost (mc_cdobc_step_f32), counted from the code: n^2 + 6 n
 * multiply-adds plus
 * about 30 float32 operations (prediction-folded control, clamps, d-axis
 * PI), no division, no sqrt, no libm call: about 120 for CDOBC with
 * 6e + Q + N = 2 (n = 7), about 250 for the largest set (n = 12); a few
 * microseconds on a Cortex-M4F, well within a 10-20 kHz period. The ISR
 * runs mc_cdobc_step_core_f32 (no d_hat: n^2 + 5 n multiply-adds), the
 * state double-buffered (no copy), one finiteness test: about 385
 * instructions for n = 7 on the QEMU Cortex-M4F image (tests/qemu).
 *
 * Units: V, A, s, rad/s (mechanical), H, ohm, Wb, kg m^2, N m s/rad.
 */
#ifndef MC_CDOBC_H
#define MC_CDOBC_H

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "mc/clamp.h"
#include "mc/compiler.h"
#include "mc/pi.h"
#include "mc/status.h"

#define MC_CDOBC_HARM_MAX 4u /* harmonic internal models */
#define MC_CDOBC_POLY_MAX 3u /* polynomial order N */
#define MC_CDOBC_N_MAX    (1u + 2u * MC_CDOBC_HARM_MAX + MC_CDOBC_POLY_MAX)
#define MC_CDOBC_LOOP_MAX (MC_CDOBC_N_MAX + 5u) /* analysis loop states */

/* ---- model set (cdobc_models.c) --------------------------------------- */

typedef enum {
    MC_CDOBC_ELEC = 0, /* frequency order * n_p * |omega*| */
    MC_CDOBC_MECH = 1  /* frequency order * |omega*| */
} mc_cdobc_axis_t;

typedef struct {
    mc_cdobc_axis_t axis;
    uint32_t order; /* 1 .. 1000 */
    float zeta;     /* ROBUST: damping of this pair, (0, 1); 0: the
                       parameters' harm_zeta */
} mc_cdobc_harm_t;

typedef struct {
    uint32_t n_harm; /* 0 .. MC_CDOBC_HARM_MAX */
    mc_cdobc_harm_t harm[MC_CDOBC_HARM_MAX];
    uint32_t poly_order; /* N, 0 .. MC_CDOBC_POLY_MAX */
} mc_cdobc_models_t;

/* Checks the list: n_harm, poly_order in range, axes known, orders in
 * 1 .. 1000, each zeta 0 or in (0, 1), distinct frequencies (in mechanical
 * multiples, k n_p for electrical), at least one model. MC_ERR_PARAM otherwise.
 * Interrupt context: no. */
mc_status_t mc_cdobc_models_check(const mc_cdobc_models_t *m,
                                  uint32_t pole_pairs);

/* n = 1 + 2 n_harm + N. Interrupt context: yes. */
uint32_t mc_cdobc_models_order(const mc_cdobc_models_t *m);

/* Continuous model of w (7), n x n row major, for a checked list:
 * A[0][0] = -a, A[0][first state of each model] = 1, harmonic blocks
 * [0 1; -w^2 0], polynomial chain of integrators. level[i]: number of
 * integrators between state i and x2 (x2: 0, a harmonic's states 1 and
 * 2, polynomial state j: j + 1); h: 1 on each model's first state (the
 * disturbance it feeds into x2'), 0 elsewhere; w_rad_s[i]: frequency of
 * harmonic i at mechanical speed omega_rad_s (> 0). Interrupt context: no.
 */
void mc_cdobc_models_build(const mc_cdobc_models_t *m, uint32_t pole_pairs,
                           double omega_rad_s, double a_per_s, double *A,
                           uint32_t *level, double *h, double *w_rad_s);

/* ---- placement (cdobc_place.c), double, design time -------------------- */

/* Solve A x = b in place (A destroyed, b becomes x), n <= 2 N_MAX, Gauss
 * with partial pivoting. MC_ERR_PARAM if a pivot is not larger than
 * 1e-13 times the largest column entry (singular to working precision).
 * Interrupt context: no. */
mc_status_t mc_cdobc_solve_f64(uint32_t n, double *A, double *b);

/* Monic polynomial (low order first, coef[0 .. n-1], s^n implied) with
 * the n roots re[i] + j im[i]; a root with im != 0 must be followed by
 * its conjugate. MC_ERR_PARAM otherwise. Interrupt context: no. */
mc_status_t mc_cdobc_poly_from_roots(uint32_t n, const double *re,
                                     const double *im, double *coef);

/* Ackermann's formula for the single-output pair (A, c): l such that
 * A - l c has the characteristic polynomial coef (monic, low order
 * first):  l = p(A) O^-1 e_n,  O = [c; c A; ...; c A^(n-1)].
 * Solved as O v = e_n, then p(A) v by Horner. Callers scale A and c to
 * O(1) entries first (O is then well conditioned). The controller gain
 * of (A, b) is the dual: k^T = ackermann(A^T, b^T). 1 <= n <= N_MAX.
 * MC_ERR_PARAM if (A, c) is not observable to working precision.
 * Interrupt context: no. */
mc_status_t mc_cdobc_ackermann_f64(uint32_t n, const double *A, const double *c,
                                   const double *coef, double *l);

/* ---- parameters and design (cdobc_discrete.c) -------------------------- */

typedef enum {
    MC_CDOBC_PLACE_LITERAL = 0, /* every observer pole at -obs_pole */
    MC_CDOBC_PLACE_ROBUST = 1   /* harmonic pairs at their frequency */
} mc_cdobc_placement_t;

typedef enum {
    MC_CDOBC_KIND_CDOBC = 0,  /* 6e + Q-th mechanical + polynomial */
    MC_CDOBC_KIND_GPIOBC = 1, /* polynomial only */
    MC_CDOBC_KIND_HDOBC = 2   /* harmonics only */
} mc_cdobc_kind_t;

typedef struct {
    float Ts_s;          /* control period, (0, 1e-2] */
    uint32_t pole_pairs; /* n_p, 1 .. 100 */
    float psi_f_Wb;      /* > 0 */
    float L_q_H;         /* > 0 */
    float L_d_H;         /* > 0 (coupling term of (6)) */
    float R_ohm;         /* > 0 */
    float J_kgm2;        /* > 0 */
    float B_Nms_rad;     /* >= 0 */
    mc_cdobc_models_t models;
    mc_cdobc_placement_t placement;
    float ctl_pole_rad_s;  /* controller poles at -this, > 0 (200) */
    float obs_pole_rad_s;  /* observer poles at -this, > 0 (520) */
    float harm_zeta;       /* ROBUST: harmonic damping, (0, 1) */
    float omega_min_rad_s; /* floor of |omega*| for frequencies, > 0 */
    float v_max_V;         /* |v_q|, |v_d| limit, > 0 (200) */
    float kp_d_V_A;        /* d-axis PI (120), >= 0 */
    float ki_d_V_As;       /* (240), >= 0, kp + ki > 0 */
} mc_cdobc_params_t;

/* Paper 002 Section IV motor and gains (n_p = 4, Q = 32, psi_f =
 * 0.084 Wb, L = 26 mH, R = 9.7 ohm, J = 1.35e-4 kg m^2, B_v = 7.4e-5,
 * poles -200 / -520, d-axis PI 120 / 240, +-200 V) for the given period
 * and family member; models: CDOBC {6 electrical, 32 mechanical} + N = 2,
 * GPIOBC N = 2, HDOBC {6 electrical, 32 mechanical}; ROBUST placement
 * with zeta = 0.03, omega_min = 10 rad/s. Interrupt context: no. */
void mc_cdobc_params_paper002(mc_cdobc_params_t *p, float Ts_s,
                              mc_cdobc_kind_t kind);

/* Validates every field (finite, ranges above, model list). Interrupt
 * context: no. */
mc_status_t mc_cdobc_params_check(const mc_cdobc_params_t *p);

/* The discrete design at one speed reference, double. */
typedef struct {
    uint32_t n;                      /* observer order */
    uint32_t n_harm, poly_order;     /* the models' layout of w (above) */
    double Ts_s, omega_design_rad_s; /* |omega*| floored */
    double b1, a_per_s, L_q_H;       /* (5) */
    double J_kgm2, R_ohm, psi_f_Wb, B_Nms_rad, n_p;
    double c_qd_V_s;                            /* (6) with i_d = 0 */
    double w_rad_s[MC_CDOBC_HARM_MAX];          /* model frequencies */
    double Ad[MC_CDOBC_N_MAX * MC_CDOBC_N_MAX]; /* w block of the ZOH */
    double Bd2[MC_CDOBC_N_MAX];
    double a_wn[MC_CDOBC_N_MAX]; /* nu column of the w rows */
    double c[MC_CDOBC_N_MAX];    /* nu row: nu+ = a_nn nu + c w + Bd1 v */
    double a_nn, Bd1;
    double Ld[MC_CDOBC_N_MAX];          /* observer gain */
    double k1, k2;                      /* (9) gains, paper's sense */
    double g[MC_CDOBC_N_MAX], gu, g_nu; /* folded control */
    double h[MC_CDOBC_N_MAX];           /* model outputs into x2' */
    double obs_re[MC_CDOBC_N_MAX], obs_im[MC_CDOBC_N_MAX]; /* poles, s */
    /* continuous (nu, w) model, scaled: x = diag(t) xs (analysis) */
    double Acs[(MC_CDOBC_N_MAX + 1u) * (MC_CDOBC_N_MAX + 1u)];
    double t[MC_CDOBC_N_MAX + 1u];
} mc_cdobc_design_t;

/* Design at the speed reference omega_ref_rad_s (sign ignored, floored at
 * omega_min_rad_s). Validates p. MC_ERR_NONFINITE / MC_ERR_PARAM;
 * MC_ERR_RANGE if a model frequency reaches a quarter of the sampling
 * rate (w Ts >= pi / 2: drop that model at this speed); *d untouched on
 * error. Stack: about 21 KB with the ZOH (measured with -fstack-usage,
 * arm-none-eabi-gcc -Os), plus 4.5 KB in mc_cdobc_init_f32.
 * Interrupt context: no. */
mc_status_t mc_cdobc_design_f64(const mc_cdobc_params_t *p,
                                double omega_ref_rad_s, mc_cdobc_design_t *d);

/* float32 coefficients of the step. The observer's matrix minus I,
 * Ad - I - Ld c, by its structure: the models are autonomous, so Ad - I
 * is row x2, one 2 x 2 block per harmonic model and the polynomial's
 * block (its other entries exactly zero, checked by mc_cdobc_coef_f32),
 * and Ld c has rank one (one dot product c . w). */
typedef struct {
    uint32_t n, n_harm, poly_order;
    float a0[MC_CDOBC_N_MAX];         /* row x2 of Ad - I */
    float harm[MC_CDOBC_HARM_MAX][4]; /* harmonic model b's block of Ad - I
                                         (rows 1 + 2b, 2 + 2b), by rows */
    float poly[MC_CDOBC_POLY_MAX * MC_CDOBC_POLY_MAX]; /* the polynomial's
                                         block of Ad - I, by rows (row
                                         stride MC_CDOBC_POLY_MAX) */
    float c[MC_CDOBC_N_MAX];  /* nu row of the model: c . w */
    float Gu[MC_CDOBC_N_MAX]; /* Bd2 - Ld Bd1 */
    float Gn[MC_CDOBC_N_MAX]; /* a_wn - Ld (a_nn - 1) */
    float Ld[MC_CDOBC_N_MAX];
    float g[MC_CDOBC_N_MAX];
    float h[MC_CDOBC_N_MAX]; /* 1 on each model's output state */
    float gu, k1, g_nu;
    float omega_design_rad_s;
} mc_cdobc_coef_f32_t;

/* Rounds a design to float32; MC_ERR_PARAM if a value does not fit
 * (overflow or a nonzero rounding to zero) or Ad - I has a nonzero entry
 * outside its structure (mc_cdobc_coef_f32_t). Interrupt context: no. */
mc_status_t mc_cdobc_coef_f32(const mc_cdobc_design_t *d,
                              mc_cdobc_coef_f32_t *c);

/* ---- analysis (cdobc_analysis.c), double, design time ------------------ */

/* |D - D_hat| / |d| of the discrete observer at each f_Hz[i] (0 <= f <
 * 1 / (2 Ts)), sampled: an unmodelled disturbance d(t) = cos(2 pi f t)
 * adds to D in x2' (5); its exact effect over one period on (nu, w) is
 * the corner block Gamma (n+1 x 2) of exp(Ts [A_c e_x2 e_1^T; 0 S]),
 * S = [0 -w; w 0] its exosystem, so the transfer at z = exp(j w Ts) is
 *   1 + h (zI - Phi)^-1 (Gamma_w - Ld Gamma_nu) (1, -j)^T,
 * Phi = Ad - Ld c. It is 0 at every modelled frequency (and at DC with a
 * polynomial model). n_f <= 1000. Interrupt context: no. */
mc_status_t mc_cdobc_est_error_gain(const mc_cdobc_design_t *d, uint32_t n_f,
                                    const double *f_Hz, double *gain);

/* Plant / model ratios of the true plant (each > 0): J, R, L and the
 * flux linkage (torque constant and back-EMF constant together). */
typedef struct {
    double J, R, L, Kt;
} mc_cdobc_plant_factors_t;

/* The discrete closed loop of one period at the design point, linear
 * (no saturation, i_d = 0, omega* constant), state
 * (omega, i_q, v_{k-1}, v_k, nu_{k-1}, w): ZOH of the true plant
 * (J f.J, R f.R, L f.L, psi_f f.Kt, B_v), voltage applied one period
 * after it is computed, the step's equations in double. Writes dim
 * (n + 5) and Acl (dim x dim row major). Interrupt context: no. */
mc_status_t mc_cdobc_loop_matrix(const mc_cdobc_design_t *d,
                                 const mc_cdobc_plant_factors_t *f,
                                 uint32_t *dim, double *Acl);

/* Spectral radius of that matrix by Gelfand's formula, rho = lim
 * ||A^k||^(1/k), k = 2^24 reached by 24 normalised squarings (bounded
 * time). It approaches rho from above: about 1e-6 high for simple
 * poles, up to 3e-4 for the 7- to 12-fold defective pole of LITERAL
 * (measured against a QR eigenvalue solver in test_cdobc_design.c);
 * closer to 1 than that, use an eigenvalue solver. Stable iff rho < 1.
 * Interrupt context: no. */
mc_status_t mc_cdobc_loop_radius(const mc_cdobc_design_t *d,
                                 const mc_cdobc_plant_factors_t *f,
                                 double *rho);

/* ---- the regulator (cdobc.c), float32 ---------------------------------- */

typedef struct {
    mc_cdobc_coef_f32_t coef;
    float np_Ld_H;         /* n_p L_d: (6) coupling, times i_d */
    float omega_min_rad_s; /* floor of the speed for the frequencies */
    float v_max_V;
    mc_pi_f32_t pi_d; /* d axis */
    /* observer state (x2 in A, models in A/s..), double-buffered: the
     * step reads w_buf[w_sel] and writes the other half, which becomes the
     * state only when the step succeeds (no copy; mc_cdobc_state_f32) */
    float w_buf[2][MC_CDOBC_N_MAX];
    uint32_t w_sel;
    float nu_prev; /* -omega of the last step (rad/s) */
    float v_prev;  /* v applied over the last period (V) */
    float v_cur;   /* v applied over the current period (V) */
} mc_cdobc_f32_t;

typedef struct {
    float v_q_V, v_d_V; /* saturated, to be applied next period */
    float v_q_unsat_V;  /* (10) before saturation */
    float d_hat;        /* h . w: estimated D of (5) (A/s) */
    bool q_limited, d_limited;
} mc_cdobc_out_t;

/* Validate, design at omega_ref0_rad_s and round; states zero (call
 * mc_cdobc_reset_f32 before the first step). *ctl untouched on error.
 * Interrupt context: no. */
mc_status_t mc_cdobc_init_f32(mc_cdobc_f32_t *ctl, const mc_cdobc_params_t *p,
                              float omega_ref0_rad_s);

/* Start at the measured speed: observer states (both halves) and held
 * inputs zero, nu_prev = -omega_m (no first innovation), d-axis
 * integrator zero. MC_ERR_NONFINITE for a non-finite speed. Interrupt
 * context: yes. */
mc_status_t mc_cdobc_reset_f32(mc_cdobc_f32_t *ctl, float omega_m_rad_s);

/* Swap in coefficients designed for a new speed reference (same model
 * set: same n, else MC_ERR_PARAM); the states are kept. Copies about
 * n^2 + 4 n words: call it from the ISR or with the ISR masked.
 * Interrupt context: yes. */
mc_status_t mc_cdobc_set_coef_f32(mc_cdobc_f32_t *ctl,
                                  const mc_cdobc_coef_f32_t *c);

/* True if the coefficients in use were designed for a speed that differs
 * from max(|omega_ref|, omega_min) by more than rel_tol of the latter
 * (the glue's cue to run mc_cdobc_design_f64 in the background; see
 * "Re-design" above for the tolerance). A non-finite argument answers
 * true. Interrupt context: yes (one division-free compare). */
bool mc_cdobc_needs_redesign_f32(const mc_cdobc_f32_t *ctl,
                                 float omega_ref_rad_s, float rel_tol);

/* One period: measured omega_m, reference omega*, measured i_d. Writes
 * *out. Non-finite input or result: MC_ERR_NONFINITE, state and *out
 * untouched. Implemented as mc_cdobc_step_core_f32 (below) and d_hat.
 * Interrupt context: yes. */
mc_status_t mc_cdobc_step_f32(mc_cdobc_f32_t *ctl, float omega_m_rad_s,
                              float omega_ref_rad_s, float i_d_A,
                              mc_cdobc_out_t *out);

/* The observer state w in use (n values). Interrupt context: yes. */
MC_STATIC_FORCEINLINE float *mc_cdobc_state_f32(mc_cdobc_f32_t *ctl)
{
    return ctl->w_buf[ctl->w_sel];
}

/* The observer update (8) of the step, discrete, from w into w_next:
 * w_next = w + Gn nu_prev + Gu v_prev + Ld (dnu - c . w) + (Ad - I) w
 * (each row in that order; (Ad - I) w by its structure,
 * mc_cdobc_coef_f32_t); returns v + g . w_next (the terms in the order
 * of the rows). Out of line: its loops get the registers they need.
 * Interrupt context: yes. */
float mc_cdobc_observe_f32(const mc_cdobc_coef_f32_t *k, const float *w,
                           float *w_next, float nu_prev, float v_prev,
                           float dnu, float v);

/* The step of mc_cdobc_step_f32 without d_hat, inline for the ISR: true
 * with the new state and *out (d_hat 0), or false with state and *out
 * untouched when an input or a result is not finite.
 * One finiteness test: v, v_q and v_d times 0 summed (mc/finite.h). It
 * covers the inputs and the new observer state: a non-finite omega_m,
 * omega* or w_i reaches v through a finite nonzero or zero gain (inf * 0
 * and inf - inf are NaN), a non-finite i_d reaches v_d (mc/pi.h).
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool
mc_cdobc_step_core_f32(mc_cdobc_f32_t *ctl, float omega_m_rad_s,
                       float omega_ref_rad_s, float i_d_A, mc_cdobc_out_t *out)
{
    const mc_cdobc_coef_f32_t *k = &ctl->coef;
    const float *w = ctl->w_buf[ctl->w_sel];
    float *w_next = ctl->w_buf[ctl->w_sel ^ 1u];
    const float nu_prev = ctl->nu_prev;
    const float v_prev = ctl->v_prev;
    /* observer (8), discrete: w += (Ad - I - Ld c) w + Gn nu_prev
     * + Gu v_prev + Ld (nu - nu_prev) */
    const float nu = -omega_m_rad_s;
    const float dnu = nu - nu_prev;
    /* (6) + (9) on the prediction, folded (above); the g . w terms
     * added as the rows of the new w come out, in the same order */
    float v = k->k1 * omega_ref_rad_s + k->g_nu * nu + k->gu * ctl->v_cur;
    v = mc_cdobc_observe_f32(k, w, w_next, nu_prev, v_prev, dnu, v);
    /* (6) d-q coupling, (10) saturation */
    const float u_c = ctl->np_Ld_H * i_d_A * omega_m_rad_s;
    const float v_unsat = v + u_c;
    const float v_max = ctl->v_max_V;
    const bool q_lim = fabsf(v_unsat) > v_max;
    const float v_q = mc_clamp_sym_f32(v_unsat, v_max);
    /* d axis: PI on i_d* - i_d = -i_d (its own clamp); the integrator is
     * kept only if the step succeeds */
    mc_pi_f32_t pi = ctl->pi_d;
    const float v_d = mc_pi_step_unchecked_f32(&pi, -i_d_A);
    const bool d_lim = !(v_d < v_max) || !(v_d > -v_max);
    if (!((v * 0.0f + v_q * 0.0f + v_d * 0.0f) == 0.0f)) {
        return false;
    }
    /* commit; the observer sees the voltage actually applied */
    ctl->w_sel ^= 1u;
    ctl->pi_d.integrator = pi.integrator;
    ctl->v_prev = ctl->v_cur;
    ctl->v_cur = v_q - u_c;
    ctl->nu_prev = nu;
    *out = (mc_cdobc_out_t){ .v_q_V = v_q,
                             .v_d_V = v_d,
                             .v_q_unsat_V = v_unsat,
                             .d_hat = 0.0f, /* mc_cdobc_step_f32's */
                             .q_limited = q_lim,
                             .d_limited = d_lim };
    return true;
}

/* ---- reference prefilter (cdobc_prefilter.c), float32 ------------------ */

/*
 * Two-degree-of-freedom option: a prefilter on omega* that replaces the
 * closed loop's reference poles by faster ones, leaving the feedback (and
 * so the disturbance rejection the controller poles set) unchanged.
 * Nominally omega* reaches omega through T(z) = k1 N(z) / ((z - a)^2 z)
 * (a = exp(-ctl_pole Ts)): the observer is driven by -omega and v, not by
 * omega*, so its poles do not appear (separation), and N(z) is the plant's
 * numerator, which state feedback does not move. The prefilter
 *   F(z) = ((1 - a_m) / (1 - a))^2 (z - a)^2 / (z - a_m)^2,
 *   a_m = exp(-ref_pole Ts),
 * makes F T the closed loop of a controller with its poles at -ref_pole:
 * a step of omega* settles like that design (double pole at -ref_pole)
 * while loads and harmonics meet the -ctl_pole design. F(1) = 1. Written
 * as omega*_f = omega* + d with F - 1 = (1 - z^-1) ((g - 1) + c0 z^-1) /
 * (1 - a_m z^-1)^2, g = ((1 - a_m) / (1 - a))^2, c0 = a_m^2 - g a^2, fed
 * by the reference's increments: a constant omega* gives d -> 0 and
 * omega*_f = omega* exactly, whatever the coefficients' rounding. A step
 * of omega* first commands g times the plain law's k1 step (1.32 for
 * -230 against -200). The PID baseline takes omega* unfiltered
 * (test_cdobc_prefilter.c).
 */
typedef struct {
    float g_minus_1; /* g - 1 */
    float c0;        /* a_m^2 - g a^2 */
    float two_a_m;   /* 2 a_m */
    float a_m_sq;    /* a_m^2 */
    float ref_prev;  /* omega* of the last step, rad/s */
    float s1, s2;    /* transposed direct form states of d, rad/s */
} mc_cdobc_prefilter_f32_t;

/* Design for the controller's poles at -ctl_pole_rad_s and the
 * reference's at -ref_pole_rad_s, period Ts_s (both poles > 0, ref_pole Ts
 * and ctl_pole Ts <= 1; double at design time); state at rest at 0.
 * MC_ERR_NONFINITE / MC_ERR_PARAM (*f untouched). Interrupt context: no. */
mc_status_t mc_cdobc_prefilter_init_f32(mc_cdobc_prefilter_f32_t *f, float Ts_s,
                                        float ctl_pole_rad_s,
                                        float ref_pole_rad_s);

/* At rest at omega_ref_rad_s (its next step is the change from there).
 * Interrupt context: yes. */
MC_STATIC_FORCEINLINE void
mc_cdobc_prefilter_reset_f32(mc_cdobc_prefilter_f32_t *f, float omega_ref_rad_s)
{
    f->ref_prev = omega_ref_rad_s;
    f->s1 = 0.0f;
    f->s2 = 0.0f;
}

/* One period: omega*_f. Unchecked (a non-finite omega* propagates into
 * the output and the state, for the caller's one finiteness test; a
 * restart resets). Interrupt context: yes (no division). */
MC_STATIC_FORCEINLINE float
mc_cdobc_prefilter_step_f32(mc_cdobc_prefilter_f32_t *f, float omega_ref_rad_s)
{
    const float dx = omega_ref_rad_s - f->ref_prev;
    const float d = f->g_minus_1 * dx + f->s1;
    f->s1 = f->c0 * dx + f->two_a_m * d + f->s2;
    f->s2 = -f->a_m_sq * d;
    f->ref_prev = omega_ref_rad_s;
    return omega_ref_rad_s + d;
}

/* ---- noncascade PID baseline (cdobc_pid.c), float32 -------------------- */

typedef struct {
    float kp_V_s;    /* V per rad/s (23) */
    float ki_Ts_V;   /* ki (V per rad, 10) times Ts */
    float kd_Ts_V_s; /* kd (V s^2 / rad, 0.0167) / Ts */
    float c_qd_V_s;  /* (6) omega feed-forward, 0 to disable */
    float v_max_V;
    float integ_V;    /* integrator state */
    float omega_prev; /* omega of the last step (rad/s) */
} mc_cdobc_pid_f32_t;

/* Paper gains 23, 10, 0.0167 are passed by the caller; c_qd from
 * mc_cdobc_design_t or 0. Validates (finite, gains >= 0, Ts > 0, v_max >
 * 0). Interrupt context: no. */
mc_status_t mc_cdobc_pid_init_f32(mc_cdobc_pid_f32_t *pid, float kp_V_s,
                                  float ki_V, float kd_V_s2, float Ts_s,
                                  float c_qd_V_s, float v_max_V);

/* Start at the measured speed, integrator zero. Interrupt context: yes. */
mc_status_t mc_cdobc_pid_reset_f32(mc_cdobc_pid_f32_t *pid,
                                   float omega_m_rad_s);

/* v_q = sat(c_qd omega + kp e + I - kd (omega_k - omega_{k-1}) / Ts),
 * e = omega* - omega; backward-Euler integrator with conditional
 * integration (not while saturated in the direction of e). Non-finite:
 * MC_ERR_NONFINITE, state untouched. Interrupt context: yes. */
mc_status_t mc_cdobc_pid_step_f32(mc_cdobc_pid_f32_t *pid, float omega_m_rad_s,
                                  float omega_ref_rad_s, float *v_q_V);

#endif /* MC_CDOBC_H */
