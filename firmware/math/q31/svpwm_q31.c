/* Q31 space-vector PWM (see mc/svpwm_q31.h). Integer only. */
#include "mc/svpwm_q31.h"

#include "mc/clarke_q31.h"

/* floor(2^62 / 3): v_alpha^2 + v_beta^2 (Q62, integer) > 1/3 exactly iff it
 * exceeds this value. */
#define SVPWM_CIRCLE_SQ_Q62 ((uint64_t)1537228672809129301U)
#define SVPWM_ONE_Q31       ((int64_t)1 << 31)
#define SVPWM_ONE_Q62       ((int64_t)1 << 62)

/* round(num / den) for num >= 0 and den > 0 (both callers divide by a
 * magnitude their branch has just shown to exceed 2^30). */
static int64_t div_round_positive(int64_t num, int64_t den)
{
    return (num + den / 2) / den;
}

static void min_max(const int64_t v[3], int64_t *v_min, int64_t *v_max)
{
    *v_min = v[0];
    *v_max = v[0];
    for (int k = 1; k < 3; ++k) {
        *v_min = v[k] < *v_min ? v[k] : *v_min;
        *v_max = v[k] > *v_max ? v[k] : *v_max;
    }
}

/* Scale (alpha, beta) by the Q31 factor `scale` in [0, 1). */
static void scale_command(mc_q31_t scale, mc_q31_t *alpha, mc_q31_t *beta)
{
    *alpha = mc_mul_sat_q31(*alpha, scale);
    *beta = mc_mul_sat_q31(*beta, scale);
}

/* Sector 1..6 of atan2(beta, alpha) from three sign tests:
 * A: beta >= 0                     (theta in [0, 180))
 * B: sqrt(3) alpha - beta > 0      (theta in (-120, 60))
 * C: -sqrt(3) alpha - beta > 0     (theta in (120, 300))
 * code A + 2B + 4C: 3 -> 1, 1 -> 2, 5 -> 3, 4 -> 4, 6 -> 5, 2 -> 6
 * (codes 0 and 7 are impossible; they map to 1). The comparisons are made on
 * sqrt(3)/2 alpha vs beta/2 in Q62, exact up to the constant's rounding. */
static uint8_t sector_of(mc_q31_t alpha, mc_q31_t beta)
{
    static const uint8_t sector_of_code[8] = { 1U, 2U, 6U, 1U, 4U, 3U, 5U, 1U };
    if (alpha == 0 && beta == 0) {
        return 1U;
    }
    const int64_t alpha_q62 = (int64_t)alpha * MC_Q31_SQRT3_BY_2;
    const int64_t half_beta_q62 = (int64_t)beta * ((int64_t)1 << 30);
    const unsigned a = beta >= 0 ? 1U : 0U;
    const unsigned b = alpha_q62 - half_beta_q62 > 0 ? 1U : 0U;
    const unsigned c = -alpha_q62 - half_beta_q62 > 0 ? 1U : 0U;
    return sector_of_code[a + 2U * b + 4U * c];
}

mc_status_t mc_svpwm_q31(mc_q31_t v_alpha_pu, mc_q31_t v_beta_pu,
                         mc_svpwm_limit_t limit, mc_svpwm_out_q31_t *out)
{
    if (limit != MC_SVPWM_LIMIT_CIRCLE && limit != MC_SVPWM_LIMIT_HEXAGON) {
        return MC_ERR_PARAM;
    }
    mc_q31_t alpha = v_alpha_pu;
    mc_q31_t beta = v_beta_pu;
    bool reduced = false;
    int64_t v[3];
    int64_t v_min;
    int64_t v_max;

    if (limit == MC_SVPWM_LIMIT_CIRCLE) {
        /* |alpha|, |beta| <= 2^31: the sum of squares is <= 2^63, fits. */
        const uint64_t mag_sq_q62 = (uint64_t)((int64_t)alpha * alpha) +
                                    (uint64_t)((int64_t)beta * beta);
        if (mag_sq_q62 > SVPWM_CIRCLE_SQ_Q62) {
            /* mag > 2^31/sqrt(3) > 0, so the division is safe and the factor
             * (1/sqrt(3)) / |v| is in (0, 1). */
            const int64_t mag_q31 = (int64_t)mc_isqrt_u64(mag_sq_q62);
            const int64_t scale =
                div_round_positive(MC_Q31_INV_SQRT3 * SVPWM_ONE_Q31, mag_q31);
            scale_command(mc_sat_q31(scale), &alpha, &beta);
            reduced = true;
        }
        mc_inv_clarke_wide_q31(alpha, beta, v);
    } else {
        mc_inv_clarke_wide_q31(alpha, beta, v);
        min_max(v, &v_min, &v_max);
        const int64_t spread = v_max - v_min;
        if (spread > SVPWM_ONE_Q31) {
            /* spread > 2^31 > 0: factor 1 / spread in (0, 1) */
            const int64_t scale = div_round_positive(SVPWM_ONE_Q62, spread);
            scale_command(mc_sat_q31(scale), &alpha, &beta);
            mc_inv_clarke_wide_q31(alpha, beta, v);
            reduced = true;
        }
    }

    min_max(v, &v_min, &v_max);
    for (int k = 0; k < 3; ++k) {
        /* duty = 1/2 + v_k - (max + min)/2, computed in Q32 and rounded once;
         * a rounding excess beyond [0, 1] saturates. */
        const int64_t duty_q32 = SVPWM_ONE_Q31 + 2 * v[k] - v_max - v_min;
        const int64_t duty = mc_round_shift_q63(duty_q32, 1U);
        out->duty[k] = duty < 0 ? 0 : mc_sat_q31(duty);
    }
    out->sector = sector_of(v_alpha_pu, v_beta_pu);
    out->overmodulated = reduced;
    out->v_alpha_pu = alpha;
    out->v_beta_pu = beta;
    return MC_OK;
}
