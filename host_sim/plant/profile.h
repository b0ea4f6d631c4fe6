/*
 * profile.h - deterministic time profiles for the host simulator.
 *
 * A profile is a scalar function of time v(t) built as the SUM of four
 * optional parts, all stored in fixed-size arrays (no allocation):
 *
 *   1. piecewise-linear breakpoints (t_i, v_i), times non-decreasing.
 *      Before the first point v = v_0, after the last point v = v_last,
 *      linear interpolation in between. A step is two points with the same
 *      time; the profile is right-continuous (at t == t_i of a step the
 *      later point's value applies). A ramp is two points at different times.
 *      No points: this part is 0.
 *   2. sinusoids  a * sin(2*pi*f*(t - t_start) + phase), zero for t < t_start.
 *   3. a polynomial  sum_k c_k * (t - t_start)^k, zero for t < t_start.
 *   4. band-limited noise: a sum of SIM_PROFILE_NOISE_TONES sinusoids with
 *      seeded random phases and frequencies stratified over (0, cutoff_Hz]
 *      (tone k lies in (k, k+1] * cutoff/N), equal amplitudes so that the
 *      RMS over a long window is rms. Deterministic for a given seed and
 *      evaluable at any t (RK4 stages need that). rms == 0 disables it.
 *
 * Units are the caller's (N m for load torque, V for bus voltage, rad/s for
 * speed references...). Time is in seconds.
 *
 * Portable C11: no allocation, no stdio. Safe in interrupt context (pure).
 */
#ifndef SIM_PROFILE_H
#define SIM_PROFILE_H

#include <stdbool.h>
#include <stdint.h>

#define SIM_PROFILE_MAX_POINTS      32u
#define SIM_PROFILE_MAX_SINES       8u
#define SIM_PROFILE_MAX_POLY_COEFFS 6u /* c_0 .. c_5 */
#define SIM_PROFILE_NOISE_TONES     16u

typedef struct {
    double t_s;
    double value;
} sim_profile_point_t;

typedef struct {
    double amplitude;
    double freq_Hz;
    double phase_rad;
    double t_start_s; /* the sinusoid is 0 before this time */
} sim_profile_sine_t;

typedef struct {
    double coeffs[SIM_PROFILE_MAX_POLY_COEFFS]; /* c_k of (t - t_start)^k */
    uint32_t n_coeffs;                          /* 0 = no polynomial */
    double t_start_s;                           /* 0 before this time */
} sim_profile_poly_t;

typedef struct {
    double rms;       /* 0 = no noise */
    double cutoff_Hz; /* highest tone frequency, > 0 when rms > 0 */
    uint64_t seed;
} sim_profile_noise_t;

typedef struct {
    sim_profile_point_t points[SIM_PROFILE_MAX_POINTS];
    uint32_t n_points;
    sim_profile_sine_t sines[SIM_PROFILE_MAX_SINES];
    uint32_t n_sines;
    sim_profile_poly_t poly;
    sim_profile_noise_t noise;
} sim_profile_t;

typedef enum {
    SIM_PROFILE_OK = 0,
    SIM_PROFILE_ERR_NULL = -1,
    SIM_PROFILE_ERR_TOO_MANY = -2,    /* n_points / n_sines / n_coeffs too big */
    SIM_PROFILE_ERR_NONFINITE = -3,   /* NaN or Inf anywhere in use */
    SIM_PROFILE_ERR_TIME_ORDER = -4,  /* breakpoint times decreasing */
    SIM_PROFILE_ERR_NEGATIVE = -5,    /* negative frequency, rms or cutoff */
    SIM_PROFILE_ERR_NOISE_CUTOFF = -6 /* rms > 0 with cutoff_Hz == 0 */
} sim_profile_err_t;

/* All parts empty: v(t) = 0. */
void sim_profile_clear(sim_profile_t *p);

/* v(t) = value for all t (one breakpoint at t = 0, everything else empty). */
void sim_profile_set_constant(sim_profile_t *p, double value);

/* Check a profile. Returns SIM_PROFILE_OK or a negative sim_profile_err_t;
 * if msg is not NULL, *msg receives a static English sentence naming the
 * offending field (never NULL, "ok" on success). */
int sim_profile_validate(const sim_profile_t *p, const char **msg);

/* v(t). The profile must have passed sim_profile_validate(). */
double sim_profile_eval(const sim_profile_t *p, double t_s);

/* The smooth piece of the profile that is active at t_piece_s (its linear
 * breakpoint segment, the sines and polynomial started by then), evaluated
 * at t_s, which may lie outside that piece. sim_profile_eval(p, t) is
 * sim_profile_eval_on_piece(p, t, t). For integrators: the stages of one
 * step evaluated on the piece of the step's midpoint see a smooth
 * function, so a step that ends at a breakpoint (even when rounding of the
 * step times puts the breakpoint a few ulp inside it) keeps the order of
 * the method instead of dropping to first order. */
double sim_profile_eval_on_piece(const sim_profile_t *p, double t_s, double t_piece_s);

/* True when on [t_a_s, t_b_s] the profile is one linear function of time
 * as sim_profile_eval_on_piece sees it from pieces active in that span
 * (only breakpoints, the same segment active at t_a_s and t_b_s): then
 * v(t) = *value + *slope * (t - t_a_s) there, up to rounding. False with
 * sinusoids, a polynomial or noise (they are not linear). */
bool sim_profile_linear_on(const sim_profile_t *p, double t_a_s, double t_b_s, double *value,
                           double *slope);

/* dv/dt(t): slope of the piecewise-linear part (0 outside the breakpoints,
 * the right-hand slope at a breakpoint; a step contributes no impulse) plus
 * the exact derivatives of the sinusoids, polynomial and noise. */
double sim_profile_deriv(const sim_profile_t *p, double t_s);

#endif /* SIM_PROFILE_H */
