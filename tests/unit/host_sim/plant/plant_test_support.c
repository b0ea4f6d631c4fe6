#include "plant_test_support.h"

#include <math.h>

void test_duties_for_alpha_beta(double v_alpha, double v_beta, double v_dc, double duty[3])
{
    const double v_a = v_alpha;
    const double v_b = -0.5 * v_alpha + 0.5 * sqrt(3.0) * v_beta;
    const double v_c = -0.5 * v_alpha - 0.5 * sqrt(3.0) * v_beta;
    duty[0] = 0.5 + v_a / v_dc;
    duty[1] = 0.5 + v_b / v_dc;
    duty[2] = 0.5 + v_c / v_dc;
}

double test_uniform(uint64_t *state, double lo, double hi)
{
    uint64_t s = *state;
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    *state = s;
    return lo + (hi - lo) * (double)(s >> 11) * 0x1.0p-53;
}

double test_rel_err(double got, double want)
{
    return fabs(got - want) / fabs(want);
}

double test_six_pulse_current_A(double E_V, double v_V, double R_ohm)
{
    const double pi = 3.14159265358979323846;
    if (v_V >= E_V * cos(pi / 6.0)) {
        const double phi0 = acos(v_V / E_V);
        return 3.0 / pi * (2.0 * E_V * sin(phi0) - 2.0 * v_V * phi0) / (2.0 * R_ohm);
    }
    const double e_phase_V = E_V / sqrt(3.0);
    const double theta1 = acos(v_V / (sqrt(3.0) * E_V)) - pi / 3.0;
    const double three_phase = 2.0 * (e_phase_V * sin(theta1) - 2.0 * v_V * theta1 / 3.0) / R_ohm;
    const double pair =
        (2.0 * E_V * sin(pi / 6.0 - theta1) - v_V * (pi / 3.0 - 2.0 * theta1)) / (2.0 * R_ohm);
    return 3.0 / pi * (three_phase + pair);
}
