/* Performance metrics of a sampled response; definitions in sim/metrics.h. */
#include "sim/metrics.h"

#include <math.h>
#include <stdbool.h>

#define RISE_LOW_LEVEL  0.1
#define RISE_HIGH_LEVEL 0.9

const char *sim_metrics_status_str(sim_metrics_status_t status)
{
    switch (status) {
    case SIM_METRICS_OK: return "ok";
    case SIM_METRICS_ERR_ARGUMENT: return "invalid argument";
    case SIM_METRICS_ERR_EMPTY: return "no sample in the window";
    case SIM_METRICS_ERR_ZERO_STEP: return "zero step amplitude or denominator";
    case SIM_METRICS_ERR_NOT_REACHED: return "level never reached";
    }
    return "unknown status";
}

/* Signal present, finite, with strictly increasing time; ref (if given) finite. */
static bool signal_valid(const sim_signal_t *sig, const double *ref)
{
    if (sig == NULL || sig->t == NULL || sig->y == NULL || sig->n == 0) {
        return false;
    }
    for (size_t k = 0; k < sig->n; k++) {
        if (!isfinite(sig->t[k]) || !isfinite(sig->y[k])) {
            return false;
        }
        if (ref != NULL && !isfinite(ref[k])) {
            return false;
        }
        if (k > 0 && !(sig->t[k] > sig->t[k - 1])) {
            return false;
        }
    }
    return true;
}

/* Index range [*first, *last] of the samples with t0_s <= t <= t1_s. */
static sim_metrics_status_t window(const sim_signal_t *sig, const double *ref, double t0_s,
                                   double t1_s, size_t *first, size_t *last)
{
    if (!signal_valid(sig, ref) || isnan(t0_s) || isnan(t1_s) || t0_s > t1_s) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    size_t k = 0;
    while (k < sig->n && sig->t[k] < t0_s) {
        k++;
    }
    if (k == sig->n || sig->t[k] > t1_s) {
        return SIM_METRICS_ERR_EMPTY;
    }
    *first = k;
    while (k + 1 < sig->n && sig->t[k + 1] <= t1_s) {
        k++;
    }
    *last = k;
    return SIM_METRICS_OK;
}

/* Step valid and the index of the first sample at or after the step. */
static sim_metrics_status_t step_start(const sim_signal_t *sig, const sim_step_t *step,
                                       size_t *first)
{
    if (step == NULL || !isfinite(step->t_step_s) || !isfinite(step->y_initial) ||
        !isfinite(step->y_final)) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    size_t last;
    sim_metrics_status_t st = window(sig, NULL, step->t_step_s, INFINITY, first, &last);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    if (step->y_final == step->y_initial) {
        return SIM_METRICS_ERR_ZERO_STEP;
    }
    return SIM_METRICS_OK;
}

/* Progress of sample k through the step: 0 at y_initial, 1 at y_final. */
static double progress(const sim_signal_t *sig, const sim_step_t *step, size_t k)
{
    return (sig->y[k] - step->y_initial) / (step->y_final - step->y_initial);
}

/* Time at which the progress first reaches `level` (at or after sample `first`). */
static sim_metrics_status_t first_crossing(const sim_signal_t *sig, const sim_step_t *step,
                                           size_t first, double level, double *t_cross_s)
{
    for (size_t k = first; k < sig->n; k++) {
        double p = progress(sig, step, k);
        if (p >= level) {
            if (k == first) {
                *t_cross_s = sig->t[k];
            } else {
                double p_prev = progress(sig, step, k - 1);
                double frac = (level - p_prev) / (p - p_prev);
                *t_cross_s = sig->t[k - 1] + frac * (sig->t[k] - sig->t[k - 1]);
            }
            return SIM_METRICS_OK;
        }
    }
    return SIM_METRICS_ERR_NOT_REACHED;
}

sim_metrics_status_t sim_metrics_rise_time(const sim_signal_t *sig, const sim_step_t *step,
                                           double *rise_time_s)
{
    size_t first;
    if (rise_time_s == NULL) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    sim_metrics_status_t st = step_start(sig, step, &first);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    double t_low;
    double t_high;
    st = first_crossing(sig, step, first, RISE_LOW_LEVEL, &t_low);
    if (st == SIM_METRICS_OK) {
        st = first_crossing(sig, step, first, RISE_HIGH_LEVEL, &t_high);
    }
    if (st == SIM_METRICS_OK) {
        *rise_time_s = t_high - t_low;
    }
    return st;
}

sim_metrics_status_t sim_metrics_settling_time(const sim_signal_t *sig, const sim_step_t *step,
                                               double band, double *settling_time_s)
{
    size_t first;
    if (settling_time_s == NULL || !(band > 0.0 && band < 1.0)) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    sim_metrics_status_t st = step_start(sig, step, &first);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    /* Deviation from the final value in units of the step amplitude. */
    const double amplitude = fabs(step->y_final - step->y_initial);
    size_t k = sig->n;
    while (k > first && fabs(sig->y[k - 1] - step->y_final) / amplitude <= band) {
        k--;
    }
    if (k == first) { /* inside the band from the first sample on */
        *settling_time_s = sig->t[first] - step->t_step_s;
        return SIM_METRICS_OK;
    }
    size_t out = k - 1; /* last sample outside the band */
    if (out + 1 == sig->n) {
        return SIM_METRICS_ERR_NOT_REACHED;
    }
    double d_out = (sig->y[out] - step->y_final) / amplitude;
    double d_in = (sig->y[out + 1] - step->y_final) / amplitude;
    double edge = d_out > 0.0 ? band : -band;
    double frac = (d_out - edge) / (d_out - d_in);
    double t_cross = sig->t[out] + frac * (sig->t[out + 1] - sig->t[out]);
    *settling_time_s = t_cross - step->t_step_s;
    return SIM_METRICS_OK;
}

sim_metrics_status_t sim_metrics_overshoot(const sim_signal_t *sig, const sim_step_t *step,
                                           double *overshoot_percent)
{
    size_t first;
    if (overshoot_percent == NULL) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    sim_metrics_status_t st = step_start(sig, step, &first);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    double max_excess = 0.0; /* progress beyond 1, never negative */
    for (size_t k = first; k < sig->n; k++) {
        double excess = progress(sig, step, k) - 1.0;
        if (excess > max_excess) {
            max_excess = excess;
        }
    }
    *overshoot_percent = 100.0 * max_excess;
    return SIM_METRICS_OK;
}

sim_metrics_status_t sim_metrics_offset_error(const sim_signal_t *sig, const double *ref,
                                              double t0_s, double t1_s, double *offset_error)
{
    size_t first;
    size_t last;
    if (ref == NULL || offset_error == NULL) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    sim_metrics_status_t st = window(sig, ref, t0_s, t1_s, &first, &last);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    double sum = 0.0;
    for (size_t k = first; k <= last; k++) {
        sum += sig->y[k] - ref[k];
    }
    *offset_error = sum / (double)(last - first + 1);
    return SIM_METRICS_OK;
}

sim_metrics_status_t sim_metrics_fluctuation(const sim_signal_t *sig, double t0_s, double t1_s,
                                             double *fluctuation, double *fluctuation_rate_percent)
{
    size_t first;
    size_t last;
    sim_metrics_status_t st = window(sig, NULL, t0_s, t1_s, &first, &last);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    double y_min = sig->y[first];
    double y_max = sig->y[first];
    for (size_t k = first + 1; k <= last; k++) {
        y_min = fmin(y_min, sig->y[k]);
        y_max = fmax(y_max, sig->y[k]);
    }
    if (fluctuation_rate_percent != NULL) {
        if (y_max + y_min == 0.0) {
            return SIM_METRICS_ERR_ZERO_STEP;
        }
        *fluctuation_rate_percent = (y_max - y_min) / fabs(y_max + y_min) * 100.0;
    }
    if (fluctuation != NULL) {
        *fluctuation = (y_max - y_min) / 2.0;
    }
    return SIM_METRICS_OK;
}

sim_metrics_status_t sim_metrics_rms_error(const sim_signal_t *sig, const double *ref, double t0_s,
                                           double t1_s, double *rms_error)
{
    size_t first;
    size_t last;
    if (ref == NULL || rms_error == NULL) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    sim_metrics_status_t st = window(sig, ref, t0_s, t1_s, &first, &last);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    double sum_sq = 0.0;
    for (size_t k = first; k <= last; k++) {
        double e = sig->y[k] - ref[k];
        sum_sq += e * e;
    }
    *rms_error = sqrt(sum_sq / (double)(last - first + 1));
    return SIM_METRICS_OK;
}

sim_metrics_status_t sim_metrics_max_dip(const sim_signal_t *sig, const double *ref,
                                         double t_step_s, double window_s, double *max_dip,
                                         double *dip_time_s)
{
    size_t first;
    size_t last;
    if (ref == NULL || max_dip == NULL || !isfinite(t_step_s) || !(window_s >= 0.0)) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    sim_metrics_status_t st = window(sig, ref, t_step_s, t_step_s + window_s, &first, &last);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    size_t k_max = first;
    for (size_t k = first + 1; k <= last; k++) {
        if (fabs(sig->y[k] - ref[k]) > fabs(sig->y[k_max] - ref[k_max])) {
            k_max = k;
        }
    }
    *max_dip = fabs(sig->y[k_max] - ref[k_max]);
    if (dip_time_s != NULL) {
        *dip_time_s = sig->t[k_max];
    }
    return SIM_METRICS_OK;
}

sim_metrics_status_t sim_metrics_recovery_time(const sim_signal_t *sig, const double *ref,
                                               double t_step_s, double window_s, double band,
                                               double *recovery_time_s, double *settled)
{
    size_t first;
    size_t last;
    if (ref == NULL || recovery_time_s == NULL || !isfinite(t_step_s) || !(window_s > 0.0) ||
        !isfinite(window_s) || !(band > 0.0) || !isfinite(band)) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    const double t_end = t_step_s + window_s;
    sim_metrics_status_t st = window(sig, ref, t_step_s, t_end, &first, &last);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    /* The settled error: mean over the last quarter of the window. */
    size_t q_first;
    size_t q_last;
    st = window(sig, ref, t_end - SIM_METRICS_RECOVERY_SETTLED_FRACTION * window_s, t_end, &q_first,
                &q_last);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    double sum = 0.0;
    for (size_t k = q_first; k <= q_last; k++) {
        sum += sig->y[k] - ref[k];
    }
    const double e_inf = sum / (double)(q_last - q_first + 1u);
    /* The last sample outside the band. */
    size_t k_out = last + 1u;
    for (size_t k = last + 1u; k-- > first;) {
        if (fabs(sig->y[k] - ref[k] - e_inf) > band) {
            k_out = k;
            break;
        }
    }
    if (k_out == last) {
        return SIM_METRICS_ERR_NOT_REACHED;
    }
    double t_in = t_step_s; /* never outside: recovered at once */
    if (k_out <= last) {
        const double d0 = sig->y[k_out] - ref[k_out] - e_inf;
        const double d1 = sig->y[k_out + 1u] - ref[k_out + 1u] - e_inf;
        const double edge = d0 > 0.0 ? band : -band; /* the side it was outside on */
        t_in = sig->t[k_out] + (sig->t[k_out + 1u] - sig->t[k_out]) * (d0 - edge) / (d0 - d1);
    }
    *recovery_time_s = t_in - t_step_s;
    if (settled != NULL) {
        *settled = e_inf;
    }
    return SIM_METRICS_OK;
}

sim_metrics_status_t sim_metrics_peak_abs(const sim_signal_t *sig, double t0_s, double t1_s,
                                          double *peak_abs)
{
    size_t first;
    size_t last;
    if (peak_abs == NULL) {
        return SIM_METRICS_ERR_ARGUMENT;
    }
    sim_metrics_status_t st = window(sig, NULL, t0_s, t1_s, &first, &last);
    if (st != SIM_METRICS_OK) {
        return st;
    }
    double peak = 0.0;
    for (size_t k = first; k <= last; k++) {
        peak = fmax(peak, fabs(sig->y[k]));
    }
    *peak_abs = peak;
    return SIM_METRICS_OK;
}
