/*
 * plant_dynamics.h - right-hand side of the PMSM + mechanics ODE (model in
 * plant.h) and the state-vector layout. Internal to sim_plant.
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
    PX_LEN
};

_Static_assert(PX_LEN == PLANT_PRIVATE_STATE_LEN, "state length");

/* Instantaneous quantities at one evaluation (for the true-state view). */
typedef struct {
    double i_abc_A[3];
    double v_abc_V[3];
    double tau_e_Nm, tau_load_Nm, tau_cog_Nm, tau_friction_Nm;
} plant_aux_t;

/* dx/dt at time t_s for state x under the voltage source src. The load
 * profile is evaluated on its piece active at t_piece_s (the midpoint of
 * the integration step; see sim_profile_eval_on_piece). aux may be NULL. */
void plant_derivatives(const plant_t *p, const plant_source_t *src, double t_s, double t_piece_s,
                       const double x[PX_LEN], double dx[PX_LEN], plant_aux_t *aux);

/* tau_cog(theta_m) = sum_k A_k cos(k Q theta_m + phi_k) [N m]. */
double plant_cogging_torque(const plant_t *p, double theta_m_rad);

#endif /* SIM_PLANT_DYNAMICS_H */
