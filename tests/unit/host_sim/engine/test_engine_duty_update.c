/*
 * The engine tells the firmware, through the HAL (hal_pwm_init's timing
 * record), when the plant's inverter latches the duties: the firmware's
 * timing record (mc_app_t.timing, mc/timing.h) then holds a sample-to-apply
 * delay of 1.5 periods with PLANT_DUTY_UPDATE_NEXT_PERIOD and 1.0 with
 * PLANT_DUTY_UPDATE_HALF_PERIOD, unless the firmware configuration
 * overrides it. sim_engine_init refuses a half-period update with an odd
 * substeps_per_period (the update must fall on a substep boundary) and a
 * firmware PWM rate other than the plant's.
 */
#include "mc_test.h"

#include <stdlib.h>
#include <string.h>

#include "sim_engine.h"

static sim_engine_t *engine; /* about 5 kB: on the heap */
static plant_config_t pc;
static mc_config_t fc;

static int setup(void **state)
{
    (void)state;
    engine = malloc(sizeof *engine);
    return engine == NULL ? -1 : 0;
}

static int teardown(void **state)
{
    (void)state;
    free(engine);
    return 0;
}

/* Default plant (fast integrator) with this update model, and the default
 * firmware on that plant. */
static void configure(plant_duty_update_t update)
{
    plant_config_default(&pc);
    pc.substeps_per_period = PLANT_SUBSTEPS_FAST;
    pc.inverter.duty_update = update;
    mc_config_init_default(&fc);
    sim_engine_firmware_from_plant(&pc, &fc);
}

static void next_period_update_is_a_delay_of_1_5(void **state)
{
    (void)state;
    configure(PLANT_DUTY_UPDATE_NEXT_PERIOD);
    assert_true(fc.timing.delay_periods == 0.0f); /* the default: the HAL's */
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
    assert_true(engine->mailbox.pwm_delay_periods == SIM_ENGINE_DELAY_NEXT_PERIOD);
    assert_true(mc_app_timing(&engine->app)->delay_periods == 1.5f);
    assert_true(SIM_ENGINE_DELAY_NEXT_PERIOD == 1.5f);
    assert_false(engine->half_period_update);
    /* the realised period is the plant's */
    assert_true(mc_app_timing(&engine->app)->Ts_s == 1.0f / 20000.0f);
}

static void half_period_update_is_a_delay_of_1_0(void **state)
{
    (void)state;
    configure(PLANT_DUTY_UPDATE_HALF_PERIOD);
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
    assert_true(engine->mailbox.pwm_delay_periods == SIM_ENGINE_DELAY_HALF_PERIOD);
    assert_true(mc_app_timing(&engine->app)->delay_periods == 1.0f);
    assert_true(SIM_ENGINE_DELAY_HALF_PERIOD == 1.0f);
    assert_true(engine->half_period_update);
    /* it runs: the firmware calibrates, enables the outputs and drives a
     * current with duties that change half a period after each sample */
    const mc_command_t cmd = { .enable = true, .mode = MC_MODE_CURRENT, .i_q_ref_A = 1.0f };
    for (int k = 0; k < 2000; ++k) {
        assert_int_equal(sim_engine_step(engine, &cmd), SIM_ENGINE_OK);
    }
    const sim_trace_sample_t *s = sim_engine_last(engine);
    assert_true(s->outputs_applied);
    assert_int_equal(s->fw.faults_latched, 0);
    assert_true(s->plant.i_q_A > 0.9 && s->plant.i_q_A < 1.1);
}

/* A delay in the firmware configuration overrides the HAL's. */
static void configured_delay_overrides_the_hal(void **state)
{
    (void)state;
    const plant_duty_update_t updates[] = { PLANT_DUTY_UPDATE_NEXT_PERIOD,
                                            PLANT_DUTY_UPDATE_HALF_PERIOD };
    for (size_t i = 0; i < 2; ++i) {
        configure(updates[i]);
        fc.timing.delay_periods = 1.25f;
        assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
        assert_true(mc_app_timing(&engine->app)->delay_periods == 1.25f);
    }
}

static void half_period_update_needs_even_substeps(void **state)
{
    (void)state;
    const uint32_t odd[] = { 1u, 5u, 49u };
    for (size_t i = 0; i < sizeof odd / sizeof odd[0]; ++i) {
        configure(PLANT_DUTY_UPDATE_HALF_PERIOD);
        pc.substeps_per_period = odd[i];
        assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_ERR_PLANT);
        assert_non_null(strstr(sim_engine_message(engine), "even"));
        /* the engine stays unusable */
        const mc_command_t cmd = { .mode = MC_MODE_CURRENT };
        assert_int_equal(sim_engine_step(engine, &cmd), SIM_ENGINE_ERR_STATE);
        /* the next-period update takes any count */
        configure(PLANT_DUTY_UPDATE_NEXT_PERIOD);
        pc.substeps_per_period = odd[i];
        assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
    }
    configure(PLANT_DUTY_UPDATE_HALF_PERIOD);
    pc.substeps_per_period = PLANT_DEFAULT_SUBSTEPS; /* 50 */
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
}

static void firmware_pwm_rate_must_be_the_plants(void **state)
{
    (void)state;
    configure(PLANT_DUTY_UPDATE_NEXT_PERIOD);
    fc.timing.f_pwm_Hz = 10000.0f; /* valid for the firmware, not the plant's */
    assert_int_equal(mc_config_validate(&fc), MC_OK);
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_ERR_MISMATCH);
    assert_non_null(strstr(sim_engine_message(engine), "f_pwm_Hz"));
    /* the plant at 10 kHz and a firmware left at its default 20 kHz */
    configure(PLANT_DUTY_UPDATE_NEXT_PERIOD);
    pc.inverter.f_pwm_Hz = 10000.0;
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_ERR_MISMATCH);
    /* sim_engine_firmware_from_plant makes them agree */
    sim_engine_firmware_from_plant(&pc, &fc);
    assert_true(fc.timing.f_pwm_Hz == 10000.0f);
    assert_int_equal(sim_engine_init(engine, &pc, &fc), SIM_ENGINE_OK);
    assert_true(mc_app_timing(&engine->app)->Ts_s == 1.0f / 10000.0f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(next_period_update_is_a_delay_of_1_5),
        cmocka_unit_test(half_period_update_is_a_delay_of_1_0),
        cmocka_unit_test(configured_delay_overrides_the_hal),
        cmocka_unit_test(half_period_update_needs_even_substeps),
        cmocka_unit_test(firmware_pwm_rate_must_be_the_plants),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
