#include "plant_inverter.h"

double plant_inverter_terminal_V(const plant_source_t *src, int x, double i_A, double v_dc_V,
                                 double v_error_V)
{
    return src->duty[x] * v_dc_V - plant_current_sign(i_A, src->i_band_A) * v_error_V;
}
