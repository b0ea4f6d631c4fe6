/*
 * Space-vector PWM by min-max injection. See mc/svpwm.h: the common case
 * is inline there, the limit and the checked variant here.
 */
#include "mc/svpwm.h"

#include <float.h>
#include <math.h>

#include "mc/clarke.h"

/* Sector from the indices of the largest and smallest phase voltage:
 * sector 1 (0..60 deg): a max, c min; 2: b max, c min; 3: b max, a min;
 * 4: c max, a min; 5: c max, b min; 6: a max, b min. Indexed [max][min]. */
static const uint8_t sector_by_max_min[3][3] = {
    { 1u, 6u, 1u },
    { 3u, 2u, 2u },
    { 4u, 5u, 4u },
};

/* The sector of the phase voltages v_V (the first index of the largest
 * and of the smallest). */
static uint8_t sector_of(const float v_V[3])
{
    uint8_t i_max = 0u;
    uint8_t i_min = 0u;
    for (uint8_t i = 1u; i < 3u; i++) {
        if (v_V[i] > v_V[i_max]) {
            i_max = i;
        }
        if (v_V[i] < v_V[i_min]) {
            i_min = i;
        }
    }
    return sector_by_max_min[i_max][i_min];
}

mc_svpwm_out_f32_t mc_svpwm_edge_f32(float v_alpha_V, float v_beta_V,
                                     float v_dc_V, mc_svpwm_limit_t limit)
{
    mc_svpwm_out_f32_t out;
    out.sector = 0u;
    mc_svpwm_phases_t p = mc_svpwm_phases_f32(v_alpha_V, v_beta_V);
    const float spread_V = p.max_V - p.min_V;
    /* Overmodulation: the command normalised by its (finite, > 0) phase
     * spread, times a factor k that puts it on the boundary. Working with
     * the normalised vector avoids overflow of |v|^2 and underflow of a
     * tiny r/|v| ratio for absurdly large commands. */
    bool overmodulated = false;
    float k_V = 0.0f;
    if (limit == MC_SVPWM_LIMIT_HEXAGON) {
        if (spread_V > v_dc_V) { /* outside the hexagon: spread -> v_dc */
            overmodulated = true;
            k_V = v_dc_V;
        }
    } else if (spread_V > v_dc_V * MC_SQRT3_BY_2_F) {
        /* possibly outside the circle |v| = v_dc/sqrt(3), since the spread
         * lies in [1.5, sqrt(3)] |v| */
        const float inv_spread = 1.0f / spread_V; /* guarded: spread > 0 */
        const float a_n = v_alpha_V * inv_spread;
        const float b_n = v_beta_V * inv_spread;
        const float mag_n = sqrtf(a_n * a_n + b_n * b_n); /* >= 1/sqrt(3) */
        const float r_lin_V = v_dc_V * MC_INV_SQRT3_F;
        if (mag_n * spread_V > r_lin_V) {
            overmodulated = true;
            k_V = r_lin_V / mag_n; /* guarded: mag_n >= 1/sqrt(3) */
        }
    }
    if (overmodulated) {
        /* A positive factor keeps the angle and the phase ordering. */
        const float inv_spread = 1.0f / spread_V; /* guarded: spread > 0 */
        v_alpha_V = (v_alpha_V * inv_spread) * k_V;
        v_beta_V = (v_beta_V * inv_spread) * k_V;
        for (uint8_t i = 0u; i < 3u; i++) {
            p.v_V[i] = (p.v_V[i] * inv_spread) * k_V;
        }
        p.max_V = (p.max_V * inv_spread) * k_V;
        p.min_V = (p.min_V * inv_spread) * k_V;
    }
    /* Rounding can push the boundary phases a few ulp outside [0,1] at
     * full modulation; this is not a limit, only float noise: clamped. */
    const float inv_v_dc = 1.0f / v_dc_V; /* guarded: v_dc >= FLT_MIN */
    mc_svpwm_duties_f32(&p, inv_v_dc, true, out.duty);
    out.overmodulated = overmodulated;
    out.v_alpha_V = v_alpha_V;
    out.v_beta_V = v_beta_V;
    return out;
}

mc_status_t mc_svpwm_f32(float v_alpha_V, float v_beta_V, float v_dc_V,
                         mc_svpwm_limit_t limit, mc_svpwm_out_f32_t *out)
{
    if (!isfinite(v_alpha_V) || !isfinite(v_beta_V) || !isfinite(v_dc_V)) {
        return MC_ERR_NONFINITE;
    }
    if (!(v_dc_V >= FLT_MIN)) { /* <= 0 or denormal: 1/v_dc would overflow */
        return MC_ERR_RANGE;
    }
    if (limit != MC_SVPWM_LIMIT_CIRCLE && limit != MC_SVPWM_LIMIT_HEXAGON) {
        return MC_ERR_PARAM;
    }
    const mc_svpwm_phases_t p = mc_svpwm_phases_f32(v_alpha_V, v_beta_V);
    if (!isfinite(p.max_V - p.min_V)) {
        return MC_ERR_RANGE; /* finite command too large for float */
    }
    mc_svpwm_unchecked_f32(v_alpha_V, v_beta_V, v_dc_V, limit, out);
    out->sector = sector_of(p.v_V);
    return MC_OK;
}
