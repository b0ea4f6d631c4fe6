#include "test_p001_bench.h"

#include "motor_convention.h"

#include "mc_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

void bench_plant_config(plant_config_t *pc, double m_R, double m_L, double m_psi)
{
    fixture_plant_config(pc);
    /* the paper's machine: its Phi = 0.17 Wb is two-phase (power-invariant) */
    plant_motor_to_amplitude_invariant(&pc->motor, PLANT_POWER_INVARIANT);
    pc->mismatch.R = m_R;
    pc->mismatch.L = m_L;
    pc->mismatch.psi = m_psi;
    /* Load steps (two points at one time: a right-continuous step). */
    const double t0 = BENCH_T0_S;
    const sim_profile_point_t pts[] = {
        { t0 + 1.0, 0.0 }, { t0 + 1.0, 1.0 }, { t0 + 2.5, 1.0 },
        { t0 + 2.5, 0.0 }, { t0 + 5.0, 0.0 }, { t0 + 5.0, 1.0 },
    };
    sim_profile_clear(&pc->load_torque_Nm);
    for (uint32_t k = 0u; k < sizeof pts / sizeof pts[0]; ++k) {
        pc->load_torque_Nm.points[k] = pts[k];
    }
    pc->load_torque_Nm.n_points = (uint32_t)(sizeof pts / sizeof pts[0]);
}

void bench_fw_config(const plant_config_t *pc, mc_config_t *fc, mc_controller_t controller)
{
    fixture_fw_config(pc, fc);
    fc->controller = controller;
    fc->estimator =
        (controller == MC_CONTROLLER_IDAPBC) ? MC_ESTIMATOR_FLUX_II : MC_ESTIMATOR_FLUX_PLL;
}

double bench_ref_rpm(double tb)
{
    if (tb < 0.0) {
        return 0.0;
    }
    if (tb < 1.0) {
        return 50.0 * tb;
    }
    if (tb < 3.0) {
        return 50.0;
    }
    if (tb < 5.0) {
        return 50.0 + 35.0 * (tb - 3.0);
    }
    if (tb < 7.0) {
        return 120.0;
    }
    if (tb < 9.0) {
        return 120.0 - 60.0 * (tb - 7.0);
    }
    return 0.0;
}

typedef struct {
    double sum_sq;
    uint64_t n;
} rms_t;

static void rms_add(rms_t *r, double x)
{
    r->sum_sq += x * x;
    r->n++;
}

static double rms_get(const rms_t *r)
{
    return (r->n > 0u) ? sqrt(r->sum_sq / (double)r->n) : NAN;
}

static bool in(double tb, double a, double b)
{
    return tb >= a && tb < b;
}

/* Electrical angle difference wrapped to [-pi, pi]. */
static double angle_err(double est, double truth)
{
    return remainder(est - truth, MC_TEST_TWO_PI);
}

/* Start metrics: ALIGN time, peak current, the true state at the first
 * RUN sample. */
static void record_start(bench_result_t *r, const sim_trace_sample_t *s, const mc_config_t *fc,
                         double *t_align_start)
{
    if (s->fw.state == MC_STATE_ALIGN) {
        if (*t_align_start < 0.0) {
            *t_align_start = s->t_s;
        }
        for (unsigned k = 0u; k < 3u; ++k) {
            r->peak_current_align_A = fmax(r->peak_current_align_A, fabs(s->plant.i_abc_A[k]));
        }
    } else if (s->fw.state == MC_STATE_RUN && r->t_run_s < 0.0) {
        r->t_run_s = s->t_s;
        r->t_align_s = s->t_s - *t_align_start;
        r->align_angle_err_rad = angle_err(s->plant.theta_e_rad, (double)fc->align.angle_e_rad);
        r->align_omega_m_rad_s = s->plant.omega_m_rad_s;
    }
}

bench_result_t bench_run(const plant_config_t *pc, const mc_config_t *fc, const char *label)
{
    return bench_run_to(pc, fc, label, BENCH_LENGTH_S);
}

bench_result_t bench_run_to(const plant_config_t *pc, const mc_config_t *fc, const char *label,
                            double tb_end_s)
{
    sim_engine_t *e = fixture_engine(pc, fc);
    mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    bench_result_t r = { .t_first_fault_s = -1.0, .t_run_s = -1.0, .t_align_s = -1.0 };
    double t_align_start = -1.0;
    rms_t sp120 = { 0 }, sp50 = { 0 }, th50 = { 0 }, th120 = { 0 };
    rms_t tau120 = { 0 };
    double sum_ew120 = 0.0, sum_west120 = 0.0;
    bool reached_run = false;
    const double t_end = BENCH_T0_S + tb_end_s;
    while (sim_engine_time_s(e) < t_end - 0.5 * sim_engine_period_s(e)) {
        const double tb_cmd = sim_engine_time_s(e) - BENCH_T0_S;
        cmd.omega_m_ref_rad_s = (float)(bench_ref_rpm(tb_cmd) / BENCH_RPM_PER_RAD_S);
        assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_OK);
        const sim_trace_sample_t *s = sim_engine_last(e);
        const double tb = s->t_s - BENCH_T0_S;
        for (unsigned k = 0u; k < 3u; ++k) {
            r.peak_current_A = fmax(r.peak_current_A, fabs(s->plant.i_abc_A[k]));
            if (tb >= 0.0) {
                r.peak_current_profile_A =
                    fmax(r.peak_current_profile_A, fabs(s->plant.i_abc_A[k]));
            }
        }
        if (s->fw.faults_latched != 0u && r.t_first_fault_s < 0.0) {
            r.t_first_fault_s = tb;
        }
        record_start(&r, s, fc, &t_align_start);
        reached_run = reached_run || s->fw.state == MC_STATE_RUN;
        if (tb < 0.0) {
            continue;
        }
        const double w_rpm = s->plant.omega_m_rad_s * BENCH_RPM_PER_RAD_S;
        const double ref_rpm = bench_ref_rpm(tb);
        const double ew = ref_rpm - w_rpm;
        const double eth = angle_err((double)s->fw.theta_e_rad, s->plant.theta_e_rad);
        const double etau = (double)s->fw.tau_L_hat_Nm - s->plant.tau_load_Nm;
        if (in(tb, 5.5, 7.0)) {
            rms_add(&sp120, ew);
            rms_add(&th120, eth);
            rms_add(&tau120, etau);
            sum_ew120 += ew;
            sum_west120 += (double)s->fw.omega_m_rad_s * BENCH_RPM_PER_RAD_S - w_rpm;
        }
        if (in(tb, 1.5, 2.5)) {
            rms_add(&sp50, ew);
        }
        if (in(tb, 1.5, 3.0)) {
            rms_add(&th50, eth);
        }
        if (in(tb, 1.0, 1.5)) {
            r.dip_load_1s_rpm = fmax(r.dip_load_1s_rpm, ew);
        }
        if (in(tb, 5.0, 5.5)) {
            r.dip_load_5s_rpm = fmax(r.dip_load_5s_rpm, ew);
        }
        if (in(tb, 0.5, 8.5)) {
            r.max_speed_err_moving_rpm = fmax(r.max_speed_err_moving_rpm, fabs(ew));
            r.max_angle_err_moving_rad = fmax(r.max_angle_err_moving_rad, fabs(eth));
        }
        if (in(tb, 9.5, 10.0)) {
            r.max_abs_speed_end_rpm = fmax(r.max_abs_speed_end_rpm, fabs(w_rpm));
            r.max_angle_err_end_rad = fmax(r.max_angle_err_end_rad, fabs(eth));
            r.max_tau_err_end_Nm = fmax(r.max_tau_err_end_Nm, fabs(etau));
        }
        if (tb < 1e-9 && !reached_run) {
            fail_msg("%s: drive not in RUN at the benchmark start", label);
        }
    }
    r.faults = sim_engine_last(e)->fw.faults_latched;
    r.rms_speed_err_120_rpm = rms_get(&sp120);
    r.rms_speed_err_50_rpm = rms_get(&sp50);
    r.rms_angle_err_50_rad = rms_get(&th50);
    r.rms_angle_err_120_rad = rms_get(&th120);
    r.rms_tau_err_120_Nm = rms_get(&tau120);
    r.mean_speed_err_120_rpm = (sp120.n > 0u) ? sum_ew120 / (double)sp120.n : NAN;
    r.mean_speed_est_err_120_rpm = (sp120.n > 0u) ? sum_west120 / (double)sp120.n : NAN;
    free(e);
    printf("[%s] ALIGN %.4f s, then true angle err %.3g rad, w %.3g rad/s, "
           "peak current in ALIGN %.4g A\n",
           label, r.t_align_s, r.align_angle_err_rad, r.align_omega_m_rad_s,
           r.peak_current_align_A);
    printf("[%s] speed RMS err: 50 rpm %.4g rpm, 120 rpm %.4g rpm; max "
           "|err| moving %.4g rpm\n",
           label, r.rms_speed_err_50_rpm, r.rms_speed_err_120_rpm, r.max_speed_err_moving_rpm);
    printf("[%s] at 120 rpm: mean speed err (ref - w) %.4g rpm, mean "
           "estimate err (w_hat - w) %.4g rpm\n",
           label, r.mean_speed_err_120_rpm, r.mean_speed_est_err_120_rpm);
    printf("[%s] load-step dips: tb=1 s %.4g rpm, tb=5 s %.4g rpm\n", label, r.dip_load_1s_rpm,
           r.dip_load_5s_rpm);
    printf("[%s] angle RMS err: 50 rpm %.3g rad, 120 rpm %.3g rad; max "
           "moving %.3g rad\n",
           label, r.rms_angle_err_50_rad, r.rms_angle_err_120_rad, r.max_angle_err_moving_rad);
    printf("[%s] load estimate RMS err at 120 rpm %.3g N m; peak current "
           "%.4g A\n",
           label, r.rms_tau_err_120_Nm, r.peak_current_A);
    printf("[%s] zero speed tb 9.5-10 s: max |w| %.4g rpm, max angle err "
           "%.3g rad, max load err %.3g N m; faults 0x%x (first at tb %.4f "
           "s)\n",
           label, r.max_abs_speed_end_rpm, r.max_angle_err_end_rad, r.max_tau_err_end_Nm,
           (unsigned)r.faults, r.t_first_fault_s);
    return r;
}
