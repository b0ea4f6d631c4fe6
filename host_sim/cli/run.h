/*
 * Closed-loop run of a scenario: engine (plant + host HAL + firmware) stepped
 * once per PWM period with the scenario's reference, fault injections from
 * the scenario, a metric series kept in memory and an optional CSV trace.
 */
#ifndef PMSM_SIM_RUN_H
#define PMSM_SIM_RUN_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "run_phases.h"
#include "sim/scenario.h"

/* At most this many series samples are kept; longer runs keep one sample per
 * block of `stride` periods. */
#define RUN_SERIES_MAX_SAMPLES 4000000u

/* Metric series, values in the reference's display unit (rpm, rad, A). */
typedef struct {
    double *t_s;
    double *y;               /* controlled variable of the TRUE plant state */
    double *ref;             /* reference given to the drive */
    double *angle_err_e_rad; /* controller's theta_e - true theta_e, wrapped to
                                [-pi, pi) */
    double *tau_load_hat_Nm; /* firmware load-torque estimate (0 without one) */
    double *tau_load_Nm;     /* true load torque */
    double *zero;            /* zeros: the reference of the error series */
    size_t n;
} run_series_t;

typedef struct {
    run_series_t series;
    uint32_t stride; /* periods per series sample */
    uint64_t periods;
    double sim_s;           /* simulated time */
    double wall_s;          /* wall-clock time of the step loop */
    double isr_cost_mean_s; /* host wall time per fast ISR */
    double isr_cost_max_s;
    uint32_t faults_latched;  /* mc_fault_t bits at the end */
    double first_fault_sim_s; /* simulated time of the first latched fault;
                                 NAN when none was latched */
    mc_state_t final_state;
    run_phase_stats_t phases[RUN_PHASE_COUNT]; /* peaks by phase of the run */
} run_result_t;

typedef struct {
    FILE *csv;                         /* decimated trace (NULL: none) */
    bool keep_series;                  /* false: skip the metric series (bench) */
    bool progress;                     /* progress on stderr once a run takes > 2 s */
    const volatile sig_atomic_t *stop; /* non-zero: end the run early, as a
                                          failure (a signal; NULL: never) */
} run_options_t;

/* Run s. Returns false with a message on an engine error (the result is then
 * incomplete). Free the series with run_result_free() in every case. */
bool run_scenario(const scenario_t *s, const run_options_t *opt, run_result_t *res, char *msg,
                  size_t msg_size);

void run_result_free(run_result_t *res);

#endif /* PMSM_SIM_RUN_H */
