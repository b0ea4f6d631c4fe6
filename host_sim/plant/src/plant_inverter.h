/*
 * plant_inverter.h - switching-period average model of the two-level
 * inverter (model and sign conventions documented in plant.h). Internal.
 */
#ifndef SIM_PLANT_INVERTER_H
#define SIM_PLANT_INVERTER_H

#include <stdbool.h>

typedef enum {
    PLANT_SRC_INVERTER, /* switching, duties held over the period */
    PLANT_SRC_DISABLED, /* all switches off, currents freewheel via diodes */
    PLANT_SRC_OPEN,     /* disabled and currents extinguished: i == 0 */
    PLANT_SRC_IDEAL_DQ  /* ideal rotor-frame voltage source (no inverter) */
} plant_source_kind_t;

typedef struct {
    plant_source_kind_t kind;
    double duty[3];      /* clamped to [0, 1] */
    double v_dc_V;       /* held over the period, >= 0 */
    double v_error_V;    /* t_dead f_pwm v_dc + v_drop: per-phase magnitude */
    double i_band_A;     /* dead-time linear zone, 0 = hard sign */
    double v_d_V, v_q_V; /* PLANT_SRC_IDEAL_DQ only */
} plant_source_t;

/* Phase-to-star voltages v_phase (common mode removed) of the inverter for
 * phase currents i_abc, and the power drawn from the bus [W].
 * kind must be PLANT_SRC_INVERTER or PLANT_SRC_DISABLED. */
void plant_inverter_phase_voltages(const plant_source_t *src, const double i_abc[3],
                                   double v_phase[3], double *p_bus_W);

#endif /* SIM_PLANT_INVERTER_H */
