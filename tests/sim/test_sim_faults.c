/*
 * Fault handling in closed loop: a fault injected at the sampling instant
 * t_f stops the inverter for the very period that starts at t_f (the ISR of
 * that sample disables the outputs, and a disable is immediate), latches
 * (state FAULT, outputs off, the true phase currents decay to zero), ignores
 * a clear request while its cause is present, clears on a request once the
 * cause is gone, and restarts only after enable was re-armed.
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>

#include "sim_fixture.h"

#define T_FAULT_S   0.06
#define FAULT_LEN_S 0.02

static void step_ok(sim_engine_t *e, const mc_command_t *cmd)
{
    assert_int_equal(sim_engine_step(e, cmd), SIM_ENGINE_OK);
}

static void run_fault_case(sim_inject_kind_t kind, double value, uint32_t expected_fault,
                           bool comparator)
{
    plant_config_t pc;
    mc_config_t fc;
    fixture_configs(&pc, &fc);
    pc.locked_rotor = true;
    pc.inverter.overcurrent_comparator = comparator;
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const sim_injection_t inj = { .kind = kind,
                                  .t_start_s = T_FAULT_S,
                                  .t_end_s = T_FAULT_S + FAULT_LEN_S,
                                  .phase = 1u,
                                  .value = value };
    assert_int_equal(sim_engine_add_injection(e, &inj), SIM_ENGINE_OK);

    mc_command_t cmd = { .enable = true, .mode = MC_MODE_CURRENT, .i_q_ref_A = 3.0f };
    fixture_start(e, &cmd);
    /* Up to the sample before t_f: running, inverter switching, 3 A. */
    fixture_run_until(e, &cmd, T_FAULT_S);
    const sim_trace_sample_t *s = sim_engine_last(e);
    assert_true(s->t_s < T_FAULT_S);
    assert_int_equal(s->fw.state, MC_STATE_RUN);
    assert_true(s->outputs_applied);
    assert_true(fabs(s->plant.i_q_A - 3.0) < 0.05);

    /* The sample at t_f: fault latched and the inverter off in the same
     * period. */
    step_ok(e, &cmd);
    s = sim_engine_last(e);
    assert_true(fabs(s->t_s - T_FAULT_S) < 1e-9);
    assert_int_equal(s->injections_active, 1u);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    assert_int_equal(s->fw.faults_latched & expected_fault, expected_fault);
    assert_false(s->fw.outputs_enabled);
    assert_false(s->outputs_applied);
    /* the board's comparators trip on the sampled current beyond the
     * level (not on NaN) */
    assert_int_equal(s->oc_tripped, comparator && expected_fault == MC_FAULT_OVERCURRENT);

    /* Latched while the cause is present; a clear request is refused. */
    cmd.clear_fault = true;
    fixture_run_until(e, &cmd, T_FAULT_S + 0.5 * FAULT_LEN_S);
    cmd.clear_fault = false;
    fixture_run_until(e, &cmd, T_FAULT_S + FAULT_LEN_S);
    s = sim_engine_last(e);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    assert_false(s->outputs_applied);
    /* PWM off: the true currents were driven to zero. */
    assert_true(s->plant.open_circuit);
    assert_true(fabs(s->plant.i_q_A) < 1e-9);

    /* Cause gone, no request: still latched. */
    fixture_run_until(e, &cmd, T_FAULT_S + FAULT_LEN_S + 0.005);
    s = sim_engine_last(e);
    assert_int_equal(s->injections_active, 0u);
    assert_int_equal(s->fw.faults_active, 0u);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    assert_false(s->outputs_applied);

    /* Clear request (rising edge) with the cause gone: IDLE, but enable is
     * still asserted and must be re-armed before the drive restarts. */
    cmd.clear_fault = true;
    step_ok(e, &cmd);
    s = sim_engine_last(e);
    assert_int_equal(s->fw.state, MC_STATE_IDLE);
    assert_int_equal(s->fw.faults_latched, 0u);
    for (int k = 0; k < 20; ++k) {
        step_ok(e, &cmd);
        assert_int_equal(sim_engine_last(e)->fw.state, MC_STATE_IDLE);
        assert_false(sim_engine_last(e)->outputs_applied);
    }
    cmd.enable = false;
    cmd.clear_fault = false;
    step_ok(e, &cmd);
    cmd.enable = true;
    fixture_start(e, &cmd);
    fixture_run_until(e, &cmd, sim_engine_time_s(e) + 0.01);
    s = sim_engine_last(e);
    assert_int_equal(s->fw.state, MC_STATE_RUN);
    assert_true(s->outputs_applied);
    assert_true(fabs(s->plant.i_q_A - 3.0) < 0.05);
    free(e);
}

/* One case of run_fault_case(), the state of its cmocka test. */
typedef struct {
    sim_inject_kind_t kind;
    double value;
    uint32_t expected_fault;
    bool comparator; /* the board's over-current comparators armed: the
                        steady ISRs leave the levels to them */
} fault_case_t;

static void test_fault_case(void **state)
{
    const fault_case_t *c = *state;
    run_fault_case(c->kind, c->value, c->expected_fault, c->comparator);
}

/* A cmocka test of test_fault_case named after the case. */
#define FAULT_CASE_TEST(c)                                                                         \
    {                                                                                              \
        "test_" #c, test_fault_case, NULL, NULL, (void *)&(c)                                      \
    }

/* A +30 A spike on the phase-b current sensor (trip level 20 A). */
static const fault_case_t overcurrent_spike = { SIM_INJECT_CURRENT_OFFSET, 30.0,
                                                MC_FAULT_OVERCURRENT, false };
/* The same with the board's comparators. */
static const fault_case_t overcurrent_spike_comparator = { SIM_INJECT_CURRENT_OFFSET, 30.0,
                                                           MC_FAULT_OVERCURRENT, true };
/* NaN in the phase-b current measurement, without and with comparators
 * (then the current loop's outputs find it). */
static const fault_case_t nan_current = { SIM_INJECT_CURRENT_NAN, 0.0, MC_FAULT_NONFINITE, false };
static const fault_case_t nan_current_comparator = { SIM_INJECT_CURRENT_NAN, 0.0,
                                                     MC_FAULT_NONFINITE, true };
/* External fault / STO input. */
static const fault_case_t external_input = { SIM_INJECT_FAULT_INPUT, 0.0, MC_FAULT_EXTERNAL,
                                             false };
/* Bus voltage measured at 70 V (trip 60 V) and at 10 V (trip 20 V). */
static const fault_case_t bus_overvoltage = { SIM_INJECT_VDC_MEASURED, 70.0,
                                              MC_FAULT_DC_OVERVOLTAGE, false };
static const fault_case_t bus_undervoltage = { SIM_INJECT_VDC_MEASURED, 10.0,
                                               MC_FAULT_DC_UNDERVOLTAGE, false };

/* A NaN reference in RUN is a non-finite fault too. */
static void test_nan_reference(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    fixture_configs(&pc, &fc);
    pc.locked_rotor = true;
    mc_command_t cmd = { .enable = true, .mode = MC_MODE_SPEED };
    sim_engine_t *e = fixture_running(&pc, &fc, &cmd);
    fixture_run_until(e, &cmd, 0.04);
    cmd.omega_m_ref_rad_s = NAN;
    /* The speed loop runs every 10th ISR: the fault comes within 10. */
    for (int k = 0; k < 10 && sim_engine_last(e)->fw.state == MC_STATE_RUN; ++k) {
        step_ok(e, &cmd);
    }
    const sim_trace_sample_t *s = sim_engine_last(e);
    assert_int_equal(s->fw.state, MC_STATE_FAULT);
    assert_int_equal(s->fw.faults_latched, MC_FAULT_NONFINITE);
    assert_false(s->outputs_applied);
    free(e);
}

static void test_engine_rejects_bad_injections(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    fixture_configs(&pc, &fc);
    sim_engine_t *e = fixture_engine(&pc, &fc);
    const sim_injection_t bad[] = {
        { .kind = SIM_INJECT_CURRENT_OFFSET, .t_start_s = NAN, .t_end_s = 1.0 },
        { .kind = SIM_INJECT_CURRENT_OFFSET, .t_start_s = 1.0, .t_end_s = 0.5 },
        { .kind = SIM_INJECT_CURRENT_OFFSET, .t_start_s = 0.0, .t_end_s = 1.0, .phase = 3u },
        { .kind = SIM_INJECT_VDC_MEASURED, .t_start_s = 0.0, .t_end_s = 1.0, .value = INFINITY },
        { .kind = (sim_inject_kind_t)99, .t_start_s = 0.0, .t_end_s = 1.0 },
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(sim_engine_add_injection(e, &bad[i]), SIM_ENGINE_ERR_INJECTION);
    }
    const sim_injection_t ok = { .kind = SIM_INJECT_FAULT_INPUT,
                                 .t_start_s = 5.0,
                                 .t_end_s = INFINITY };
    for (uint32_t i = 0; i < SIM_ENGINE_MAX_INJECTIONS; ++i) {
        assert_int_equal(sim_engine_add_injection(e, &ok), SIM_ENGINE_OK);
    }
    assert_int_equal(sim_engine_add_injection(e, &ok), SIM_ENGINE_ERR_INJECTION);
    /* A mismatched PWM frequency or encoder is refused at init. */
    fc.timing.f_pwm_Hz = 10000.0f;
    assert_int_equal(sim_engine_init(e, &pc, &fc), SIM_ENGINE_ERR_MISMATCH);
    fixture_fw_config(&pc, &fc);
    pc.sensors.encoder.lines = 1024u;
    assert_int_equal(sim_engine_init(e, &pc, &fc), SIM_ENGINE_ERR_MISMATCH);
    const mc_command_t cmd = { .enable = true };
    assert_int_equal(sim_engine_step(e, &cmd), SIM_ENGINE_ERR_STATE);
    free(e);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        FAULT_CASE_TEST(overcurrent_spike),
        FAULT_CASE_TEST(overcurrent_spike_comparator),
        FAULT_CASE_TEST(nan_current),
        FAULT_CASE_TEST(nan_current_comparator),
        FAULT_CASE_TEST(external_input),
        FAULT_CASE_TEST(bus_overvoltage),
        FAULT_CASE_TEST(bus_undervoltage),
        cmocka_unit_test(test_nan_reference),
        cmocka_unit_test(test_engine_rejects_bad_injections),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
