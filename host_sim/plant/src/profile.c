#include "profile.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "sim_rng.h"

#define TWO_PI 6.283185307179586476925286766559

void sim_profile_clear(sim_profile_t *p)
{
    memset(p, 0, sizeof *p);
}

void sim_profile_set_constant(sim_profile_t *p, double value)
{
    sim_profile_clear(p);
    p->points[0].t_s = 0.0;
    p->points[0].value = value;
    p->n_points = 1u;
}

static int fail(const char **msg, int code, const char *text)
{
    if (msg != NULL) {
        *msg = text;
    }
    return code;
}

static int validate_points(const sim_profile_t *p, const char **msg)
{
    if (p->n_points > SIM_PROFILE_MAX_POINTS) {
        return fail(msg, SIM_PROFILE_ERR_TOO_MANY,
                    "profile: more breakpoints than SIM_PROFILE_MAX_POINTS");
    }
    for (uint32_t i = 0; i < p->n_points; ++i) {
        if (!isfinite(p->points[i].t_s) || !isfinite(p->points[i].value)) {
            return fail(msg, SIM_PROFILE_ERR_NONFINITE,
                        "profile: breakpoint time or value is not finite");
        }
        if (i > 0u && p->points[i].t_s < p->points[i - 1u].t_s) {
            return fail(msg, SIM_PROFILE_ERR_TIME_ORDER,
                        "profile: breakpoint times must be non-decreasing");
        }
    }
    return SIM_PROFILE_OK;
}

static int validate_sines(const sim_profile_t *p, const char **msg)
{
    if (p->n_sines > SIM_PROFILE_MAX_SINES) {
        return fail(msg, SIM_PROFILE_ERR_TOO_MANY,
                    "profile: more sinusoids than SIM_PROFILE_MAX_SINES");
    }
    for (uint32_t i = 0; i < p->n_sines; ++i) {
        const sim_profile_sine_t *s = &p->sines[i];
        if (!isfinite(s->amplitude) || !isfinite(s->freq_Hz) || !isfinite(s->phase_rad) ||
            !isfinite(s->t_start_s)) {
            return fail(msg, SIM_PROFILE_ERR_NONFINITE, "profile: sinusoid field is not finite");
        }
        if (s->freq_Hz < 0.0) {
            return fail(msg, SIM_PROFILE_ERR_NEGATIVE, "profile: sinusoid frequency must be >= 0");
        }
    }
    return SIM_PROFILE_OK;
}

static int validate_poly_noise(const sim_profile_t *p, const char **msg)
{
    if (p->poly.n_coeffs > SIM_PROFILE_MAX_POLY_COEFFS) {
        return fail(msg, SIM_PROFILE_ERR_TOO_MANY,
                    "profile: more polynomial coefficients than SIM_PROFILE_MAX_POLY_COEFFS");
    }
    for (uint32_t k = 0; k < p->poly.n_coeffs; ++k) {
        if (!isfinite(p->poly.coeffs[k])) {
            return fail(msg, SIM_PROFILE_ERR_NONFINITE,
                        "profile: polynomial coefficient is not finite");
        }
    }
    if (!isfinite(p->poly.t_start_s)) {
        return fail(msg, SIM_PROFILE_ERR_NONFINITE, "profile: polynomial start time is not finite");
    }
    if (!isfinite(p->noise.rms) || !isfinite(p->noise.cutoff_Hz)) {
        return fail(msg, SIM_PROFILE_ERR_NONFINITE, "profile: noise rms or cutoff is not finite");
    }
    if (p->noise.rms < 0.0 || p->noise.cutoff_Hz < 0.0) {
        return fail(msg, SIM_PROFILE_ERR_NEGATIVE, "profile: noise rms and cutoff must be >= 0");
    }
    if (p->noise.rms > 0.0 && p->noise.cutoff_Hz <= 0.0) {
        return fail(msg, SIM_PROFILE_ERR_NOISE_CUTOFF,
                    "profile: noise with rms > 0 needs cutoff_Hz > 0");
    }
    return SIM_PROFILE_OK;
}

int sim_profile_validate(const sim_profile_t *p, const char **msg)
{
    if (p == NULL) {
        return fail(msg, SIM_PROFILE_ERR_NULL, "profile: NULL pointer");
    }
    int rc = validate_points(p, msg);
    if (rc == SIM_PROFILE_OK) {
        rc = validate_sines(p, msg);
    }
    if (rc == SIM_PROFILE_OK) {
        rc = validate_poly_noise(p, msg);
    }
    if (rc == SIM_PROFILE_OK && msg != NULL) {
        *msg = "ok";
    }
    return rc;
}

/* Index of the last breakpoint with t_i <= t, or -1 if t < t_0. */
static int last_point_at_or_before(const sim_profile_t *p, double t_s)
{
    int i = -1;
    while ((uint32_t)(i + 1) < p->n_points && p->points[i + 1].t_s <= t_s) {
        ++i;
    }
    return i;
}

/* The linear piece active at t_piece_s, evaluated (extended) at t_s. */
static double points_eval(const sim_profile_t *p, double t_s, double t_piece_s)
{
    if (p->n_points == 0u) {
        return 0.0;
    }
    const int i = last_point_at_or_before(p, t_piece_s);
    if (i < 0) {
        return p->points[0].value;
    }
    if ((uint32_t)i + 1u == p->n_points) {
        return p->points[i].value;
    }
    const sim_profile_point_t *a = &p->points[i];
    const sim_profile_point_t *b = &p->points[i + 1];
    /* b->t_s > t_piece_s >= a->t_s, so the span is positive */
    return a->value + (b->value - a->value) * (t_s - a->t_s) / (b->t_s - a->t_s);
}

static double points_slope(const sim_profile_t *p, double t_s)
{
    const int i = last_point_at_or_before(p, t_s);
    if (i < 0 || (uint32_t)i + 1u >= p->n_points) {
        return 0.0;
    }
    const sim_profile_point_t *a = &p->points[i];
    const sim_profile_point_t *b = &p->points[i + 1];
    return (b->value - a->value) / (b->t_s - a->t_s);
}

/* One noise tone: frequency stratified in ((k)/N, (k+1)/N] * cutoff. */
static void noise_tone(const sim_profile_noise_t *n, uint32_t k, double *w_rad_s, double *phase)
{
    const double u_f = sim_rng_unit(sim_rng_hash(n->seed, 2u * (uint64_t)k));
    const double u_p = sim_rng_unit(sim_rng_hash(n->seed, 2u * (uint64_t)k + 1u));
    const double f_hz = n->cutoff_Hz * ((double)k + 1.0 - u_f) / (double)SIM_PROFILE_NOISE_TONES;
    *w_rad_s = TWO_PI * f_hz;
    *phase = TWO_PI * u_p;
}

static double noise_amplitude(const sim_profile_noise_t *n)
{
    return n->rms * sqrt(2.0 / (double)SIM_PROFILE_NOISE_TONES);
}

double sim_profile_eval(const sim_profile_t *p, double t_s)
{
    return sim_profile_eval_on_piece(p, t_s, t_s);
}

double sim_profile_eval_on_piece(const sim_profile_t *p, double t_s, double t_piece_s)
{
    double v = points_eval(p, t_s, t_piece_s);
    for (uint32_t i = 0; i < p->n_sines; ++i) {
        const sim_profile_sine_t *s = &p->sines[i];
        if (t_piece_s >= s->t_start_s) {
            v += s->amplitude * sin(TWO_PI * s->freq_Hz * (t_s - s->t_start_s) + s->phase_rad);
        }
    }
    if (p->poly.n_coeffs > 0u && t_piece_s >= p->poly.t_start_s) {
        const double tau = t_s - p->poly.t_start_s;
        double acc = 0.0;
        for (uint32_t k = p->poly.n_coeffs; k-- > 0u;) {
            acc = acc * tau + p->poly.coeffs[k];
        }
        v += acc;
    }
    if (p->noise.rms > 0.0) {
        const double a = noise_amplitude(&p->noise);
        for (uint32_t k = 0; k < SIM_PROFILE_NOISE_TONES; ++k) {
            double w, ph;
            noise_tone(&p->noise, k, &w, &ph);
            v += a * sin(w * t_s + ph);
        }
    }
    return v;
}

bool sim_profile_linear_on(const sim_profile_t *p, double t_a_s, double t_b_s, double *value,
                           double *slope)
{
    if (p->n_sines > 0u || p->poly.n_coeffs > 0u || p->noise.rms > 0.0 ||
        last_point_at_or_before(p, t_a_s) != last_point_at_or_before(p, t_b_s)) {
        return false;
    }
    *value = points_eval(p, t_a_s, t_a_s);
    *slope = (p->n_points == 0u) ? 0.0 : points_slope(p, t_a_s);
    return true;
}

double sim_profile_deriv(const sim_profile_t *p, double t_s)
{
    double d = points_slope(p, t_s);
    for (uint32_t i = 0; i < p->n_sines; ++i) {
        const sim_profile_sine_t *s = &p->sines[i];
        if (t_s >= s->t_start_s) {
            const double w = TWO_PI * s->freq_Hz;
            d += s->amplitude * w * cos(w * (t_s - s->t_start_s) + s->phase_rad);
        }
    }
    if (p->poly.n_coeffs > 1u && t_s >= p->poly.t_start_s) {
        const double tau = t_s - p->poly.t_start_s;
        double acc = 0.0;
        for (uint32_t k = p->poly.n_coeffs; k-- > 1u;) {
            acc = acc * tau + (double)k * p->poly.coeffs[k];
        }
        d += acc;
    }
    if (p->noise.rms > 0.0) {
        const double a = noise_amplitude(&p->noise);
        for (uint32_t k = 0; k < SIM_PROFILE_NOISE_TONES; ++k) {
            double w, ph;
            noise_tone(&p->noise, k, &w, &ph);
            d += a * w * cos(w * t_s + ph);
        }
    }
    return d;
}
