/* Nominal motor model checks (mc/motor.h). */
#include "mc/motor.h"

#include "mc/faults.h"

mc_status_t mc_motor_validate(const mc_motor_params_t *m)
{
    const float f[] = { m->R_ohm,  m->Ld_H,   m->Lq_H,
                        m->psi_Wb, m->J_kgm2, m->B_Nm_s_rad };
    if (!mc_all_finite_f32(f, (uint32_t)(sizeof f / sizeof f[0]))) {
        return MC_ERR_NONFINITE;
    }
    if (m->R_ohm < 0.0f || !(m->Ld_H > 0.0f) || !(m->Lq_H > 0.0f) ||
        !(m->psi_Wb > 0.0f) || m->pole_pairs < 1u ||
        m->pole_pairs > MC_MOTOR_POLE_PAIRS_MAX || !(m->J_kgm2 > 0.0f) ||
        m->B_Nm_s_rad < 0.0f) {
        return MC_ERR_PARAM;
    }
    return MC_OK;
}
