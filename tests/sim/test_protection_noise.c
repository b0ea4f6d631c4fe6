/*
 * No false trip with realistic sensors: 10 mA RMS noise on every phase
 * current and 12-bit converters (currents +-25 A: 12.2 mA per code; bus
 * 0-100 V: 24 mV per code), on the paper-001 benchmark (alignment, the
 * speed profile, the load steps) under the baseline FOC with its encoder,
 * the paper's sensorless IDA-PBC and the NAM baseline. Every fault class
 * of mc/faults.h must stay clear for the whole run. The margins this
 * rests on (firmware/app/config.c): the sensor sum sees 17 mA RMS against
 * a 1 A threshold; the back-EMF checks filter the L di/dt of the noise
 * (1.1 V per sample) to 0.04 V against a 0.5 V floor.
 */
#include "mc_test.h"

#include <math.h>
#include <stdlib.h>

#include "protection_fixture.h"
#include "test_p001_bench.h"

static void noisy_sensors(plant_config_t *pc)
{
    pc->sensors.current.noise_rms_A = 0.01;
    pc->sensors.current.adc_bits = 12u;
    pc->sensors.current.full_scale_A = 25.0;
    pc->sensors.vdc.adc_bits = 12u;
    pc->sensors.vdc.full_scale_V = 100.0;
}

static void run_clean(plant_config_t *pc, mc_config_t *fc, const char *label)
{
    sim_engine_t *e = fixture_engine(pc, fc);
    const prot_result_t r =
        prot_run(e, prot_bench_cmd, BENCH_T0_S + BENCH_LENGTH_S, 0.0, fc->limits.i_max_A, 0.0);
    prot_print(label, &r);
    free(e);
    assert_int_equal(r.first_fault, 0u);
    assert_true(r.t_fault_s < 0.0);
}

static void test_foc_encoder(void **state)
{
    (void)state;
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    noisy_sensors(&pc);
    fixture_fw_config(&pc, &fc);
    run_clean(&pc, &fc, "noise, FOC + encoder");
}

static void test_sensorless(mc_controller_t ctl, const char *label)
{
    plant_config_t pc;
    mc_config_t fc;
    bench_plant_config(&pc, 1.0, 1.0, 1.0);
    noisy_sensors(&pc);
    bench_fw_config(&pc, &fc, ctl);
    run_clean(&pc, &fc, label);
}

static void test_paper(void **state)
{
    (void)state;
    test_sensorless(MC_CONTROLLER_IDAPBC, "noise, paper (IDA-PBC)");
}

static void test_nam(void **state)
{
    (void)state;
    test_sensorless(MC_CONTROLLER_FOC_PI, "noise, NAM");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_foc_encoder),
        cmocka_unit_test(test_paper),
        cmocka_unit_test(test_nam),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
