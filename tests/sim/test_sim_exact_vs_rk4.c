/*
 * The exact plant integrator (PLANT_SOLVER_EXACT) against classic RK4,
 * both at a 1 us step (PLANT_DEFAULT_SUBSTEPS at 20 kHz), over the whole
 * paper-001 benchmark (test_p001_bench.h: alignment, then tb 0..10 s,
 * speed profile and load steps): an engine with the RK4 plant runs the
 * drive in closed loop, and a second plant, exact, is advanced beside it
 * with the same inverter input every period (duties and outputs the
 * engine applied), so the two differ only by their integrators.
 *
 * Why the inputs are shared and not a second closed loop: the firmware
 * computes in float32; two closed loops whose currents differ by 1e-8 A
 * (5e-9 relative) round differently somewhere within a second, and those
 * float32 rounding differences (1e-7 relative per period) then walk the
 * sensorless estimate apart (measured: 1e-8 A at tb 5 s, 2e-5 A at 7.5 s)
 * or flip an encoder count (the FOC case: 0.4 A at once), whatever the
 * plant's integrator.
 *
 * Expectation (independent of the code under test): both integrate the
 * same ODE with a local error far below 1e-9 of the signals per substep
 * (RK4: O((h / tau)^5), tau = L / R = 17 ms, and |omega_e h| < 4e-5; the
 * exact step: O(h^4) from the speed's variation within a substep), so
 * they agree to the acceptance: relative difference <= 1e-6,
 * measured as
 *   max over the run |x_exact - x_rk4| / max over the run |x_rk4|
 * for x = i_d, i_q (the scale: the larger of max |i_d|, max |i_q|) and
 * omega_m. The bound fails if the exact step drops a term of the
 * electrical solution (e.g. the back-EMF's particular solution P, 1e-3 A
 * a substep) or mistimes a load step by a substep (1 N m for 1 us moves
 * omega_m by 8e-5 rad/s, 7e-6 of the benchmark's 12.6 rad/s).
 *
 * Case: set by EXACT_VS_RK4_FOC: 1 = the baseline encoder FOC, 0 = the
 * paper's sensorless IDA-PBC (one executable each, so they run in
 * parallel and stay short under ASan).
 */
#include "mc_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "test_p001_bench.h"

#define MAX_REL_DIFF 1e-6

typedef struct {
    double diff_current_A, max_current_A;
    double diff_speed_rad_s, max_speed_rad_s;
} agreement_t;

static void run_replay(const plant_config_t *pc, const mc_config_t *fc, agreement_t *a)
{
    plant_config_t pc_exact = *pc;
    plant_config_t pc_rk4 = *pc;
    pc_exact.substeps_per_period = PLANT_DEFAULT_SUBSTEPS;
    pc_exact.solver_method = PLANT_SOLVER_EXACT;
    pc_rk4.substeps_per_period = PLANT_DEFAULT_SUBSTEPS;
    pc_rk4.solver_method = PLANT_SOLVER_RK4;
    assert_int_equal(pc->inverter.duty_update, PLANT_DUTY_UPDATE_NEXT_PERIOD);
    sim_engine_t *rk = fixture_engine(&pc_rk4, fc);
    plant_t *ex = malloc(sizeof *ex);
    assert_non_null(ex);
    assert_int_equal(plant_init(ex, &pc_exact), PLANT_OK);
    mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    *a = (agreement_t){ 0 };
    const double t_end_s = BENCH_T0_S + BENCH_LENGTH_S;
    while (sim_engine_time_s(rk) < t_end_s) {
        const double tb_s = sim_engine_time_s(rk) - BENCH_T0_S;
        cmd.omega_m_ref_rad_s = (float)(bench_ref_rpm(tb_s) / BENCH_RPM_PER_RAD_S);
        assert_int_equal(sim_engine_step(rk, &cmd), SIM_ENGINE_OK);
        const sim_trace_sample_t *s = sim_engine_last(rk);
        assert_int_equal(s->fw.faults_latched, 0u);
        plant_advance(ex, s->duty_applied, s->outputs_applied);
        const plant_true_state_t *x = plant_true_state(ex);
        const plant_true_state_t *r = plant_true_state(&rk->plant);
        assert_true(x->t_s == r->t_s);
        a->diff_current_A =
            fmax(a->diff_current_A, fmax(fabs(x->i_d_A - r->i_d_A), fabs(x->i_q_A - r->i_q_A)));
        a->max_current_A = fmax(a->max_current_A, fmax(fabs(r->i_d_A), fabs(r->i_q_A)));
        a->diff_speed_rad_s = fmax(a->diff_speed_rad_s, fabs(x->omega_m_rad_s - r->omega_m_rad_s));
        a->max_speed_rad_s = fmax(a->max_speed_rad_s, fabs(r->omega_m_rad_s));
    }
    assert_int_equal(sim_engine_last(rk)->fw.state, MC_STATE_RUN);
    free(ex);
    free(rk);
}

static void test_exact_vs_rk4(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    const bool foc = EXACT_VS_RK4_FOC != 0;
    bench_fw_config(&pc, &fc, foc ? MC_CONTROLLER_FOC_PI : MC_CONTROLLER_IDAPBC);
    if (foc) {
        fc.estimator = MC_ESTIMATOR_ENCODER;
    }
    agreement_t a;
    run_replay(&pc, &fc, &a);
    assert_true(a.max_current_A > 1.0 && a.max_speed_rad_s > 10.0); /* the profile ran */
    const double rel_i = a.diff_current_A / a.max_current_A;
    const double rel_w = a.diff_speed_rad_s / a.max_speed_rad_s;
    print_message("%s, paper-001 benchmark, exact vs RK4 at 1 us: max |di_dq| %.3g A of "
                  "max |i_dq| %.3g A (%.3g), max |domega_m| %.3g rad/s of %.3g rad/s (%.3g)\n",
                  foc ? "encoder FOC" : "sensorless IDA-PBC", a.diff_current_A, a.max_current_A,
                  rel_i, a.diff_speed_rad_s, a.max_speed_rad_s, rel_w);
    assert_true(rel_i <= MAX_REL_DIFF);
    assert_true(rel_w <= MAX_REL_DIFF);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_exact_vs_rk4),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
