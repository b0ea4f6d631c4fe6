/*
 * The harness of the closed-loop QEMU images (p001_closed_loop.c,
 * p000_eeo_closed_loop.c, p002_cdobc_closed_loop.c): the plant
 * (host_sim/plant) and the real firmware run through host_sim/engine, one
 * sim_engine_step per PWM period; the harness prints the state changes,
 * stops on a latched fault, sorts the instruction count of every ISR
 * (isr_meter.h) by state and prints the common checkpoints at the end.
 *
 * Output (semihosting), parsed by run_qemu_test.py:
 *   CHECK <name> <value>   checkpoints and counts
 *   isr ...                instruction statistics
 * Common checkpoints: t_run_s (the first RUN sample), isr_overruns,
 * run_fast_max_instr, run_slow_max_instr, run_fast_count, run_slow_count,
 * run_fast_mean_instr, run_slow_mean_instr, run_max_instr, run_mean_instr
 * (all RUN ISRs), isr_meter_errors (isr_meter.h: 0), mc_app_bytes (the
 * drive's state, sizeof(mc_app_t)), fw_self_max_instr (the firmware's own
 * deadline measurement, hal_cycle_counter: instructions from its first to
 * its last counter read).
 * The drive runs as an MCU build would: timing.telemetry_every_isr off
 * (mc/timing.h), so the record the harness reads after an ISR may be an
 * earlier ISR's (isr_count tells).
 * RUN ISRs are the ISRs that start and end in RUN; "slow" ones ran the
 * decimated outer loop (the firmware's own flag, telemetry slow_loop_ran),
 * "fast" ones did not, among them every ISR that left the record as it
 * was (only a steady RUN ISR between slow ticks does).
 *
 * ISR report (for hal/qemu_m4/cycle_estimate.py; off in the images as
 * built): qemu_loop_report is in .data, so a tool can set it in a copy of
 * the ELF. With skip != UINT32_MAX, once `skip` RUN ISRs have run and the
 * drive is in RUN, the harness
 *   - if wait != 0: prints "ISR report: waiting" and reads one character
 *     from the semihosting console (SYS_READC; QEMU stops the core until
 *     the host sends it: the tool turns its trace on meanwhile),
 *   - calls qemu_loop_report_begin() (an empty function: a mark in an
 *     execution trace),
 *   - prints, for each of the next `count` ISRs,
 *       ISR <index> <instructions> <class>
 *     (index: 0-based count of sim_engine_step calls, one ISR each;
 *     instructions: isr_meter_last(); class: run_fast, run_slow, calib,
 *     align or other),
 *   - then, if stop != 0, ends the run (qemu_loop_step returns
 *     QEMU_LOOP_STOPPED).
 */
#ifndef QEMU_CLOSED_LOOP_H
#define QEMU_CLOSED_LOOP_H

#include <stdint.h>

#include "isr_meter.h"
#include "sim_engine.h"

typedef struct {
    uint32_t skip;  /* RUN ISRs before the report; UINT32_MAX: no report */
    uint32_t count; /* ISRs reported */
    uint32_t stop;  /* non-zero: end the run after the report */
    uint32_t wait;  /* non-zero: wait for a console character before it */
} qemu_loop_report_t;

extern volatile qemu_loop_report_t qemu_loop_report;

/* Status of qemu_loop_step when the run ends after the ISR report. */
#define QEMU_LOOP_STOPPED 3

/* The mark in the execution trace before the first reported ISR. */
void qemu_loop_report_begin(void);

typedef struct {
    sim_engine_t engine;
    const sim_trace_sample_t *s; /* the latest sample */
    isr_stats_t calib, align, run_fast, run_slow;
    double t_run_s; /* time of the first RUN sample; < 0 before */
    float fw_cost_max_s;
    uint32_t isr_index; /* ISRs so far (sim_engine_step calls) */
    uint32_t reported;  /* ISRs reported so far */
    int report_state;   /* 0 before, 1 during, 2 after the report */
} qemu_loop_t;

/* The plant's defaults (plant_config_default: paper-001 motor, 48 V,
 * 20 kHz, ideal sensors), the fast setting PLANT_SUBSTEPS_FAST, the
 * board's over-current comparators (inverter.overcurrent_comparator) and a load
 * torque step 0 -> tau_L_Nm at the absolute time t_load_s. */
void qemu_loop_plant_default(plant_config_t *pc, double t_load_s, double tau_L_Nm);

/* "CHECK <name> <value>" with `decimals` decimals. */
void qemu_loop_check(const char *name, double v, unsigned decimals);

/* "<what> at tb <tb> s: <v> <unit>" (tb with 2 decimals, v with
 * `decimals`): the images' periodic progress lines (printed only). */
void qemu_loop_line(const char *what, double tb, double v, unsigned decimals, const char *unit);

/* Print "FAIL: <why>"; returns 1 (main's status). */
int qemu_loop_fail(const char *why);

/* Print the title line, initialise the engine, print the meter's overhead.
 * 0 or main's failure status. */
int qemu_loop_init(qemu_loop_t *l, const char *title, const plant_config_t *pc,
                   const mc_config_t *fc);

/* One period: step, state changes, fault check, ISR statistics, t_run_s,
 * the ISR report. 0, main's failure status or QEMU_LOOP_STOPPED. */
int qemu_loop_step(qemu_loop_t *l, const mc_command_t *cmd);

/* The common checkpoints and the statistics. 0 if RUN was reached and no
 * ISR overran, else main's failure status. */
int qemu_loop_finish(const qemu_loop_t *l);

#endif /* QEMU_CLOSED_LOOP_H */
