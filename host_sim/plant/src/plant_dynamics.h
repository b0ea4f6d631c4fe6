/*
 * plant_dynamics.h - right-hand side of the PMSM + mechanics + DC-link ODE
 * (model in plant.h) and the state-vector layout. Internal to sim_plant.
 */
#ifndef SIM_PLANT_DYNAMICS_H
#define SIM_PLANT_DYNAMICS_H

#include "plant.h"
#include "plant_inverter.h"

enum {
    PX_ID,    /* i_d [A] */
    PX_IQ,    /* i_q [A] */
    PX_OMEGA, /* omega_m [rad/s] */
    PX_THETA, /* theta_m [rad], continuous */
    PX_E_BUS, /* energy accumulators [J], see plant_energy_t */
    PX_E_ELEC,
    PX_E_CU,
    PX_E_FRIC,
    PX_E_LOAD,
    PX_E_COG,
    PX_VA_INT, /* int v_a dt over the current period [V s] */
    PX_VB_INT,
    PX_VC_INT,
    PX_VDC, /* link voltage [V]: integrated only with a capacitance */
    PX_E_SRC,
    PX_E_RSRC,
    PX_E_BRAKE,
    PX_E_CLAMP,
    PX_LEN
};

/* The elements integrated with a stiff bus (the link elements stay 0). */
#define PX_STIFF_LEN PX_VDC

_Static_assert(PX_LEN == PLANT_PRIVATE_STATE_LEN, "state length");

/* The electrical side at one state: phase currents (dq -> abc, not yet
 * projected), phase (star) voltages, rotor-frame voltages, current
 * derivatives, bridge current and bus power. */
typedef struct {
    double i_abc_A[3];
    double v_abc_V[3];
    double v_d_V, v_q_V;
    double di_d_A_s, di_q_A_s;
    double p_bus_W;
    double i_bridge_A;
    double u_float_V;  /* the floating terminal, when exactly one phase floats */
    double e_abc_V[3]; /* the back-EMF, when two or more phases float */
} plant_elec_t;

/* Instantaneous quantities at one evaluation (for the true-state view). */
typedef struct {
    double i_abc_A[3]; /* dq -> abc of the state */
    double v_abc_V[3];
    double tau_e_Nm, tau_load_Nm, tau_cog_Nm, tau_friction_Nm;
    double v_dc_V, v_source_V;
    double i_bridge_A, i_source_A, i_brake_A;
} plant_aux_t;

/* Link voltage of state x (the state, or the stiff bus held in src). */
static inline double plant_link_voltage(const plant_t *p, const plant_source_t *src,
                                        const double x[PX_LEN])
{
    return p->link_dynamic ? x[PX_VDC] : src->v_dc_V;
}

/* The electrical side in the general case (diode bridge, floating phases),
 * with c, s = cos, sin(theta_e) of the state. */
void plant_electrical(const plant_t *p, const plant_source_t *src, const double x[PX_LEN], double c,
                      double s, plant_elec_t *el);

/* dx/dt at time t_s for state x under the voltage source src and the
 * plant's conduction states. The load and source profiles are evaluated on
 * their pieces active at t_piece_s (the midpoint of the integration step;
 * see sim_profile_eval_on_piece). aux may be NULL. The link elements
 * (PX_VDC ..) are written only with a capacitance. */
void plant_derivatives(const plant_t *p, const plant_source_t *src, double t_s, double t_piece_s,
                       const double x[PX_LEN], double dx[PX_LEN], plant_aux_t *aux);

/* tau_cog(theta_m) = sum_k A_k cos(k Q theta_m + phi_k) [N m]. */
double plant_cogging_torque(const plant_t *p, double theta_m_rad);

/* B omega + the smoothed Coulomb torque at omega [N m]. */
double plant_friction_torque(const plant_motor_params_t *m, double omega_rad_s);

#endif /* SIM_PLANT_DYNAMICS_H */
