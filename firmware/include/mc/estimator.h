/*
 * The interface every angle/speed estimator of the list (mc/estimators.h)
 * implements, in its own glue file (firmware/app/est_<name>.c):
 *
 *   mc_est_<name>_config_default(cfg)       its configuration block
 *   mc_est_<name>_params[]                  the block's parameter table
 *   mc_est_<name>_info(cfg)                 what it provides and needs
 *   mc_est_<name>_init(est, cfg, timing)    design; MC_OK or the error
 *   mc_est_<name>_hold(est, theta_e_rad)    the observers stop and report
 *                                           this angle (ALIGN starts)
 *   mc_est_<name>_start(est, in)            restart at in->theta_e_hold_rad
 *                                           with this sample (ALIGN ends)
 *   mc_est_<name>_step(est, in, t, sc)      one sample: theta_e, theta_m,
 *                                           omega_m, tau_L_hat (and
 *                                           flux_ratio_sq) into *t; fault
 *                                           bits. It writes only finite
 *                                           values (a non-finite one is
 *                                           MC_FAULT_NONFINITE and leaves
 *                                           *t as it was), and the sine
 *                                           and cosine of t->theta_e_rad
 *                                           after the step into *sc
 * Interrupt context: hold, start and step yes; the others no.
 */
#ifndef MC_ESTIMATOR_H
#define MC_ESTIMATOR_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/angle.h"
#include "mc/compiler.h"
#include "mc/delay_comp.h"
#include "mc/drive_io.h"
#include "mc/params.h"
#include "mc/status.h"
#include "mc/timing.h"

typedef struct mc_config mc_config_t;

typedef struct {
    bool sensorless;             /* angle from the currents: the drive
                                    aligns the rotor first (mc/align.h) */
    bool provides_load;          /* tau_L_hat is an estimate (else 0) */
    float speed_bandwidth_rad_s; /* of the speed estimate (0: not stated;
                                    a speed loop must stay below half) */
    uint32_t encoder_cpr;        /* counts per revolution expected from
                                    the HAL (0: no encoder used) */
} mc_estimator_info_t;

/* One sample as the estimators see it. */
typedef struct {
    uint32_t encoder_count;                    /* hal_encoder_count() */
    float i_alpha_A, i_beta_A;                 /* offset-corrected, Clarke */
    const mc_applied_voltage_f32_t *v_applied; /* mean voltage over the
                                                  last interval */
    bool running;           /* RUN: observers step; else held */
    bool slow_tick;         /* a slow-loop tick (mc/app.h): the sample on
                               which an estimator re-anchors what it
                               accumulates (mc_flux_obs_update_f32's
                               angle) and runs its plausibility tests
                               (mc/est_flux_front.h) */
    float theta_e_hold_rad; /* angle reported while held (the
                               ALIGN vector's) */
} mc_est_input_t;

/* The sine and cosine of the reported electrical angle, for the
 * controller's Park and inverse Park: an estimator may have them cheaper
 * than from the angle (mc/est_flux_front.h). */
typedef struct {
    float sin_e, cos_e;
} mc_est_sincos_t;

/* *sc = sin, cos of theta_e_rad by the out-of-line mc_sincos_f32, for a
 * step's uncommon paths: through locals, so the address of *sc is not
 * taken and the common path keeps it in registers. Interrupt context:
 * yes. */
MC_STATIC_FORCEINLINE void mc_est_sincos_of(float theta_e_rad,
                                            mc_est_sincos_t *sc)
{
    float s;
    float c;
    mc_sincos_f32(theta_e_rad, &s, &c);
    sc->sin_e = s;
    sc->cos_e = c;
}

/* Declares the interface above for estimator `name`, after its
 * mc_est_<name>_config_t and mc_est_<name>_t: the parameter table and every
 * function but the step, which the glue header defines
 * MC_STATIC_FORCEINLINE (it runs in the ISR). One declaration for every
 * estimator, so their signatures cannot drift apart. */
#define MC_ESTIMATOR_INTERFACE(name)                                           \
    extern const mc_param_t mc_est_##name##_params[];                          \
    void mc_est_##name##_config_default(mc_est_##name##_config_t *c);          \
    mc_estimator_info_t mc_est_##name##_info(const mc_config_t *cfg);          \
    mc_status_t mc_est_##name##_init(mc_est_##name##_t *est,                   \
                                     const mc_config_t *cfg,                   \
                                     const mc_timing_t *tm);                   \
    void mc_est_##name##_hold(mc_est_##name##_t *est, float theta_e_rad);      \
    uint32_t mc_est_##name##_start(mc_est_##name##_t *est, float theta_e_rad,  \
                                   const mc_est_input_t *in)

#endif /* MC_ESTIMATOR_H */
