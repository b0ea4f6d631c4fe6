/* Computation / PWM delay: angle advance and applied-voltage history.
 * See mc/delay_comp.h. */
#include "mc/delay_comp.h"

static int delay_periods_valid(float d)
{
    return d >= MC_DELAY_PERIODS_MIN && d <= MC_DELAY_PERIODS_MAX;
}

mc_status_t mc_delay_comp_init_f32(mc_delay_comp_f32_t *dc, float Ts_s,
                                   float delay_periods, bool enabled)
{
    if (!isfinite(Ts_s) || !isfinite(delay_periods)) {
        return MC_ERR_NONFINITE;
    }
    if (Ts_s <= 0.0f || !delay_periods_valid(delay_periods)) {
        return MC_ERR_PARAM;
    }
    dc->advance_s = delay_periods * Ts_s;
    dc->enabled = enabled;
    dc->sin_advance = 0.0f;
    dc->cos_advance = 1.0f;
    return MC_OK;
}

mc_status_t mc_applied_voltage_init_f32(mc_applied_voltage_f32_t *av,
                                        float delay_periods)
{
    if (!isfinite(delay_periods)) {
        return MC_ERR_NONFINITE;
    }
    if (!delay_periods_valid(delay_periods)) {
        return MC_ERR_PARAM;
    }
    av->w_older = delay_periods - 0.5f;
    av->w_newer = 1.0f - av->w_older;
    return mc_applied_voltage_reset_f32(av, 0.0f, 0.0f);
}

mc_status_t mc_applied_voltage_reset_f32(mc_applied_voltage_f32_t *av,
                                         float v_alpha_V, float v_beta_V)
{
    if (!isfinite(v_alpha_V) || !isfinite(v_beta_V)) {
        return MC_ERR_NONFINITE;
    }
    av->v_older_V[0] = v_alpha_V;
    av->v_older_V[1] = v_beta_V;
    av->v_newer_V[0] = v_alpha_V;
    av->v_newer_V[1] = v_beta_V;
    return MC_OK;
}
