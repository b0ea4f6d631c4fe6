/*
 * Plausibility bounds of mechanical estimates (speed, load torque), shared by
 * the sensorless speed/load estimators (mc/speed_load_observer.h,
 * mc/pll_observer.h).
 *
 * A diverging observer shows up as an estimate far outside anything the drive
 * can do; the application checks the estimates against configured bounds
 * every sample and treats a violation as a fault (never clamps it away).
 *
 * Units: rad/s (mechanical), N m.
 */
#ifndef MC_ESTIMATE_BOUNDS_H
#define MC_ESTIMATE_BOUNDS_H

#include <math.h>
#include <stdbool.h>

#include "mc/compiler.h"
#include "mc/status.h"

typedef struct {
    float omega_m_max_rad_s; /* |omega_m_hat| above this is implausible, > 0 */
    float tau_max_Nm;        /* |tau_L_hat| above this is implausible, > 0 */
} mc_estimate_bounds_t;

/* MC_OK if both bounds are finite and > 0, else MC_ERR_PARAM.
 * Interrupt context: yes (but meant for init). */
static inline mc_status_t
mc_estimate_bounds_validate(const mc_estimate_bounds_t *b)
{
    const int ok = isfinite(b->omega_m_max_rad_s) && isfinite(b->tau_max_Nm) &&
                   b->omega_m_max_rad_s > 0.0f && b->tau_max_Nm > 0.0f;
    return ok ? MC_OK : MC_ERR_PARAM;
}

/* True if |omega_m_rad_s| <= omega_m_max and |tau_Nm| <= tau_max; false
 * for NaN and Inf too (the bounds are finite). Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool
mc_estimate_bounds_hold(const mc_estimate_bounds_t *b, float omega_m_rad_s,
                        float tau_Nm)
{
    return fabsf(omega_m_rad_s) <= b->omega_m_max_rad_s &&
           fabsf(tau_Nm) <= b->tau_max_Nm;
}

/* MC_OK if |omega_m_rad_s| <= omega_m_max and |tau_Nm| <= tau_max,
 * MC_ERR_NONFINITE for NaN/Inf, MC_ERR_RANGE otherwise.
 * Interrupt context: yes. */
static inline mc_status_t
mc_estimate_bounds_check(const mc_estimate_bounds_t *b, float omega_m_rad_s,
                         float tau_Nm)
{
    /* the common case first */
    if (mc_estimate_bounds_hold(b, omega_m_rad_s, tau_Nm)) {
        return MC_OK;
    }
    if (!isfinite(omega_m_rad_s) || !isfinite(tau_Nm)) {
        return MC_ERR_NONFINITE;
    }
    return MC_ERR_RANGE;
}

#endif /* MC_ESTIMATE_BOUNDS_H */
