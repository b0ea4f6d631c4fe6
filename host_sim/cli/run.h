/*
 * Closed-loop run of a scenario: engine (plant + host HAL + firmware) stepped
 * once per PWM period with the scenario's reference, fault injections from
 * the scenario, a metric series kept in memory and an optional CSV trace.
 *
 * With a CAN bridge (run_options_t.can) the drive gets its CAN node and its
 * commands come over CAN, not from the reference: the frames that reached
 * the socket before the step loop are dropped (hal_socketcan_flush), the
 * bridge is pumped (hal_socketcan_pump) before every step and once after
 * the last, and no metric series is kept (the metrics against the
 * reference do not apply).
 *
 * Realtime (run_options_t.realtime): period k is due at wall time
 * t0 + k Ts (t0: the start of the step loop, CLOCK_MONOTONIC). The loop
 * sleeps (clock_nanosleep, TIMER_ABSTIME) at the start of each batch of
 * RUN_RT_BATCH_S of periods while it is more than RUN_RT_LEAD_S ahead of
 * the batch's due time, so the simulation leads wall time by at most about
 * RUN_RT_BATCH_S + RUN_RT_LEAD_S and a late wake-up costs no period. The
 * clock is read before every period: a period reached more than one period
 * after its due time (its simulated end already past in wall time) is a
 * missed period. A late loop is not resynchronised: it runs as fast as it
 * can until it is back on time, each period reached late counted. After
 * the last period the loop sleeps until the run's simulated end, so the
 * run lasts at least its simulated time.
 */
#ifndef PMSM_SIM_RUN_H
#define PMSM_SIM_RUN_H

#include <signal.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "mc/can_node.h"
#include "run_phases.h"
#include "sim/scenario.h"
#include "socketcan.h"

/* At most this many series samples are kept; longer runs keep one sample per
 * block of `stride` periods. */
#define RUN_SERIES_MAX_SAMPLES 4000000u

/* Realtime pacing: one sleep per batch of this much simulated time, and
 * the most a batch may start before its due time. */
#define RUN_RT_BATCH_S 1e-3
#define RUN_RT_LEAD_S  1e-3

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
    /* realtime (run_options_t.realtime) */
    bool realtime;
    uint32_t rt_batch_periods; /* periods per pacing batch */
    uint64_t missed_periods;   /* reached over one period after their due time */
    double max_late_s;         /* the latest a period was reached after its due
                                  time (0 when never late) */
    /* CAN (run_options_t.can): commands over CAN, no series kept */
    bool can;
    uint32_t can_node_id;
    char can_ifname[HAL_SOCKETCAN_IFNAME_MAX];
    mc_can_counters_t can_node;        /* the node's counters at the end */
    hal_socketcan_counters_t can_link; /* the bridge's */
} run_result_t;

typedef struct {
    FILE *csv;                         /* decimated trace (NULL: none) */
    bool keep_series;                  /* false: skip the metric series (bench) */
    bool progress;                     /* progress on stderr once a run takes > 2 s */
    const volatile sig_atomic_t *stop; /* non-zero: end the run early, as a
                                          failure (a signal; NULL: never) */
    bool realtime;                     /* pace the run to wall time */
    hal_socketcan_t *can;              /* an open bridge: the drive gets its CAN
                                          node on it (NULL: no CAN) */
    mc_can_node_config_t can_cfg;      /* the node's configuration (with can) */
} run_options_t;

/* Run s. Returns false with a message on an engine error (the result is then
 * incomplete). Free the series with run_result_free() in every case. */
bool run_scenario(const scenario_t *s, const run_options_t *opt, run_result_t *res, char *msg,
                  size_t msg_size);

void run_result_free(run_result_t *res);

#endif /* PMSM_SIM_RUN_H */
