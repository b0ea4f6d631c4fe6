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
