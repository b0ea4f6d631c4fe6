#include "plant_inverter.h"

/* Dead-time current shape s(i): sign(i), or linear inside +-band. */
static double current_sign(double i_A, double band_A)
{
    if (band_A > 0.0) {
        const double u = i_A / band_A;
        return u > 1.0 ? 1.0 : (u < -1.0 ? -1.0 : u);
    }
    return (i_A > 0.0) ? 1.0 : ((i_A < 0.0) ? -1.0 : 0.0);
}

void plant_inverter_phase_voltages(const plant_source_t *src, const double i_abc[3],
                                   double v_phase[3], double *p_bus_W)
{
    double v_term[3];
    double p_bus = 0.0;
    for (int x = 0; x < 3; ++x) {
        if (src->kind == PLANT_SRC_INVERTER) {
            v_term[x] =
                src->duty[x] * src->v_dc_V - current_sign(i_abc[x], src->i_band_A) * src->v_error_V;
            p_bus += src->duty[x] * src->v_dc_V * i_abc[x];
        } else { /* diodes: i > 0 returns through the low side, i < 0 the high side */
            v_term[x] = 0.5 * src->v_dc_V * (1.0 - current_sign(i_abc[x], 0.0));
            p_bus += v_term[x] * i_abc[x];
        }
    }
    const double common = (v_term[0] + v_term[1] + v_term[2]) / 3.0;
    for (int x = 0; x < 3; ++x) {
        v_phase[x] = v_term[x] - common;
    }
    *p_bus_W = p_bus;
}
