/*
 * Shared set-up of the closed-loop tests: the paper-001 motor's numbers in
 * the plant's amplitude-invariant frame (plant_config_default; the paper's
 * own machine: test_p001_bench.h) on a 48 V bus
 * at 20 kHz, ideal sensors, a 2500-line encoder, the baseline FOC with the
 * firmware defaults, and helpers to run the engine.
 */
#ifndef SIM_FIXTURE_H
#define SIM_FIXTURE_H

#include <stdbool.h>

#include "sim_engine.h"

/* Plant: plant_config_default() (paper 001 motor, 48 V, 20 kHz, 2500
 * lines) with the fast solver (PLANT_SUBSTEPS_FAST). */
void fixture_plant_config(plant_config_t *cfg);

/* Firmware: mc_config_init_default(), then what the bench takes from the
 * plant pc (sim_engine_firmware_from_plant: nominal motor, PWM rate,
 * encoder resolution). */
void fixture_fw_config(const plant_config_t *pc, mc_config_t *cfg);

/* Both of the above (the firmware from this plant). */
void fixture_configs(plant_config_t *pc, mc_config_t *fc);

/* A heap-allocated engine initialised with these configs (asserts OK).
 * Free with free(). */
sim_engine_t *fixture_engine(const plant_config_t *pc, const mc_config_t *fc);

/* Step with cmd (enable set) until the firmware reports RUN (asserts it
 * gets there within the firmware's calibration samples + 10 periods). */
void fixture_start(sim_engine_t *e, const mc_command_t *cmd);

/* fixture_engine() then fixture_start() with cmd: a drive in RUN. */
sim_engine_t *fixture_running(const plant_config_t *pc, const mc_config_t *fc,
                              const mc_command_t *cmd);

/* Step with cmd until sim time reaches t_end_s. */
void fixture_run_until(sim_engine_t *e, const mc_command_t *cmd, double t_end_s);

#endif /* SIM_FIXTURE_H */
