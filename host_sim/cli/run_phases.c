/* Phases of a run and their peaks (run_phases.h). */
#include "run_phases.h"

#include <math.h>

run_phase_t run_phase_of(mc_state_t state, double t_s, double profile_start_s)
{
    switch (state) {
    case MC_STATE_IDLE:
    case MC_STATE_CALIBRATING:
    case MC_STATE_ALIGN: return RUN_PHASE_START;
    case MC_STATE_RUN: return t_s < profile_start_s ? RUN_PHASE_HOLD : RUN_PHASE_PROFILE;
    case MC_STATE_FAULT: return RUN_PHASE_FAULT;
    }
    return RUN_PHASE_FAULT; /* not a state of the firmware: never a clean run */
}

const char *run_phase_name(run_phase_t phase)
{
    switch (phase) {
    case RUN_PHASE_START: return "start";
    case RUN_PHASE_HOLD: return "hold";
    case RUN_PHASE_PROFILE: return "profile";
    case RUN_PHASE_FAULT: return "fault";
    case RUN_PHASE_COUNT: break;
    }
    return "unknown";
}

const char *run_phase_meaning(run_phase_t phase)
{
    switch (phase) {
    case RUN_PHASE_START: return "start (calibration, alignment)";
    case RUN_PHASE_HOLD: return "hold before the profile";
    case RUN_PHASE_PROFILE: return "under the profile";
    case RUN_PHASE_FAULT: return "after the fault";
    case RUN_PHASE_COUNT: break;
    }
    return "unknown";
}

/* The larger of a and b; NaN when either is (a non-finite sample must show). */
static double peak(double a, double b)
{
    return (isnan(a) || isnan(b)) ? NAN : fmax(a, b);
}

static double max_abs3(const double x[3])
{
    return peak(fabs(x[0]), peak(fabs(x[1]), fabs(x[2])));
}

void run_phases_record(run_phase_stats_t phases[RUN_PHASE_COUNT], mc_state_t state_before,
                       double profile_start_s, const plant_true_state_t *p)
{
    run_phase_stats_t *ph = &phases[run_phase_of(state_before, p->t_s, profile_start_s)];
    const double i_peak = max_abs3(p->i_abc_A);
    const double v_peak = max_abs3(p->v_abc_V);
    if (ph->samples == 0) {
        ph->t_first_s = p->t_s;
        ph->i_peak_A = i_peak;
        ph->v_peak_V = v_peak;
    }
    ph->samples++;
    ph->t_last_s = p->t_s;
    ph->i_peak_A = peak(ph->i_peak_A, i_peak);
    ph->v_peak_V = peak(ph->v_peak_V, v_peak);
}
