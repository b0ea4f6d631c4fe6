/*
 * The drive's configuration, grouped by block. Motor parameters are the
 * controller's NOMINAL values (the plant may differ). Every quantity has
 * one spelling, units in the name, SI.
 *
 * The blocks shared by every controller and estimator are written here;
 * the controller and estimator blocks (cfg.<name>) come from their lists
 * (mc/controllers.h, mc/estimators.h), their types from their glue
 * headers. mc_config_params() publishes every field by name (mc/params.h).
 *
 * Validation runs the same block inits the drive runs (on a scratch
 * instance) plus the rules between blocks (config.c); each block states
 * its own ranges in its header.
 */
#ifndef MC_CONFIG_H
#define MC_CONFIG_H

#include <stdint.h>

#include "mc/align.h"
#include "mc/controllers.h"
#include "mc/current_loop.h"
#include "mc/deadtime_comp.h"
#include "mc/emf_monitor.h"
#include "mc/est_flux_front.h"
#include "mc/estimate_bounds.h"
#include "mc/estimators.h"
#include "mc/faults.h"
#include "mc/motor.h"
#include "mc/params.h"
#include "mc/status.h"
#include "mc/timing.h"

/* Reference limits of the control (documented limits, not protections). */
typedef struct {
    float i_max_A;         /* |i_dq_ref| limit, (0, protection.i_trip_A) */
    float omega_max_rad_s; /* speed reference limit, > 0 */
} mc_limits_config_t;

typedef struct {
    float kp_per_s; /* P gain of the position loop, > 0 */
} mc_position_config_t;

typedef struct mc_config {
    mc_controller_t controller; /* one of mc/controllers.h */
    mc_estimator_t estimator;   /* one of mc/estimators.h */
    mc_motor_params_t motor;
    mc_timing_config_t timing;
    mc_limits_config_t limits;
    mc_fault_limits_t protection; /* trip levels (mc/faults.h) */
    mc_current_loop_config_t current;
    mc_deadtime_config_t deadtime; /* inverter dead time (mc/deadtime_comp.h) */
    mc_position_config_t position;
    mc_align_config_t align;         /* sensorless start (mc/align.h) */
    mc_flux_obs_config_t flux_obs;   /* sensorless front end */
    mc_emf_check_config_t emf_check; /* estimators' back-EMF plausibility */
#define MC_X_MEMBER(name, NAME) mc_ctl_##name##_config_t name;
    MC_CONTROLLERS(MC_X_MEMBER)
#undef MC_X_MEMBER
#define MC_X_MEMBER(name, NAME) mc_est_##name##_config_t name;
    MC_ESTIMATORS(MC_X_MEMBER)
#undef MC_X_MEMBER
} mc_config_t;

/* Defaults for the paper-001 motor (R 0.225 ohm, L 3.8 mH, psi 0.17 Wb,
 * n_p 3, J 0.012 kg m^2) on a 48 V bus at 20 kHz with the baseline FOC and
 * the encoder; see config.c and each block's default for every value and
 * its reason. Interrupt context: no. */
void mc_config_init_default(mc_config_t *cfg);

/* Check a configuration: finite values, each block's own rules (its init
 * on a scratch instance, with the timing as if the HAL realised the
 * requested period exactly), the rules between blocks. MC_OK,
 * MC_ERR_NONFINITE or MC_ERR_PARAM. Interrupt context: no (about 1.5 kB
 * of stack). */
mc_status_t mc_config_validate(const mc_config_t *cfg);

/* The parameter blocks, NULL-name terminated: "" (controller, estimator),
 * then one per block in the order of mc_config_t, named like its member.
 * Interrupt context: yes (constant data). */
const mc_param_block_t *mc_config_params(void);

/* What the configured estimator provides and needs (mc/estimator.h); all
 * zero for an estimator outside the list. Interrupt context: no. */
mc_estimator_info_t mc_config_estimator_info(const mc_config_t *cfg);

/* Plausibility bounds of the speed and load estimates (protection).
 * Interrupt context: yes. */
static inline mc_estimate_bounds_t
mc_config_estimate_bounds(const mc_config_t *cfg)
{
    return (mc_estimate_bounds_t){
        .omega_m_max_rad_s = cfg->protection.estimate_omega_max_rad_s,
        .tau_max_Nm = cfg->protection.estimate_tau_max_Nm,
    };
}

#endif /* MC_CONFIG_H */
