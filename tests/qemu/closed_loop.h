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
 * fw_self_max_instr (the firmware's own deadline measurement,
 * hal_cycle_counter: instructions from its first to its last counter read).
 */
#ifndef QEMU_CLOSED_LOOP_H
#define QEMU_CLOSED_LOOP_H

#include <stdint.h>

#include "isr_meter.h"
#include "sim_engine.h"

typedef struct {
    sim_engine_t engine;
    const sim_trace_sample_t *s; /* the latest sample */
    isr_stats_t calib, align, run_fast, run_slow;
    double t_run_s; /* time of the first RUN sample; < 0 before */
    float fw_cost_max_s;
} qemu_loop_t;

/* The plant's defaults (plant_config_default: paper-001 motor, 48 V,
 * 20 kHz, ideal sensors), the fast setting PLANT_SUBSTEPS_FAST and a load
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

/* One period: step, state changes, fault check, ISR statistics, t_run_s.
 * 0 or main's failure status. */
int qemu_loop_step(qemu_loop_t *l, const mc_command_t *cmd);

/* The common checkpoints and the statistics. 0 if RUN was reached and no
 * ISR overran, else main's failure status. */
int qemu_loop_finish(const qemu_loop_t *l);

#endif /* QEMU_CLOSED_LOOP_H */
