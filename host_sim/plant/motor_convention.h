/*
 * The frame a motor's parameters are given in, and their conversion to the
 * plant's.
 *
 * The plant integrates a three-phase machine in the amplitude-invariant
 * dq frame (plant.h: torque 1.5 n_p psi i_q; its currents are the phase
 * current amplitudes). Papers 000 and 001 give their motors as two-phase
 * machines, torque n_p Phi i^T Jcal rho (no 3/2): the power-invariant
 * frame of the same three-phase machine, in which currents, voltages and
 * flux linkages are sqrt(3/2) times the amplitude-invariant ones while
 * resistances, inductances, torques, speeds, inertia and friction are the
 * same (power v^T i and torque are invariant by construction). So a motor
 * given power-invariant is this plant's with psi = Phi / sqrt(3/2); its
 * paper's currents are the plant's i_alpha, i_beta times sqrt(3/2).
 * Paper 002 uses 1.5 n_p psi_f i_q: amplitude-invariant.
 */
#ifndef SIM_MOTOR_CONVENTION_H
#define SIM_MOTOR_CONVENTION_H

#include "plant.h"

typedef enum {
    PLANT_AMPLITUDE_INVARIANT = 0, /* the plant's own frame */
    PLANT_POWER_INVARIANT          /* two-phase, papers 000 and 001 */
} plant_motor_convention_t;

/* sqrt(3/2): power-invariant currents, voltages, flux linkages per
 * amplitude-invariant one. */
#define PLANT_POWER_INVARIANT_GAIN 1.2247448713915890491

/* Motor parameters given in `convention` to the plant's frame, in place
 * (psi_Wb divided by PLANT_POWER_INVARIANT_GAIN for the power-invariant
 * frame; the rest unchanged). */
void plant_motor_to_amplitude_invariant(plant_motor_params_t *m,
                                        plant_motor_convention_t convention);

#endif /* SIM_MOTOR_CONVENTION_H */
