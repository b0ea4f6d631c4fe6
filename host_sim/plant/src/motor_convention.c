/* Motor parameter frames (motor_convention.h). */
#include "motor_convention.h"

void plant_motor_to_amplitude_invariant(plant_motor_params_t *m,
                                        plant_motor_convention_t convention)
{
    if (convention == PLANT_POWER_INVARIANT) {
        m->psi_Wb /= PLANT_POWER_INVARIANT_GAIN;
    }
}
