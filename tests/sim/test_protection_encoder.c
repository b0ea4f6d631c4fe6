/*
 * Encoder faults under the baseline FOC (paper-001 motor, 8 rad/s, a
 * 2500-line encoder: 10000 counts per turn): slips of 90 and 180 deg
 * electrical, a frozen encoder, lost counts. Before the encoder checks the
 * slips ran the motor away to 54-66 rad/s and a frozen encoder drove
 * 9.5 A into a stalled rotor indefinitely.
 *
 * Expectations (firmware defaults, mc/config.h; t0 = the injection):
 *  - a slip is a count step of 833 (90 deg) or 1667 counts (180 deg) in
 *    one sample; a rotor below twice the overspeed trip (96 rad/s) moves
 *    at most ceil(96 Ts cpr / 2 pi) + 1 = 9 counts: MC_FAULT_ENCODER in
 *    the first sample that sees it (t0; mc/encoder_tracker.h);
 *  - frozen: the PLL speed estimate falls to 0 within a few 1/w_pll
 *    (1 ms) while the measured back-EMF (psi n_p 8 rad/s = 4.1 V) stays:
 *    |e_meas| > 2 |e_pred| + 0.5 V, held check_time_s = 0.1 s
 *    (mc/emf_monitor.h): ENCODER after 0.1 s and before 0.1 s + one
 *    filter time constant (20 ms: the filtered vectors' settling);
 *  - 30 % of the counts lost: the encoder angle falls behind the rotor's
 *    at 0.3 n_p omega >= 0.3 x 3 x 8 = 7.2 rad/s electrical (the speed loop
 *    holds the ENCODER's speed at 8 rad/s: the rotor turns faster), so it
 *    passes angle_max_rad = 45 deg within 0.109 s, then 0.1 s of the
 *    check + one filter time constant: ENCODER within 0.229 s, not before
 *    0.1 s;
 *  - the inverter stops in the faulting period; the true speed stays
 *    below the overspeed trip; the true current stays within the i_max
 *    reference clamp + 5 % (the current loop tracking its reference in a
 *    frame that no longer turns with the rotor: back-EMF ripple).
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>

#include "protection_fixture.h"

#define W_REF_RAD_S 8.0
#define T_INJECT_S  0.3

static prot_result_t run_case(const sim_injection_t *inj, const char *label)
{
    plant_config_t pc;
    mc_config_t fc;
    fixture_configs(&pc, &fc);
    prot_command = (mc_command_t){ .enable = true,
                                   .mode = MC_MODE_SPEED,
                                   .omega_m_ref_rad_s = (float)W_REF_RAD_S };
    sim_engine_t *e = fixture_engine(&pc, &fc);
    prot_inject(e, inj);
    const prot_result_t r =
        prot_run(e, prot_fixed_cmd, T_INJECT_S + 1.0, 0.05, fc.limits.i_max_A, T_INJECT_S);
    prot_print(label, &r);
    free(e);
    return r;
}

static void assert_common(const prot_result_t *r, const mc_config_t *fc)
{
    assert_true(r->outputs_off_at_fault);
    assert_true(r->omega_max_abs_rad_s < (double)fc->protection.overspeed_rad_s);
    assert_true(r->i_peak_A <= 1.05 * (double)fc->limits.i_max_A);
}

static void test_slip(double angle_e_rad, const char *label)
{
    mc_config_t fc;
    plant_config_t pc;
    fixture_configs(&pc, &fc);
    const sim_injection_t inj = { .kind = SIM_INJECT_ENCODER_SLIP,
                                  .t_start_s = T_INJECT_S,
                                  .t_end_s = INFINITY,
                                  .angle_e_rad = angle_e_rad };
    const prot_result_t r = run_case(&inj, label);
    assert_int_equal(r.first_fault, MC_FAULT_ENCODER);
    assert_true(fabs(r.t_fault_s - T_INJECT_S) < 1e-9);
    assert_common(&r, &fc);
}

static void test_slip_90(void **state)
{
    (void)state;
    test_slip(0.5 * MC_TEST_PI, "slip 90 deg");
}

static void test_slip_180(void **state)
{
    (void)state;
    test_slip(MC_TEST_PI, "slip 180 deg");
}

static void test_frozen(void **state)
{
    (void)state;
    mc_config_t fc;
    plant_config_t pc;
    fixture_configs(&pc, &fc);
    const sim_injection_t inj = { .kind = SIM_INJECT_ENCODER_FROZEN,
                                  .t_start_s = T_INJECT_S,
                                  .t_end_s = INFINITY };
    const prot_result_t r = run_case(&inj, "frozen");
    assert_true(r.first_fault & (MC_FAULT_ENCODER | MC_FAULT_STALL));
    assert_true(r.t_fault_s >= T_INJECT_S);
    assert_true(r.t_fault_s <= T_INJECT_S + (double)fc.protection.stall_time_s + 0.1);
    assert_common(&r, &fc);
}

static void test_count_loss(void **state)
{
    (void)state;
    mc_config_t fc;
    plant_config_t pc;
    fixture_configs(&pc, &fc);
    const sim_injection_t inj = { .kind = SIM_INJECT_ENCODER_COUNT_LOSS,
                                  .t_start_s = T_INJECT_S,
                                  .t_end_s = INFINITY,
                                  .lost_fraction = 0.3 };
    const prot_result_t r = run_case(&inj, "count loss 30 %");
    assert_true(r.first_fault & (MC_FAULT_ENCODER | MC_FAULT_OVERSPEED | MC_FAULT_STALL));
    assert_true(r.t_fault_s >= T_INJECT_S);
    assert_true(r.t_fault_s <= T_INJECT_S + 0.5);
    assert_common(&r, &fc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slip_90),
        cmocka_unit_test(test_slip_180),
        cmocka_unit_test(test_frozen),
        cmocka_unit_test(test_count_loss),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
