/*
 * Space-vector PWM by min-max injection. See mc/svpwm.h.
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

typedef struct {
    float v[3];
    uint8_t i_max;
    uint8_t i_min;
} phase_spread_t;

static phase_spread_t phase_spread(float v_alpha_V, float v_beta_V)
{
    phase_spread_t p;
    mc_inv_clarke_f32(v_alpha_V, v_beta_V, &p.v[0], &p.v[1], &p.v[2]);
    p.i_max = 0u;
    p.i_min = 0u;
    for (uint8_t i = 1u; i < 3u; i++) {
        if (p.v[i] > p.v[p.i_max]) {
            p.i_max = i;
        }
        if (p.v[i] < p.v[p.i_min]) {
            p.i_min = i;
        }
    }
    return p;
}

/* The modulator proper on the command's phase spread p: the limit, the
 * common-mode offset, the duties and the voltage applied (all of *out but
 * the sector). */
static void modulate_spread(phase_spread_t p, float v_alpha_V, float v_beta_V,
                            float v_dc_V, mc_svpwm_limit_t limit,
                            mc_svpwm_out_f32_t *out)
{
    const float spread_V = p.v[p.i_max] - p.v[p.i_min];
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
            p.v[i] = (p.v[i] * inv_spread) * k_V;
        }
    }
    const float v_offset_V = -0.5f * (p.v[p.i_max] + p.v[p.i_min]);
    const float inv_v_dc = 1.0f / v_dc_V; /* guarded: v_dc >= FLT_MIN */
    for (uint8_t i = 0u; i < 3u; i++) {
        float d = 0.5f + (p.v[i] + v_offset_V) * inv_v_dc;
        /* Rounding can push the boundary phases a few ulp outside [0,1]
         * at full modulation; this is not a limit, only float noise. */
        d = (d < 0.0f) ? 0.0f : ((d > 1.0f) ? 1.0f : d);
        out->duty[i] = d;
    }
    out->overmodulated = overmodulated;
    out->v_alpha_V = v_alpha_V;
    out->v_beta_V = v_beta_V;
}

void mc_svpwm_unchecked_f32(float v_alpha_V, float v_beta_V, float v_dc_V,
                            mc_svpwm_limit_t limit, mc_svpwm_out_f32_t *out)
{
    modulate_spread(phase_spread(v_alpha_V, v_beta_V), v_alpha_V, v_beta_V,
                    v_dc_V, limit, out);
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
    const phase_spread_t p = phase_spread(v_alpha_V, v_beta_V);
    if (!isfinite(p.v[p.i_max] - p.v[p.i_min])) {
        return MC_ERR_RANGE; /* finite command too large for float */
    }
    modulate_spread(p, v_alpha_V, v_beta_V, v_dc_V, limit, out);
    out->sector = sector_by_max_min[p.i_max][p.i_min];
    return MC_OK;
}
