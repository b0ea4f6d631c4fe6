/*
 * The motor and sampling of paper 001, Section 5, for the unit tests
 * (double precision; the tests cast to float where the firmware needs it).
 * Torque model of the paper, (3): tau_e = n_p Phi i_q, so kt = n_p Phi.
 */
#ifndef PAPER001_MOTOR_H
#define PAPER001_MOTOR_H

#include <math.h>

#define P001_L_H         3.8e-3
#define P001_R_OHM       0.225
#define P001_FLUX_WB     0.17
#define P001_NP          3u
#define P001_J_KGM2      0.012
#define P001_KT_NM_PER_A (3.0 * P001_FLUX_WB)
#define P001_TS_S        (1.0 / 20000.0)

#define P001_PI            3.14159265358979323846
#define P001_RAD_S_PER_RPM (2.0 * P001_PI / 60.0)

/* An angle wrapped to [-pi, pi] in double (the reference the observer
 * tests compare wrapped float angles against). */
static inline double p001_wrap_rad(double x)
{
    return remainder(x, 2.0 * P001_PI);
}

#endif /* PAPER001_MOTOR_H */
