/* Closed-loop run of a scenario (see run.h). */
#define _POSIX_C_SOURCE 200809L

#include "run.h"

#include <math.h>
#include <stdlib.h>
#include <time.h>

#include "angle_diff.h"
#include "trace_csv.h"

#define PROGRESS_AFTER_S    2.0
#define PROGRESS_EVERY_S    1.0
#define CLOCK_CHECK_PERIODS 4096u

static double wall_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static mc_command_t command_at(const scenario_reference_t *ref, double t_s)
{
    mc_command_t cmd = { .enable = true, .mode = ref->mode };
    const double v = sim_profile_eval(&ref->value, t_s);
    switch (ref->mode) {
    case MC_MODE_SPEED: cmd.omega_m_ref_rad_s = (float)v; break;
    case MC_MODE_POSITION: cmd.theta_m_ref_rad = (float)v; break;
    case MC_MODE_CURRENT:
        cmd.i_q_ref_A = (float)v;
        cmd.i_d_ref_A = (float)sim_profile_eval(&ref->i_d_A, t_s);
        break;
    }
    return cmd;
}

/* The controlled variable of the true plant state, SI. */
static double controlled_si(mc_mode_t mode, const plant_true_state_t *p)
{
    switch (mode) {
    case MC_MODE_SPEED: return p->omega_m_rad_s;
    case MC_MODE_POSITION: return p->theta_m_rad;
    case MC_MODE_CURRENT: return p->i_q_A;
    }
    return NAN;
}

/* The series arrays, in one place for allocation and release. */
#define SERIES_N_ARRAYS 7

static void series_arrays(run_series_t *s, double **out[SERIES_N_ARRAYS])
{
    double **all[SERIES_N_ARRAYS] = {
        &s->t_s, &s->y, &s->ref, &s->angle_err_e_rad, &s->tau_load_hat_Nm, &s->tau_load_Nm, &s->zero
    };
    for (size_t i = 0; i < SERIES_N_ARRAYS; i++) {
        out[i] = all[i];
    }
}

static bool series_alloc(run_series_t *s, size_t n)
{
    double **arrays[SERIES_N_ARRAYS];
    *s = (run_series_t){ 0 };
    series_arrays(s, arrays);
    bool ok = true;
    for (size_t i = 0; i < SERIES_N_ARRAYS; i++) {
        *arrays[i] = calloc(n, sizeof(double));
        ok = ok && *arrays[i] != NULL;
    }
    return ok;
}

void run_result_free(run_result_t *res)
{
    double **arrays[SERIES_N_ARRAYS];
    series_arrays(&res->series, arrays);
    for (size_t i = 0; i < SERIES_N_ARRAYS; i++) {
        free(*arrays[i]);
    }
    res->series = (run_series_t){ 0 };
}

/* Period k enters the series at a block start. */
static void record(run_result_t *res, uint64_t k, const scenario_t *s,
                   const sim_trace_sample_t *smp, double ref_si)
{
    run_series_t *ser = &res->series;
    if (k % res->stride != 0) {
        return;
    }
    const double scale = s->reference.display_per_si;
    size_t j = ser->n++;
    ser->t_s[j] = smp->t_s;
    ser->y[j] = controlled_si(s->reference.mode, &smp->plant) * scale;
    ser->ref[j] = ref_si * scale;
    ser->angle_err_e_rad[j] = angle_diff_rad((double)smp->fw.theta_e_rad, smp->plant.theta_e_rad);
    ser->tau_load_hat_Nm[j] = (double)smp->fw.tau_L_hat_Nm;
    ser->tau_load_Nm[j] = smp->plant.tau_load_Nm;
}

typedef struct {
    double start_s;
    double last_print_s;
} progress_t;

static void progress_update(progress_t *p, double sim_s, double duration_s)
{
    double now = wall_now_s();
    if (now - p->start_s < PROGRESS_AFTER_S || now - p->last_print_s < PROGRESS_EVERY_S) {
        return;
    }
    fprintf(stderr, "pmsm-sim: simulated %.2f of %.2f s (%.0f %%), %.1f s wall\n", sim_s,
            duration_s, 100.0 * sim_s / duration_s, now - p->start_s);
    p->last_print_s = now;
}

static bool setup_engine(const scenario_t *s, sim_engine_t *engine, char *msg, size_t msg_size)
{
    if (sim_engine_init(engine, &s->plant, &s->firmware) != SIM_ENGINE_OK) {
        snprintf(msg, msg_size, "engine initialisation failed: %s", sim_engine_message(engine));
        return false;
    }
    for (size_t i = 0; i < s->n_injections; i++) {
        if (sim_engine_add_injection(engine, &s->injections[i]) != SIM_ENGINE_OK) {
            snprintf(msg, msg_size, "fault_injections[%zu] rejected: %s", i,
                     sim_engine_message(engine));
            return false;
        }
    }
    return true;
}

static bool step_loop(const scenario_t *s, const run_options_t *opt, sim_engine_t *engine,
                      run_result_t *res, char *msg, size_t msg_size)
{
    progress_t progress = { .start_s = wall_now_s() };
    progress.last_print_s = progress.start_s;
    double isr_cost_sum_s = 0.0;
    mc_state_t state_before = MC_STATE_IDLE;
    for (uint64_t k = 0; k < res->periods; k++) {
        const double t_s = sim_engine_time_s(engine);
        const mc_command_t cmd = command_at(&s->reference, t_s);
        if (sim_engine_step(engine, &cmd) != SIM_ENGINE_OK) {
            snprintf(msg, msg_size, "engine step at t = %.6f s failed: %s", t_s,
                     sim_engine_message(engine));
            return false;
        }
        const sim_trace_sample_t *smp = sim_engine_last(engine);
        if (opt->keep_series) {
            record(res, k, s, smp, sim_profile_eval(&s->reference.value, t_s));
        }
        run_phases_record(res->phases, state_before, s->time_offset_s, &smp->plant);
        state_before = smp->fw.state;
        if (opt->csv != NULL && k % s->trace_decimation == 0) {
            trace_csv_row(opt->csv, smp);
        }
        isr_cost_sum_s += (double)smp->fw.isr_cost_s;
        res->isr_cost_max_s = (double)smp->fw.isr_cost_max_s;
        if (smp->fw.faults_latched != 0 && isnan(res->first_fault_sim_s)) {
            res->first_fault_sim_s = smp->t_s;
        }
        res->faults_latched = smp->fw.faults_latched;
        res->final_state = smp->fw.state;
        if (k % CLOCK_CHECK_PERIODS == 0) {
            if (opt->stop != NULL && *opt->stop != 0) {
                snprintf(msg, msg_size, "run stopped by a signal at t = %.6f s", t_s);
                return false;
            }
            if (opt->progress) {
                progress_update(&progress, t_s, s->duration_s);
            }
        }
    }
    /* isr_cost_s of period k is the cost of the ISR of period k - 1 */
    res->isr_cost_mean_s = res->periods > 1 ? isr_cost_sum_s / (double)(res->periods - 1) : 0.0;
    res->sim_s = sim_engine_time_s(engine);
    res->wall_s = wall_now_s() - progress.start_s;
    return true;
}

bool run_scenario(const scenario_t *s, const run_options_t *opt, run_result_t *res, char *msg,
                  size_t msg_size)
{
    *res = (run_result_t){ .first_fault_sim_s = NAN, .stride = 1 };
    sim_engine_t *engine = malloc(sizeof(*engine));
    if (engine == NULL) {
        snprintf(msg, msg_size, "out of memory for the engine");
        return false;
    }
    bool ok = setup_engine(s, engine, msg, msg_size);
    if (ok) {
        res->periods = (uint64_t)llround(s->duration_s / sim_engine_period_s(engine));
        res->stride =
            (uint32_t)((res->periods + RUN_SERIES_MAX_SAMPLES - 1) / RUN_SERIES_MAX_SAMPLES);
        if (res->stride == 0) {
            res->stride = 1;
        }
        size_t n = (size_t)((res->periods + res->stride - 1) / res->stride);
        if (opt->keep_series && !series_alloc(&res->series, n)) {
            snprintf(msg, msg_size, "out of memory for %zu series samples", n);
            ok = false;
        }
    }
    if (ok && opt->csv != NULL) {
        trace_csv_header(opt->csv);
    }
    ok = ok && step_loop(s, opt, engine, res, msg, msg_size);
    free(engine);
    return ok;
}
