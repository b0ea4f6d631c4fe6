/*
 * sim_engine_step() with a rejected command (unknown mode) must change
 * nothing: no sensor sample (PRNG draws, encoder index), no trace sample,
 * no time step. The run afterwards is bit-identical to one without it.
 */
#include "mc_test.h"
#include <stdlib.h>
#include <string.h>

#include "sim_engine.h"

static sim_engine_t *noisy_engine(void)
{
    plant_config_t pc;
    plant_config_default(&pc);
    pc.substeps_per_period = PLANT_SUBSTEPS_FAST;
    pc.sensors.current.noise_rms_A = 0.05;
    pc.sensors.vdc.noise_rms_V = 0.1;
    pc.sensors.seed = 7u;
    mc_config_t fc;
    mc_config_init_default(&fc);
    sim_engine_firmware_from_plant(&pc, &fc);
    sim_engine_t *e = malloc(sizeof *e);
    assert_non_null(e);
    assert_int_equal(sim_engine_init(e, &pc, &fc), SIM_ENGINE_OK);
    return e;
}

static void test_rejected_command_changes_nothing(void **state)
{
    (void)state;
    sim_engine_t *a = noisy_engine();
    sim_engine_t *b = noisy_engine();
    const mc_command_t good = { .enable = true, .mode = MC_MODE_CURRENT, .i_q_ref_A = 1.0f };
    mc_command_t bad = good;
    bad.mode = (mc_mode_t)99;

    for (int k = 0; k < 200; ++k) {
        if (k == 50) {
            sim_trace_sample_t before;
            memcpy(&before, sim_engine_last(a), sizeof before);
            const double t_before = sim_engine_time_s(a);
            assert_int_equal(sim_engine_step(a, &bad), SIM_ENGINE_ERR_COMMAND);
            assert_memory_equal(&before, sim_engine_last(a), sizeof before);
            assert_true(sim_engine_time_s(a) == t_before);
        }
        assert_int_equal(sim_engine_step(a, &good), SIM_ENGINE_OK);
        assert_int_equal(sim_engine_step(b, &good), SIM_ENGINE_OK);
        const sim_trace_sample_t *sa = sim_engine_last(a);
        const sim_trace_sample_t *sb = sim_engine_last(b);
        assert_true(sa->k == sb->k);
        assert_memory_equal(&sa->meas, &sb->meas, sizeof sa->meas);
        assert_memory_equal(&sa->plant, &sb->plant, sizeof sa->plant);
    }
    free(a);
    free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rejected_command_changes_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
