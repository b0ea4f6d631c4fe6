/*
 * Compensated (Kahan) accumulation for float32 estimator states (the
 * observers' inline steps, mc/pll_observer.h, mc/speed_load_observer.h).
 *
 * An estimator state such as a speed of 333 rad/s (ulp 3e-5 rad/s) gets
 * per-sample increments far below its ulp; plain rounding then acts as a
 * small, slowly varying disturbance that the observer loop turns into
 * steady-state errors (measured: 0.04 rpm and 3e-3 N m in the speed/load
 * observer). Carrying the rounding error of each addition into the next one
 * makes the accumulation as accurate as the increments themselves.
 * Needs IEEE arithmetic without reassociation (no -ffast-math, which the
 * project does not use); no multiplications, so FMA contraction cannot
 * break it. Interrupt context: yes.
 */
#ifndef MC_COMPENSATED_SUM_H
#define MC_COMPENSATED_SUM_H

#include "mc/compiler.h"

/* Returns sum + increment (with the carried error comp applied) and writes
 * the new carried error to *comp_out. */
MC_STATIC_FORCEINLINE float mc_kahan_add_f32(float sum, float comp,
                                             float increment, float *comp_out)
{
    const float y = increment - comp;
    const float s = sum + y;
    *comp_out = (s - sum) - y;
    return s;
}

#endif /* MC_COMPENSATED_SUM_H */
