/*
 * Performance metrics of a sampled response (host only, double precision).
 *
 * Every function works on plain arrays: t[] (s, strictly increasing), y[]
 * (the measured signal) and, where a reference is involved, ref[] (same unit
 * as y). Windows [t0_s, t1_s] are closed: a sample belongs to the window when
 * t0_s <= t[k] <= t1_s. Crossing times are interpolated linearly between the
 * two samples that bracket the crossing.
 *
 * A metric that cannot be computed returns an error code and leaves *out
 * untouched; it never returns a made-up number.
 *
 * Definitions:
 *  - step response (a step of the reference at t_step_s from y_initial to
 *    y_final, amplitude D = y_final - y_initial):
 *      rise time      time from the first crossing of y_initial + 0.1 D to the
 *                     first crossing of y_initial + 0.9 D (10-90 %);
 *      settling time  time from t_step_s until |y - y_final| <= band * |D|
 *                     holds up to the end of the record (default band 2 %);
 *      overshoot      100 * max((y - y_final) / D) after t_step_s, 0 if the
 *                     response never passes y_final (percent of |D|).
 *  - steady state, over a window (paper 002, Section IV-A, the two indexes
 *    defined after Table I, also used in Table II):
 *      offset error     mean(y - ref) (paper 002 Tables I-II "Offset error";
 *                       negative when y stays below the reference);
 *      fluctuation      (y_max - y_min) / 2;
 *      fluctuation rate (y_max - y_min) / |y_max + y_min| * 100 (percent).
 *  - tracking: RMS of (y - ref) over a window (uniform sample mean).
 *  - load step (paper 001 Section 5 dips, paper 002 Table II "Decrease"):
 *      dip  max |y - ref| in [t_step_s, t_step_s + window_s], with its time.
 *  - recovery after a load step (paper 002 Table II "Recovery time"; the
 *    paper does not define it, this is the bench's reading): the time from
 *    t_step_s until |(y - ref) - e_inf| <= band holds for the rest of
 *    [t_step_s, t_step_s + window_s], with e_inf the mean of y - ref over
 *    the last quarter of that window (the error the response settles to:
 *    a controller left with an offset, like the paper's HDOBC, still has a
 *    recovery time). The crossing back into the band is interpolated; a
 *    response never outside the band recovers at once (0).
 *  - peak: max |y| over a window (currents, voltages).
 */
#ifndef SIM_METRICS_H
#define SIM_METRICS_H

#include <stddef.h>

typedef enum {
    SIM_METRICS_OK = 0,
    SIM_METRICS_ERR_ARGUMENT,   /* NULL array, n == 0, bad window/band, non-finite
                                   argument or time not strictly increasing */
    SIM_METRICS_ERR_EMPTY,      /* no sample inside the requested window */
    SIM_METRICS_ERR_ZERO_STEP,  /* step amplitude is zero (or denominator is zero) */
    SIM_METRICS_ERR_NOT_REACHED /* the response never reaches the level/band */
} sim_metrics_status_t;

/* A sampled signal: n samples of t[] (s) and y[]. */
typedef struct {
    const double *t;
    const double *y;
    size_t n;
} sim_signal_t;

/* A reference step: the reference changes at t_step_s from y_initial to y_final. */
typedef struct {
    double t_step_s;
    double y_initial;
    double y_final;
} sim_step_t;

#define SIM_METRICS_DEFAULT_SETTLING_BAND 0.02 /* 2 % of the step amplitude */

/* Short text for a status code ("ok", "empty window", ...). */
const char *sim_metrics_status_str(sim_metrics_status_t status);

sim_metrics_status_t sim_metrics_rise_time(const sim_signal_t *sig, const sim_step_t *step,
                                           double *rise_time_s);

/* band: relative half-width of the band, in (0, 1) (0.02 for 2 %). */
sim_metrics_status_t sim_metrics_settling_time(const sim_signal_t *sig, const sim_step_t *step,
                                               double band, double *settling_time_s);

sim_metrics_status_t sim_metrics_overshoot(const sim_signal_t *sig, const sim_step_t *step,
                                           double *overshoot_percent);

/* Mean of (y - ref) over [t0_s, t1_s]. */
sim_metrics_status_t sim_metrics_offset_error(const sim_signal_t *sig, const double *ref,
                                              double t0_s, double t1_s, double *offset_error);

/* Fluctuation (y_max - y_min) / 2 and fluctuation rate in percent over [t0_s, t1_s]
 * (paper 002, Section IV-A). Either output may be NULL. The rate fails with
 * SIM_METRICS_ERR_ZERO_STEP when y_max + y_min == 0 (then neither is written). */
sim_metrics_status_t sim_metrics_fluctuation(const sim_signal_t *sig, double t0_s, double t1_s,
                                             double *fluctuation, double *fluctuation_rate_percent);

/* RMS of (y - ref) over [t0_s, t1_s]. */
sim_metrics_status_t sim_metrics_rms_error(const sim_signal_t *sig, const double *ref, double t0_s,
                                           double t1_s, double *rms_error);

/* Largest |y - ref| in [t_step_s, t_step_s + window_s]; *dip_time_s (may be NULL)
 * receives the time of that sample. */
sim_metrics_status_t sim_metrics_max_dip(const sim_signal_t *sig, const double *ref,
                                         double t_step_s, double window_s, double *max_dip,
                                         double *dip_time_s);

/* Recovery time after a load step (see above); band > 0 in y's unit. *settled
 * (may be NULL) receives e_inf. SIM_METRICS_ERR_NOT_REACHED when the last
 * sample of the window is outside the band. */
#define SIM_METRICS_RECOVERY_SETTLED_FRACTION 0.25
sim_metrics_status_t sim_metrics_recovery_time(const sim_signal_t *sig, const double *ref,
                                               double t_step_s, double window_s, double band,
                                               double *recovery_time_s, double *settled);

/* Largest |y| over [t0_s, t1_s]. */
sim_metrics_status_t sim_metrics_peak_abs(const sim_signal_t *sig, double t0_s, double t1_s,
                                          double *peak_abs);

#endif /* SIM_METRICS_H */
