/*
 * Phases of a run, for the peaks of the report: the start (idle, offset
 * calibration, sensorless alignment), the hold (state run before the
 * profile starts at time_offset_s: the drive holds the profile's first
 * value), the profile (state run from time_offset_s on: the reference the
 * scenario is about) and after a fault (state fault, PWM off). The
 * alignment drives the largest currents of a sensorless start, its current
 * decays during the hold, and the voltage after a fault is the rectified
 * back-EMF; none of them says how the controller tracks its reference, so
 * each phase has its own peaks.
 *
 * A sample at t_k belongs to the phase of the state the drive was in while
 * the plant moved to it, the state after the previous ISR (IDLE for the
 * first sample): the over-current sample that trips a fault counts in the
 * phase it happened in, the coasting that follows in the fault phase.
 */
#ifndef PMSM_SIM_RUN_PHASES_H
#define PMSM_SIM_RUN_PHASES_H

#include <stdint.h>

#include "mc/drive_io.h"
#include "plant.h"

typedef enum {
    RUN_PHASE_START,
    RUN_PHASE_HOLD,
    RUN_PHASE_PROFILE,
    RUN_PHASE_FAULT,
    RUN_PHASE_COUNT
} run_phase_t;

typedef struct {
    uint64_t samples;           /* 0: the run never reached the phase */
    double t_first_s, t_last_s; /* simulated time of its first and last sample */
    double i_peak_A;            /* max true |i_a|, |i_b|, |i_c| */
    double v_peak_V;            /* max |v_a|, |v_b|, |v_c| (period means) */
} run_phase_stats_t;

/* The phase of a sample at t_s (simulated) after the drive was in state;
 * the profile starts at profile_start_s (the scenario's time_offset_s). */
run_phase_t run_phase_of(mc_state_t state, double t_s, double profile_start_s);

/* "start", "hold", "profile", "fault": the JSON keys. */
const char *run_phase_name(run_phase_t phase);

/* What the phase is, for the table. */
const char *run_phase_meaning(run_phase_t phase);

/* Sample p enters the phase of state_before (see above). */
void run_phases_record(run_phase_stats_t phases[RUN_PHASE_COUNT], mc_state_t state_before,
                       double profile_start_s, const plant_true_state_t *p);

#endif /* PMSM_SIM_RUN_PHASES_H */
