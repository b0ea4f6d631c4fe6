/*
 * Current-sensor faults under the baseline FOC (encoder, 8 rad/s, a
 * 1 N m load: |i| = 1.31 A), injected on the measurement at T_INJECT_S.
 * The three sensors of a floating star sum to zero; the supervision
 * (mc/supervisor.h), on the slow tick (every T = 0.5 ms at 20 kHz / 2 kHz),
 * faults when |i_a + i_b + i_c| > current_sum_max_A = 1 A on the samples
 * of n = current_sum_time_s / T = 2 consecutive ticks (1 ms). Before it
 * an offset drift drove the TRUE current above the 20 A trip for
 * 62-136 ms, and a stuck channel was not detected.
 *
 * Expectations (derived from the rule, tick times t0 + phase + j T, the
 * phase in [0, T) unknown to the test):
 *  - offset ramp r = 100 A/s on phase a: the sum is r (t - t0): it
 *    exceeds 1 A after t_c = t0 + 10 ms ("above" is strict), the first
 *    tick after t_c sees it, within (0, T], and the fault comes n - 1
 *    ticks later: in (t_c + (n - 1) T, t_c + n T] (+- one sample for the
 *    float comparison at the crossing). Until then the measured current
 *    is wrong by at most 1.1 A: the true current stays within the load
 *    current + 1.1 A;
 *  - offset step of +15 A on phase a (below the 20 A trip, so the phase
 *    over-current check does not fire): the sum is 15 A from the sample at
 *    t0: the first tick at or after t0 sees it, within [0, T - Ts], the
 *    fault n - 1 ticks later: in [t0 + (n - 1) T, t0 + n T - Ts], on the
 *    sample grid. For those at most 1 ms the current loop (bandwidth
 *    w_c = 2513 rad/s) pulls the true alpha current towards -2/3 x 15 A =
 *    -10 A: the true current stays below 10 A + the load current;
 *  - phase b stuck at 0 A: the sum is -i_b(true), a sinusoid of
 *    amplitude 1.31 A at 24 rad/s electrical: above 1 A for 2 acos(1 /
 *    1.31)/24 s = 58 ms of every half period (131 ms), so the fault comes
 *    within half an electrical period + 1 ms of the injection;
 *  - every case: the inverter stops in the faulting period, and no
 *    sample's true current reaches the trip.
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>

#include "protection_fixture.h"

#define T_INJECT_S  0.3
#define LOAD_NM     1.0
#define W_REF_RAD_S 8.0

static prot_result_t run_case(const sim_injection_t *inj, mc_config_t *fc, const char *label)
{
    plant_config_t pc;
    fixture_configs(&pc, fc);
    sim_profile_set_constant(&pc.load_torque_Nm, LOAD_NM);
    prot_command = (mc_command_t){ .enable = true,
                                   .mode = MC_MODE_SPEED,
                                   .omega_m_ref_rad_s = (float)W_REF_RAD_S };
    sim_engine_t *e = fixture_engine(&pc, fc);
    prot_inject(e, inj);
    const prot_result_t r =
        prot_run(e, prot_fixed_cmd, T_INJECT_S + 1.0, 0.05, fc->limits.i_max_A, T_INJECT_S);
    prot_print(label, &r);
    free(e);
    assert_int_equal(r.first_fault, MC_FAULT_CURRENT_SENSOR);
    assert_true(r.outputs_off_at_fault);
    assert_true(r.i_peak_A < (double)fc->protection.i_trip_A);
    return r;
}

/* The load current amplitude: 1 N m / (1.5 n_p psi). */
static double load_current_A(const mc_config_t *fc)
{
    return LOAD_NM / (1.5 * fc->motor.pole_pairs * (double)fc->motor.psi_Wb);
}

static void test_offset_ramp(void **state)
{
    (void)state;
    const double rate = 100.0;
    const sim_injection_t inj = { .kind = SIM_INJECT_CURRENT_OFFSET_RAMP,
                                  .t_start_s = T_INJECT_S,
                                  .t_end_s = INFINITY,
                                  .phase = 0u,
                                  .rate_A_s = rate };
    mc_config_t fc;
    const prot_result_t r = run_case(&inj, &fc, "offset ramp 100 A/s");
    const double Ts = 1.0 / (double)fc.timing.f_pwm_Hz;
    const double T = 1.0 / (double)fc.timing.slow_loop_Hz;
    const double t_c = T_INJECT_S + (double)fc.protection.current_sum_max_A / rate;
    const double n = round((double)fc.protection.current_sum_time_s / T);
    assert_true(r.t_fault_s > t_c + (n - 1.0) * T - 1.01 * Ts);
    assert_true(r.t_fault_s <= t_c + n * T + 1.01 * Ts);
    assert_true(r.i_peak_watch_A <=
                load_current_A(&fc) + 1.1 * (double)fc.protection.current_sum_max_A);
}

static void test_offset_step(void **state)
{
    (void)state;
    const sim_injection_t inj = { .kind = SIM_INJECT_CURRENT_OFFSET,
                                  .t_start_s = T_INJECT_S,
                                  .t_end_s = INFINITY,
                                  .phase = 0u,
                                  .value = 15.0 };
    mc_config_t fc;
    const prot_result_t r = run_case(&inj, &fc, "offset step +15 A");
    const double Ts = 1.0 / (double)fc.timing.f_pwm_Hz;
    const double T = 1.0 / (double)fc.timing.slow_loop_Hz;
    const double n = round((double)fc.protection.current_sum_time_s / T);
    const double k = (r.t_fault_s - T_INJECT_S) / Ts; /* samples after t0 */
    assert_true(fabs(k - round(k)) < 0.01);
    assert_true(r.t_fault_s >= T_INJECT_S + (n - 1.0) * T - 0.01 * Ts);
    assert_true(r.t_fault_s <= T_INJECT_S + n * T - 0.99 * Ts);
    assert_true(r.i_peak_watch_A <= 2.0 / 3.0 * 15.0 + load_current_A(&fc));
}

static void test_stuck_at_zero(void **state)
{
    (void)state;
    const sim_injection_t inj = { .kind = SIM_INJECT_CURRENT_STUCK,
                                  .t_start_s = T_INJECT_S,
                                  .t_end_s = INFINITY,
                                  .phase = 1u,
                                  .value = 0.0 };
    mc_config_t fc;
    const prot_result_t r = run_case(&inj, &fc, "phase b stuck at 0 A");
    const double w_e = fc.motor.pole_pairs * W_REF_RAD_S;
    assert_true(r.t_fault_s >= T_INJECT_S);
    assert_true(r.t_fault_s <=
                T_INJECT_S + MC_TEST_PI / w_e + (double)fc.protection.current_sum_time_s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_offset_ramp),
        cmocka_unit_test(test_offset_step),
        cmocka_unit_test(test_stuck_at_zero),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
