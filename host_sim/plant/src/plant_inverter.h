/*
 * plant_inverter.h - switching-period average model of the two-level
 * inverter and the source kinds of an integrated period part (model and
 * sign conventions documented in plant.h). Internal.
 */
#ifndef SIM_PLANT_INVERTER_H
#define SIM_PLANT_INVERTER_H

#include <stdbool.h>

typedef enum {
    PLANT_SRC_INVERTER, /* outputs on: switching, duties held over the period */
    PLANT_SRC_DIODES,   /* outputs off: the six-diode bridge */
    PLANT_SRC_IDEAL_DQ  /* ideal rotor-frame voltage source (no inverter) */
} plant_source_kind_t;

typedef struct {
    plant_source_kind_t kind;
    double duty[3];      /* clamped to [0, 1] */
    double v_dc_V;       /* stiff bus: held over the period, >= 0 */
    double v_error_V;    /* stiff bus: t_dead f_pwm v_dc + v_drop, per-phase magnitude */
    double i_band_A;     /* dead-time linear zone, 0 = hard sign */
    double v_d_V, v_q_V; /* PLANT_SRC_IDEAL_DQ only */
} plant_source_t;

/* Dead-time current shape s(i): sign(i), or linear inside +-band. */
static inline double plant_current_sign(double i_A, double band_A)
{
    if (band_A > 0.0) {
        const double u = i_A / band_A;
        return u > 1.0 ? 1.0 : (u < -1.0 ? -1.0 : u);
    }
    return (i_A > 0.0) ? 1.0 : ((i_A < 0.0) ? -1.0 : 0.0);
}

/* Terminal voltage (w.r.t. the negative rail) of switching phase x on the
 * bus v_dc_V with the dead-time error magnitude v_error_V (the general
 * path: plant_electrical). */
double plant_inverter_terminal_V(const plant_source_t *src, int x, double i_A, double v_dc_V,
                                 double v_error_V);

/* Phase-to-star voltages v_phase (common mode removed) of the switching
 * inverter (kind PLANT_SRC_INVERTER) for phase currents i_abc, and the
 * power drawn from the bus [W]. Inline: the simulator's innermost loop. */
static inline void plant_inverter_phase_voltages(const plant_source_t *src, double v_dc_V,
                                                 double v_error_V, const double i_abc[3],
                                                 double v_phase[3], double *p_bus_W)
{
    double v_term[3];
    double p_bus = 0.0;
    for (int x = 0; x < 3; ++x) {
        v_term[x] = src->duty[x] * v_dc_V - plant_current_sign(i_abc[x], src->i_band_A) * v_error_V;
        p_bus += src->duty[x] * v_dc_V * i_abc[x];
    }
    const double common = (v_term[0] + v_term[1] + v_term[2]) / 3.0;
    for (int x = 0; x < 3; ++x) {
        v_phase[x] = v_term[x] - common;
    }
    *p_bus_W = p_bus;
}

#endif /* SIM_PLANT_INVERTER_H */
