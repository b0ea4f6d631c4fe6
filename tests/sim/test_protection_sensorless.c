/*
 * Sensorless loss of lock and a locked rotor on the paper-001 benchmark
 * (test_p001_bench.h: alignment, then the speed profile from BENCH_T0_S;
 * firmware defaults, mc/config.h). Before the protection work the R -10 %
 * case stalled at 14-19.6 A for 2.4 s (with the reference held at 50 rpm:
 * 7 s at 14.3 A, no fault), the NAM baseline sat at its 10 A limit for
 * 7.3 s, and a locked rotor took 19.1 A indefinitely.
 *
 * R -10 % (plant R = 0.9 x the controller's), paper scheme (IDA-PBC, flux
 * observer + I&I), the paper's machine: during the 50 rpm hold under
 * 1 N m (tb about 2.1 s) the estimate's angle runs away from the rotor's
 * (to about -pi/2) while both slow down.
 * The back-EMF check (mc/emf_monitor.h) sees the measured back-EMF turn
 * away from the estimate's: once the true angle error passes angle_max =
 * 45 deg, the filtered vectors follow within a filter time constant
 * (20 ms) and the check holds 0.1 s: MC_FAULT_LOSS_OF_LOCK within
 * [0.1 s, 0.12 s] of that crossing (the angle error grows monotonically
 * here, so the filter can only delay the onset). The peak true phase
 * current stays below the current-limit loop's 11 A + 5 % (IDA-PBC has no
 * current reference: mc/current_limit.h holds it), and the true current
 * is above i_max only between the crossing and the fault. The same with
 * the reference held at 50 rpm (the fault comes before the profile leaves
 * 50 rpm at tb = 3 s: the reference cannot change it). Measured before
 * the protection work on the machine of the time: 14-19.6 A for 2.4 s.
 *
 * R -10 %, NAM baseline (FOC + flux observer + PLL): the rotor ends up
 * shaking about standstill at i_max with the estimate near zero (below the
 * back-EMF checks' speed floor, 3 electrical rad/s), so the stall check
 * (|i_dq| > 7 A at |omega_hat| < 1 rad/s for 0.5 s) faults: MC_FAULT_STALL,
 * the current within the FOC's i_max reference + 5 % (its current loop).
 * Its time is set by the estimate's wandering (it must stay below 1 rad/s
 * for 0.5 s); the thermal model bounds it from above whatever the estimate
 * does: i_max from cold is an I2T fault after i2t_peak_time_s = 2 s.
 *
 * Locked rotor (a shaft brake at tb = 2 s, 50 rpm, 1 N m):
 *  - paper: the estimate keeps turning at 50 rpm (omega_e = 15.7 rad/s,
 *    predicted back-EMF 2.7 V) while the measured back-EMF falls to zero:
 *    through the check's 20 ms filter the ratio passes 1/2 after
 *    20 ms ln 2 = 13.9 ms (the angle branch would need (pi/4) / 15.7 =
 *    50 ms), then holds 0.1 s: MC_FAULT_LOSS_OF_LOCK within 0.114 s + 10 ms
 *    (the estimate's own slow-down); IDA-PBC pushes the current past
 *    i_max meanwhile: <= the limit loop's 11 A + 5 %, above i_max only
 *    between the lock and the fault;
 *  - NAM: the PLL estimate follows the stopped flux angle down:
 *    MC_FAULT_STALL 0.5 s after the TRUE stall began (|i| > 7 A at |omega|
 *    < 1 rad/s), give or take 20 ms of the estimate's lag; current <=
 *    i_max + 5 %.
 * Every case: the inverter stops in the faulting period.
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>

#include "protection_fixture.h"
#include "test_p001_bench.h"

#define T_LOCK_S (BENCH_T0_S + 2.0)

static double g_hold_rpm = INFINITY; /* the reference's ceiling */

static mc_command_t bench_cmd(double t_s)
{
    mc_command_t c = prot_bench_cmd(t_s);
    c.omega_m_ref_rad_s = fminf(c.omega_m_ref_rad_s, (float)(g_hold_rpm / BENCH_RPM_PER_RAD_S));
    return c;
}

/* The TRUE stall: |i_dq| > stall current at |omega_m| < stall speed,
 * the start of its last unbroken run before the fault; and the first time
 * the controller's angle is off the rotor's by more than angle_max. */
typedef struct {
    double i_sq, w, angle_max;
    double t_begin_s;
    double t_angle_s;
    bool latched;
} true_stall_t;

static void watch_stall(const sim_trace_sample_t *s, void *ctx)
{
    true_stall_t *st = ctx;
    if (st->latched) {
        return;
    }
    const double err = remainder((double)s->fw.theta_e_rad - s->plant.theta_e_rad, MC_TEST_TWO_PI);
    if (st->t_angle_s < 0.0 && s->fw.state == MC_STATE_RUN && fabs(err) > st->angle_max) {
        st->t_angle_s = s->t_s;
    }
    const double i_sq = s->plant.i_d_A * s->plant.i_d_A + s->plant.i_q_A * s->plant.i_q_A;
    if (i_sq > st->i_sq && fabs(s->plant.omega_m_rad_s) < st->w) {
        if (st->t_begin_s < 0.0) {
            st->t_begin_s = s->t_s;
        }
    } else {
        st->t_begin_s = -1.0;
    }
    st->latched = s->fw.faults_latched != 0u;
}

static true_stall_t g_stall;

static prot_result_t run(double m_R, mc_controller_t ctl, bool lock, double hold_rpm,
                         mc_config_t *fc, const char *label)
{
    plant_config_t pc;
    bench_plant_config(&pc, m_R, 1.0, 1.0);
    bench_fw_config(&pc, fc, ctl);
    sim_engine_t *e = fixture_engine(&pc, fc);
    if (lock) {
        const sim_injection_t inj = { .kind = SIM_INJECT_ROTOR_LOCK,
                                      .t_start_s = T_LOCK_S,
                                      .t_end_s = INFINITY };
        prot_inject(e, &inj);
    }
    g_hold_rpm = hold_rpm;
    const double i_stall = (double)fc->protection.stall_current_A;
    g_stall = (true_stall_t){ .i_sq = i_stall * i_stall,
                              .w = (double)fc->protection.stall_speed_rad_s,
                              .angle_max = (double)fc->emf_check.angle_max_rad,
                              .t_begin_s = -1.0,
                              .t_angle_s = -1.0 };
    const prot_result_t r =
        prot_run_observed(e, bench_cmd, BENCH_T0_S + BENCH_LENGTH_S, 0.05, fc->limits.i_max_A,
                          lock ? T_LOCK_S : BENCH_T0_S, watch_stall, &g_stall);
    prot_print(label, &r);
    print_message("  true stall from %.5f s; angle error above angle_max from %.5f s\n",
                  g_stall.t_begin_s, g_stall.t_angle_s);
    free(e);
    assert_true(r.outputs_off_at_fault);
    return r;
}

static void assert_r_minus_10_paper(double hold_rpm, const char *label)
{
    mc_config_t fc;
    const prot_result_t r = run(0.9, MC_CONTROLLER_IDAPBC, false, hold_rpm, &fc, label);
    assert_int_equal(r.first_fault, MC_FAULT_LOSS_OF_LOCK);
    assert_true(g_stall.t_angle_s > BENCH_T0_S); /* in the benchmark */
    const double t_check = (double)fc.emf_check.check_time_s;
    assert_true(r.t_fault_s >= g_stall.t_angle_s + t_check);
    assert_true(r.t_fault_s <= g_stall.t_angle_s + t_check + (double)fc.emf_check.filter_s);
    assert_true(r.t_first_over_i_max_s < 0.0 || r.t_first_over_i_max_s >= g_stall.t_angle_s);
    assert_true(r.t_over_i_max_s <= r.t_fault_s - g_stall.t_angle_s);
    assert_true(r.i_peak_watch_A <= 1.05 * (double)fc.protection.current_limit_A);
}

static void test_r_minus_10_paper(void **state)
{
    (void)state;
    assert_r_minus_10_paper(INFINITY, "R -10 % paper");
}

static void test_r_minus_10_paper_hold(void **state)
{
    (void)state;
    assert_r_minus_10_paper(50.0, "R -10 % paper, 50 rpm held");
}

static void test_r_minus_10_nam(void **state)
{
    (void)state;
    mc_config_t fc;
    const prot_result_t r = run(0.9, MC_CONTROLLER_FOC_PI, false, INFINITY, &fc, "R -10 % NAM");
    assert_int_equal(r.first_fault, MC_FAULT_STALL);
    assert_true(g_stall.t_angle_s > BENCH_T0_S);
    assert_true(r.t_fault_s <= g_stall.t_angle_s + (double)fc.protection.i2t_peak_time_s);
    assert_true(r.i_peak_watch_A <= 1.05 * (double)fc.limits.i_max_A);
}

static void test_locked_paper(void **state)
{
    (void)state;
    mc_config_t fc;
    const prot_result_t r =
        run(1.0, MC_CONTROLLER_IDAPBC, true, INFINITY, &fc, "locked at tb 2 s, paper");
    assert_int_equal(r.first_fault, MC_FAULT_LOSS_OF_LOCK);
    const double t_detect =
        (double)fc.emf_check.filter_s * log(2.0) + (double)fc.emf_check.check_time_s;
    assert_true(r.t_fault_s >= T_LOCK_S + t_detect);
    assert_true(r.t_fault_s <= T_LOCK_S + t_detect + 0.01);
    assert_true(r.i_peak_watch_A <= 1.05 * (double)fc.protection.current_limit_A);
    assert_true(r.t_over_i_max_s <= r.t_fault_s - T_LOCK_S);
}

static void test_locked_nam(void **state)
{
    (void)state;
    mc_config_t fc;
    const prot_result_t r =
        run(1.0, MC_CONTROLLER_FOC_PI, true, INFINITY, &fc, "locked at tb 2 s, NAM");
    assert_int_equal(r.first_fault, MC_FAULT_STALL);
    assert_true(g_stall.t_begin_s >= T_LOCK_S);
    assert_true(fabs(r.t_fault_s - g_stall.t_begin_s - (double)fc.protection.stall_time_s) <= 0.02);
    assert_true(r.i_peak_A <= 1.05 * (double)fc.limits.i_max_A);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_r_minus_10_paper), cmocka_unit_test(test_r_minus_10_paper_hold),
        cmocka_unit_test(test_r_minus_10_nam),   cmocka_unit_test(test_locked_paper),
        cmocka_unit_test(test_locked_nam),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
