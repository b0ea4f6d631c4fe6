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

#define NS_PER_S 1000000000.0

static double wall_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Realtime pacing (run.h): times in ns of CLOCK_MONOTONIC, as doubles
 * (exact to the ns for 104 days). */
typedef struct {
    double t0_ns;
    double period_ns;
    double lead_ns;
    uint32_t batch; /* periods per batch */
} pace_t;

static double mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * NS_PER_S + (double)ts.tv_nsec;
}

static void pace_start(pace_t *p, double period_s, run_result_t *res)
{
    p->period_ns = period_s * NS_PER_S;
    p->lead_ns = RUN_RT_LEAD_S * NS_PER_S;
    const double batch = floor(RUN_RT_BATCH_S / period_s + 0.5);
    p->batch = batch < 1.0 ? 1u : (uint32_t)batch;
    p->t0_ns = mono_ns();
    res->realtime = true;
    res->rt_batch_periods = p->batch;
}

/* Sleep until this CLOCK_MONOTONIC time (a signal ends the sleep early). */
static void sleep_until_ns(double wake_ns)
{
    const double sec = floor(wake_ns / NS_PER_S);
    const struct timespec ts = { .tv_sec = (time_t)sec,
                                 .tv_nsec = (long)(wake_ns - sec * NS_PER_S) };
    (void)clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, NULL); /* 0 or EINTR */
}

/* After the last period: until the run's simulated end in wall time. */
static void pace_end(const pace_t *p, uint64_t periods)
{
    const double end_ns = p->t0_ns + (double)periods * p->period_ns;
    if (mono_ns() < end_ns) {
        sleep_until_ns(end_ns);
    }
}

/* Before period k: at a batch start, sleep until RUN_RT_LEAD_S before its
 * due time (a signal ends the sleep early); count the period missed when
 * it is reached more than one period after its due time. */
static void pace_period(const pace_t *p, uint64_t k, run_result_t *res)
{
    const double due_ns = p->t0_ns + (double)k * p->period_ns;
    double now_ns = mono_ns();
    if (k % p->batch == 0 && now_ns < due_ns - p->lead_ns) {
        sleep_until_ns(due_ns - p->lead_ns);
        now_ns = mono_ns();
    }
    const double late_ns = now_ns - due_ns;
    if (late_ns > p->period_ns) {
        res->missed_periods++;
    }
    if (late_ns * 1e-9 > res->max_late_s) {
        res->max_late_s = late_ns * 1e-9;
    }
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

static void progress_update(progress_t *p, double sim_s, double duration_s, const run_result_t *res,
                            const hal_socketcan_t *can)
{
    double now = wall_now_s();
    if (now - p->start_s < PROGRESS_AFTER_S || now - p->last_print_s < PROGRESS_EVERY_S) {
        return;
    }
    fprintf(stderr, "pmsm-sim: simulated %.2f of %.2f s (%.0f %%), %.1f s wall", sim_s, duration_s,
            100.0 * sim_s / duration_s, now - p->start_s);
    if (res->realtime) {
        fprintf(stderr, ", %llu missed periods", (unsigned long long)res->missed_periods);
    }
    if (can != NULL) {
        const hal_socketcan_counters_t *c = hal_socketcan_counters(can);
        fprintf(stderr, ", CAN rx %llu tx %llu frames", (unsigned long long)c->rx,
                (unsigned long long)c->tx);
    }
    fputs("\n", stderr);
    p->last_print_s = now;
}

static bool setup_engine(const scenario_t *s, const run_options_t *opt, sim_engine_t *engine,
                         char *msg, size_t msg_size)
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
    if (opt->can != NULL && sim_engine_can_attach(engine, &opt->can_cfg) != SIM_ENGINE_OK) {
        snprintf(msg, msg_size, "CAN node: %s", sim_engine_message(engine));
        return false;
    }
    return true;
}

/* Move the frames between the CAN interface and the drive. */
static bool pump_can(const run_options_t *opt, sim_engine_t *engine, double t_s, char *msg,
                     size_t msg_size)
{
    if (opt->can != NULL && hal_socketcan_pump(opt->can, engine) < 0) {
        snprintf(msg, msg_size, "at t = %.6f s: %s", t_s, hal_socketcan_message(opt->can));
        return false;
    }
    return true;
}

/* The end of the run: counters and times. */
static void finish(const run_options_t *opt, sim_engine_t *engine, run_result_t *res,
                   double isr_cost_sum_s, double start_s)
{
    /* isr_cost_s of period k is the cost of the ISR of period k - 1 */
    res->isr_cost_mean_s = res->periods > 1 ? isr_cost_sum_s / (double)(res->periods - 1) : 0.0;
    res->sim_s = sim_engine_time_s(engine);
    res->wall_s = wall_now_s() - start_s;
    if (opt->can != NULL) {
        res->can_node_id = opt->can->node_id;
        snprintf(res->can_ifname, sizeof res->can_ifname, "%s", opt->can->ifname);
        res->can_link = *hal_socketcan_counters(opt->can);
        const mc_can_node_t *node = sim_engine_can_node(engine);
        if (node != NULL) {
            res->can_node = *mc_can_node_counters(node);
        }
    }
}

static bool step_loop(const scenario_t *s, const run_options_t *opt, sim_engine_t *engine,
                      run_result_t *res, char *msg, size_t msg_size)
{
    /* the drive is up from here: what arrived before is not its */
    if (opt->can != NULL && hal_socketcan_flush(opt->can) < 0) {
        snprintf(msg, msg_size, "%s", hal_socketcan_message(opt->can));
        return false;
    }
    progress_t progress = { .start_s = wall_now_s() };
    progress.last_print_s = progress.start_s;
    pace_t pace = { .batch = CLOCK_CHECK_PERIODS };
    if (opt->realtime) {
        pace_start(&pace, sim_engine_period_s(engine), res);
    }
    double isr_cost_sum_s = 0.0;
    mc_state_t state_before = MC_STATE_IDLE;
    for (uint64_t k = 0; k < res->periods; k++) {
        const double t_s = sim_engine_time_s(engine);
        if (opt->realtime) {
            pace_period(&pace, k, res);
        }
        if (!pump_can(opt, engine, t_s, msg, msg_size)) {
            return false;
        }
        const mc_command_t cmd = scenario_command_at(&s->reference, t_s);
        if (sim_engine_step(engine, opt->can != NULL ? NULL : &cmd) != SIM_ENGINE_OK) {
            snprintf(msg, msg_size, "engine step at t = %.6f s failed: %s", t_s,
                     sim_engine_message(engine));
            return false;
        }
        const sim_trace_sample_t *smp = sim_engine_last(engine);
        if (opt->keep_series && opt->can == NULL) {
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
        /* every CLOCK_CHECK_PERIODS; realtime: every batch (its sleep ends
         * early on a signal) */
        if (k % pace.batch == 0) {
            if (opt->stop != NULL && *opt->stop != 0) {
                snprintf(msg, msg_size, "run stopped by a signal at t = %.6f s", t_s);
                return false;
            }
            if (opt->progress) {
                progress_update(&progress, t_s, s->duration_s, res, opt->can);
            }
        }
    }
    if (opt->realtime) {
        pace_end(&pace, res->periods); /* the run lasts its simulated time */
    }
    /* the frames of the last step */
    if (!pump_can(opt, engine, sim_engine_time_s(engine), msg, msg_size)) {
        return false;
    }
    finish(opt, engine, res, isr_cost_sum_s, progress.start_s);
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
    res->can = opt->can != NULL;
    bool ok = setup_engine(s, opt, engine, msg, msg_size);
    if (ok) {
        res->periods = (uint64_t)llround(s->duration_s / sim_engine_period_s(engine));
        res->stride =
            (uint32_t)((res->periods + RUN_SERIES_MAX_SAMPLES - 1) / RUN_SERIES_MAX_SAMPLES);
        if (res->stride == 0) {
            res->stride = 1;
        }
        size_t n = (size_t)((res->periods + res->stride - 1) / res->stride);
        if (opt->keep_series && !res->can && !series_alloc(&res->series, n)) {
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
