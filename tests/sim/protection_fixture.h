/*
 * Closed-loop protection runs: a drive on the plant, a fault injected at a
 * known time, stepped until a fault latches (or a time limit), with what
 * the acceptance of the protection work asks of every case recorded from
 * the TRUE plant state: the first fault's bits and time, whether the
 * inverter stopped in the same period, and the true phase current after it
 * first exceeded i_max (its peak and how long it stayed above).
 */
#ifndef PROTECTION_FIXTURE_H
#define PROTECTION_FIXTURE_H

#include <stdbool.h>
#include <stdint.h>

#include "sim_fixture.h"

/* The command of sample time t (s). */
typedef mc_command_t (*prot_command_fn)(double t_s);

typedef struct {
    uint32_t first_fault;        /* the first faulting ISR's bits (0: none) */
    double t_fault_s;            /* its sample time, or -1 */
    bool outputs_off_at_fault;   /* the inverter did not switch in the period
                                    that starts at the fault's sample */
    double t_run_s;              /* first RUN sample */
    double i_peak_A;             /* max true |i_abc| over the run */
    double i_peak_watch_A;       /* max true |i_abc| from t_watch_s on */
    double t_first_over_i_max_s; /* first sample with max |i_abc| > i_max,
                                    or -1 */
    double i_peak_after_i_max_A; /* max true |i_abc| from then on */
    double t_over_i_max_s;       /* total time with max |i_abc| > i_max */
    double omega_max_abs_rad_s;  /* max true |omega_m| before the fault */
    double v_dc_max_V;           /* max true link voltage over the run */
} prot_result_t;

/* Step e with cmd(t) until a fault latches and then t_after_s more (the
 * post-fault physics), or until t_end_s. i_max_A: the limit whose
 * crossing is timed; t_watch_s: where i_peak_watch_A starts (the
 * injection). */
prot_result_t prot_run(sim_engine_t *e, prot_command_fn cmd, double t_end_s, double t_after_s,
                       double i_max_A, double t_watch_s);

/* prot_fixed_cmd returns prot_command whatever the time (set it before
 * the run). */
extern mc_command_t prot_command;
mc_command_t prot_fixed_cmd(double t_s);

/* The paper-001 benchmark's speed profile (test_p001_bench.h), enabled. */
mc_command_t prot_bench_cmd(double t_s);

/* Called with every sample of prot_run_observed (ctx: the caller's). */
typedef void (*prot_observer_fn)(const sim_trace_sample_t *s, void *ctx);

/* prot_run, and obs(sample, ctx) after every step. */
prot_result_t prot_run_observed(sim_engine_t *e, prot_command_fn cmd, double t_end_s,
                                double t_after_s, double i_max_A, double t_watch_s,
                                prot_observer_fn obs, void *ctx);

/* Add an injection (asserts it is accepted). */
void prot_inject(sim_engine_t *e, const sim_injection_t *inj);

/* Print the result with a label (cmocka print_message). */
void prot_print(const char *label, const prot_result_t *r);

#endif /* PROTECTION_FIXTURE_H */
