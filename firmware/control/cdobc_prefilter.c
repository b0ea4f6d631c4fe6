/* Reference prefilter of the paper 002 regulator (two degrees of
 * freedom), float32 step, double design. See mc/cdobc.h. */
#include <math.h>

#include "mc/cdobc.h"

mc_status_t mc_cdobc_prefilter_init_f32(mc_cdobc_prefilter_f32_t *f, float Ts_s,
                                        float ctl_pole_rad_s,
                                        float ref_pole_rad_s)
{
    if (!isfinite(Ts_s) || !isfinite(ctl_pole_rad_s) ||
        !isfinite(ref_pole_rad_s)) {
        return MC_ERR_NONFINITE;
    }
    const double Ts = (double)Ts_s;
    const double x_c = (double)ctl_pole_rad_s * Ts;
    const double x_m = (double)ref_pole_rad_s * Ts;
    if (!(Ts > 0.0) || !(x_c > 0.0) || !(x_m > 0.0) || !(x_c <= 1.0) ||
        !(x_m <= 1.0)) {
        return MC_ERR_PARAM;
    }
    const double a = exp(-x_c);
    const double a_m = exp(-x_m);
    /* 1 - a = -expm1(-x) without cancellation; > 0 for 0 < x <= 1 */
    const double r = expm1(-x_m) / expm1(-x_c);
    const double g = r * r;
    *f = (mc_cdobc_prefilter_f32_t){
        .g_minus_1 = (float)(g - 1.0),
        .c0 = (float)(a_m * a_m - g * a * a),
        .two_a_m = (float)(2.0 * a_m),
        .a_m_sq = (float)(a_m * a_m),
    };
    return MC_OK;
}
