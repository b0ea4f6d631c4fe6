/* Throughput of the plant alone at 1 us and at the fast option, with the
 * default integrator (plant.h, "Integrators"): paper 001 motor, 20 kHz, random duties around a
 * rotating back-EMF-matched voltage, 1 s (CPU time). Deviation: test_plant_electrical. Usage:
 * plant_bench [rpm] [band_A] [t_dead_s]
 */
#include "mc_test.h" /* the shared constants (cmocka itself is not used) */

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "plant.h"
#include "plant_test_support.h"

static double wall_s(void)
{
    return (double)clock() / CLOCKS_PER_SEC;
}

static void duties_at(uint64_t *rng, double t_s, double omega_e, double psi, double v_dc,
                      double d[3])
{
    const double e = omega_e * psi, th = omega_e * t_s;
    test_duties_for_alpha_beta(-e * sin(th), e * cos(th), v_dc, d);
    for (int k = 0; k < 3; ++k)
        d[k] += test_uniform(rng, -0.025, 0.025);
}

static double run(plant_config_t *c, uint32_t substeps, double rpm, int n)
{
    c->substeps_per_period = substeps;
    plant_t p;
    if (plant_init(&p, c) != PLANT_OK)
        exit(1);
    uint64_t rng = 42u;
    double d[3];
    const double t0 = wall_s();
    for (int k = 0; k < n; ++k) {
        duties_at(&rng, k / 20000.0, rpm * MC_TEST_RAD_S_PER_RPM * 3.0, 0.17, 400.0, d);
        plant_advance(&p, d, true);
    }
    return wall_s() - t0;
}

int main(int argc, char **argv)
{
    const double rpm = argc > 1 ? atof(argv[1]) : 3000.0;
    plant_config_t c;
    plant_config_default(&c);
    sim_profile_set_constant(&c.inverter.v_dc_V, 400.0);
    c.inverter.dead_time_current_band_A = argc > 2 ? atof(argv[2]) : 0.0;
    c.inverter.t_dead_s = argc > 3 ? atof(argv[3]) : 0.0;
    c.omega_m0_rad_s = rpm * MC_TEST_RAD_S_PER_RPM;
    const int n = 20000; /* 1 s */
    const double w_ref = run(&c, PLANT_DEFAULT_SUBSTEPS, rpm, n);
    const double w_fast = run(&c, PLANT_SUBSTEPS_FAST, rpm, n);
    printf("rpm %.0f (%s): 1 us %.2f sim-s/wall-s, fast (%u substeps) %.2f sim-s/wall-s\n", rpm,
           c.solver_method == PLANT_SOLVER_EXACT ? "exact where linear, else RK4" : "RK4",
           1.0 / w_ref, PLANT_SUBSTEPS_FAST, 1.0 / w_fast);
    return 0;
}
