#include "sim_fixture.h"

#include "mc_test.h"

#include <stdlib.h>

void fixture_plant_config(plant_config_t *cfg)
{
    plant_config_default(cfg);
    cfg->substeps_per_period = PLANT_SUBSTEPS_FAST;
}

void fixture_fw_config(const plant_config_t *pc, mc_config_t *cfg)
{
    mc_config_init_default(cfg);
    sim_engine_firmware_from_plant(pc, cfg);
}

void fixture_configs(plant_config_t *pc, mc_config_t *fc)
{
    fixture_plant_config(pc);
    fixture_fw_config(pc, fc);
}

sim_engine_t *fixture_engine(const plant_config_t *pc, const mc_config_t *fc)
{
    sim_engine_t *e = malloc(sizeof *e);
    assert_non_null(e);
    const int rc = sim_engine_init(e, pc, fc);
    if (rc != SIM_ENGINE_OK) {
        print_error("sim_engine_init: %s\n", sim_engine_message(e));
    }
    assert_int_equal(rc, SIM_ENGINE_OK);
    return e;
}

void fixture_start(sim_engine_t *e, const mc_command_t *cmd)
{
    /* the calibration length the firmware derived from its timing */
    const uint32_t limit = mc_app_timing(&e->app)->calib_samples + 10u;
    for (uint32_t k = 0u; k < limit; ++k) {
        assert_int_equal(sim_engine_step(e, cmd), SIM_ENGINE_OK);
        if (sim_engine_last(e)->fw.state == MC_STATE_RUN) {
            return;
        }
    }
    fail_msg("drive did not reach RUN in %u periods", (unsigned)limit);
}

sim_engine_t *fixture_running(const plant_config_t *pc, const mc_config_t *fc,
                              const mc_command_t *cmd)
{
    sim_engine_t *e = fixture_engine(pc, fc);
    fixture_start(e, cmd);
    return e;
}

void fixture_run_until(sim_engine_t *e, const mc_command_t *cmd, double t_end_s)
{
    while (sim_engine_time_s(e) < t_end_s - 0.5 * sim_engine_period_s(e)) {
        assert_int_equal(sim_engine_step(e, cmd), SIM_ENGINE_OK);
    }
}
