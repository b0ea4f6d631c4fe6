/*
 * plant_frames.h - amplitude-invariant Clarke/Park helpers (see plant.h for
 * the convention). Internal to sim_plant.
 */
#ifndef SIM_PLANT_FRAMES_H
#define SIM_PLANT_FRAMES_H

#define PLANT_SQRT3  1.7320508075688772935274463415059
#define PLANT_TWO_PI 6.283185307179586476925286766559

/* dq -> abc with c = cos(theta_e), s = sin(theta_e). */
static inline void plant_dq_to_abc(double d, double q, double c, double s, double abc[3])
{
    const double alpha = c * d - s * q;
    const double beta = s * d + c * q;
    abc[0] = alpha;
    abc[1] = -0.5 * alpha + 0.5 * PLANT_SQRT3 * beta;
    abc[2] = -0.5 * alpha - 0.5 * PLANT_SQRT3 * beta;
}

/* abc (any common mode is removed by the Clarke transform) -> dq. */
static inline void plant_abc_to_dq(const double abc[3], double c, double s, double *d, double *q)
{
    const double alpha = (2.0 * abc[0] - abc[1] - abc[2]) / 3.0;
    const double beta = (abc[1] - abc[2]) / PLANT_SQRT3;
    *d = c * alpha + s * beta;
    *q = -s * alpha + c * beta;
}

#endif /* SIM_PLANT_FRAMES_H */
