/* Physical inputs bounded over the whole run, after every section is read:
 * a profile is a sum of parts, so each key's own range cannot bound it;
 * here the largest value it can reach within the run is (a strict upper
 * bound, profile_peak_bound) and it must stay physically meaningful:
 *   disturbances.load_torque_Nm  |tau| <= LOAD_MAX_MULTIPLE x the motor's
 *       torque at the drive's trip current, 1.5 n_p psi i_trip: a load the
 *       drive could not hold by that factor is an input error (9e24 N m
 *       made the simulated angle leave every numeric range)
 *   inverter.v_dc_V  |v_dc| <= BUS_MAX_V, the format's bound for every bus
 *       voltage (inverter.dc_link.v0_V, brake_on_V, vdc_measured) */
#include <math.h>
#include <stdio.h>

#include "scenario_sections.h"

#define LOAD_MAX_MULTIPLE 1000.0
#define BUS_MAX_V         1e5

/* The largest |v(t)| for t in [0, t_end_s]: the largest |point| (linear in
 * between), the sum of the sine amplitudes, sum |c_k| T^k for the
 * polynomial (T its time within the run) and the noise's tones at their
 * common peak, rms sqrt(2 N) (profile.h: N tones of amplitude
 * rms sqrt(2 / N)). */
static double profile_peak_bound(const sim_profile_t *p, double t_end_s)
{
    double points = 0.0;
    for (uint32_t i = 0; i < p->n_points; i++) {
        points = fmax(points, fabs(p->points[i].value));
    }
    double sines = 0.0;
    for (uint32_t i = 0; i < p->n_sines; i++) {
        sines += fabs(p->sines[i].amplitude);
    }
    const double T = fmax(0.0, t_end_s - p->poly.t_start_s);
    double poly = 0.0;
    for (uint32_t k = p->poly.n_coeffs; k-- > 0u;) {
        poly = poly * T + fabs(p->poly.coeffs[k]);
    }
    const double noise = p->noise.rms * sqrt(2.0 * SIM_PROFILE_NOISE_TONES);
    return points + sines + poly + noise;
}

static bool check_peak(jr_object_t *root, const char *key, const sim_profile_t *p, double t_end_s,
                       double limit, const char *unit, const char *why)
{
    const double peak = profile_peak_bound(p, t_end_s);
    if (peak <= limit) {
        return true;
    }
    char expected[SCN_TEXT_MAX];
    char found[96];
    snprintf(expected, sizeof(expected), "a profile within +-%.4g %s over the run (%s)", limit,
             unit, why);
    snprintf(found, sizeof(found), "one that can reach %.4g %s", peak, unit);
    jr_fail(root, key, SCN_ERR_RANGE, expected, found);
    return false;
}

bool scenario_check_bounds(jr_object_t *root, const scenario_t *s)
{
    const plant_motor_params_t *m = &s->plant.motor;
    const double i_trip_A = (double)s->firmware.protection.i_trip_A;
    const double tau_trip_Nm = 1.5 * (double)m->pole_pairs * m->psi_Wb * i_trip_A;
    char why[256];
    snprintf(why, sizeof(why),
             "%g x the %.4g N m the motor makes at the drive's trip current, 1.5 n_p psi "
             "i_trip with firmware.protection.i_trip_A = %g A: a load the drive could not hold "
             "by that factor is an input error",
             LOAD_MAX_MULTIPLE, tau_trip_Nm, i_trip_A);
    return check_peak(root, "disturbances.load_torque_Nm", &s->plant.load_torque_Nm, s->duration_s,
                      LOAD_MAX_MULTIPLE * tau_trip_Nm, "N m", why) &&
           check_peak(root, "inverter.v_dc_V", &s->plant.inverter.v_dc_V, s->duration_s, BUS_MAX_V,
                      "V", "the format's bound for a bus voltage, as inverter.dc_link.v0_V");
}
