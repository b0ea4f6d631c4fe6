/* Difference of two angles wrapped to [-pi, pi) (trace and metrics). */
#ifndef PMSM_SIM_ANGLE_DIFF_H
#define PMSM_SIM_ANGLE_DIFF_H

#include <math.h>

static inline double angle_diff_rad(double a, double b)
{
    const double pi = 3.14159265358979323846;
    double d = fmod(a - b + pi, 2.0 * pi);
    return (d < 0.0 ? d + 2.0 * pi : d) - pi;
}

#endif /* PMSM_SIM_ANGLE_DIFF_H */
