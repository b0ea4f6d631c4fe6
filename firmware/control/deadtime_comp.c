/* Dead-time and device-drop compensation (mc/deadtime_comp.h). */
#include "mc/deadtime_comp.h"

#include "mc/finite.h"

mc_status_t mc_deadtime_comp_init_f32(mc_deadtime_comp_f32_t *dc,
                                      const mc_deadtime_config_t *c, float Ts_s,
                                      float v_dc_min_V)
{
    const float f[] = { c->dead_time_s, c->device_drop_V, c->current_band_A,
                        Ts_s, v_dc_min_V };
    if (!mc_all_finite_f32(f, (uint32_t)(sizeof f / sizeof f[0]))) {
        return MC_ERR_NONFINITE;
    }
    if (!(c->dead_time_s >= 0.0f) || !(c->device_drop_V >= 0.0f) ||
        !(c->current_band_A > 0.0f) || !(Ts_s > 0.0f) ||
        (c->device_drop_V > 0.0f && !(v_dc_min_V > 0.0f))) {
        return MC_ERR_PARAM;
    }
    const float duty_time = c->dead_time_s / Ts_s; /* Ts > 0 checked */
    const float duty_drop = (c->device_drop_V > 0.0f)
                                ? c->device_drop_V / v_dc_min_V /* > 0 */
                                : 0.0f;
    if (!(duty_time + duty_drop <= MC_DEADTIME_DUTY_MAX)) {
        return MC_ERR_PARAM;
    }
    *dc = (mc_deadtime_comp_f32_t){
        .active = c->compensation && (duty_time + duty_drop > 0.0f),
        .duty_time = duty_time,
        .drop_V = c->device_drop_V,
        .inv_band_per_A = 1.0f / c->current_band_A, /* band > 0 checked */
    };
    return MC_OK;
}

bool mc_deadtime_comp_apply_active_f32(const mc_deadtime_comp_f32_t *dc,
                                       float i_a_A, float i_b_A, float i_c_A,
                                       float v_dc_V, float duty[3])
{
    const float i_abc_A[3] = { i_a_A, i_b_A, i_c_A };
    const float error = dc->duty_time + dc->drop_V / v_dc_V; /* v_dc > 0 */
    bool limited = false;
    for (int x = 0; x < 3; ++x) {
        float s = i_abc_A[x] * dc->inv_band_per_A;
        s = (s > 1.0f) ? 1.0f : ((s < -1.0f) ? -1.0f : s);
        float d = duty[x] + s * error;
        if (d > 1.0f) {
            d = 1.0f;
            limited = true;
        } else if (d < 0.0f) {
            d = 0.0f;
            limited = true;
        }
        duty[x] = d; /* a NaN current propagates: the output check faults */
    }
    return limited;
}
