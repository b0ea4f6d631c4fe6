/*
 * The nominal motor model the firmware is designed from (the plant may
 * differ): a three-phase PMSM in the amplitude-invariant dq frame,
 *   v_d = R i_d + Ld di_d/dt - omega_e Lq i_q
 *   v_q = R i_q + Lq di_q/dt + omega_e (Ld i_d + psi)
 *   tau_e = 1.5 n_p (psi i_q + (Ld - Lq) i_d i_q),  J omega_m' = tau_e - B
 * omega_m - tau_L omega_e = n_p omega_m. Units: ohm, H, Wb, kg m^2, N m s/rad.
 */
#ifndef MC_MOTOR_H
#define MC_MOTOR_H

#include <stdint.h>

#include "mc/status.h"

#define MC_MOTOR_POLE_PAIRS_MAX 64u

/* Papers 000 and 001 write the machine as a two-phase one, torque
 * n_p Phi i^T Jcal rho (no 3/2): the power-invariant frame of the same
 * three-phase machine, whose currents, voltages and flux linkages are
 * sqrt(3/2) times the amplitude-invariant ones used here (R, L, J,
 * torques and speeds alike; Phi = sqrt(3/2) psi). Their equations keep
 * their form in these variables with kt = 1.5 n_p psi where they have
 * n_p Phi (both the torque per A of q current), except a gain multiplying
 * a squared flux or current: (12)'s gamma is MC_POWER_INVARIANT_SQ times
 * larger here. */
#define MC_POWER_INVARIANT_SQ 1.5f

typedef struct {
    float R_ohm;         /* stator resistance, >= 0 */
    float Ld_H, Lq_H;    /* d/q inductances, > 0 */
    float psi_Wb;        /* PM flux linkage, > 0 */
    uint32_t pole_pairs; /* n_p in [1, MC_MOTOR_POLE_PAIRS_MAX] */
    float J_kgm2;        /* inertia, > 0 */
    float B_Nm_s_rad;    /* viscous friction, >= 0 */
} mc_motor_params_t;

/* Finite values in the ranges above: MC_OK, MC_ERR_NONFINITE or
 * MC_ERR_PARAM. Interrupt context: no. */
mc_status_t mc_motor_validate(const mc_motor_params_t *m);

/* Torque per ampere of q current, 1.5 n_p psi (N m/A; surface PMSM).
 * Interrupt context: yes. */
static inline float mc_motor_kt_f32(const mc_motor_params_t *m)
{
    return 1.5f * (float)m->pole_pairs * m->psi_Wb;
}

#endif /* MC_MOTOR_H */
