/*
 * The one dispatch from the application to the selected controller and
 * estimator: a switch per operation generated from the lists
 * (mc/controllers.h, mc/estimators.h). No function pointers (the ISR path
 * stays statically analysable); no default branch: every list entry has its
 * case, and a value outside the list (init validates it) takes the
 * statement after the switch.
 */
#ifndef MC_APP_DISPATCH_H
#define MC_APP_DISPATCH_H

#include <math.h>

#include "mc/app.h"
#include "mc/compiler.h"

/* ---- controllers ---------------------------------------------------- */

static inline mc_status_t mc_dispatch_controller_init(mc_app_t *app,
                                                      const mc_config_t *cfg,
                                                      const mc_timing_t *tm)
{
    switch (cfg->controller) {
#define MC_X_CASE(name, NAME)                                                  \
    case MC_CONTROLLER_##NAME:                                                 \
        return mc_ctl_##name##_init(&app->ctl.name, cfg, tm, &app->est_info);
        MC_CONTROLLERS(MC_X_CASE)
#undef MC_X_CASE
    case MC_CONTROLLER_COUNT: break;
    }
    return MC_ERR_PARAM;
}

MC_STATIC_FORCEINLINE void mc_dispatch_controller_start(mc_app_t *app)
{
    switch (app->cfg.controller) {
#define MC_X_CASE(name, NAME)                                                  \
    case MC_CONTROLLER_##NAME: mc_ctl_##name##_start(&app->ctl.name); break;
        MC_CONTROLLERS(MC_X_CASE)
#undef MC_X_CASE
    case MC_CONTROLLER_COUNT: break;
    }
}

MC_STATIC_FORCEINLINE void
mc_dispatch_controller_mode_change(mc_app_t *app, mc_mode_t from, mc_mode_t to,
                                   const mc_telemetry_t *t)
{
    switch (app->cfg.controller) {
#define MC_X_CASE(name, NAME)                                                  \
    case MC_CONTROLLER_##NAME:                                                 \
        mc_ctl_##name##_mode_change(&app->ctl.name, &app->drive, from, to, t); \
        break;
        MC_CONTROLLERS(MC_X_CASE)
#undef MC_X_CASE
    case MC_CONTROLLER_COUNT: break;
    }
}

/* Fault bits; NONFINITE for a controller outside the list. */
MC_STATIC_FORCEINLINE uint32_t mc_dispatch_controller_step(
    mc_app_t *app, const mc_command_t *cmd, mc_telemetry_t *t)
{
    switch (app->cfg.controller) {
#define MC_X_CASE(name, NAME)                                                  \
    case MC_CONTROLLER_##NAME:                                                 \
        return mc_ctl_##name##_step(&app->ctl.name, &app->drive, cmd, t);
        MC_CONTROLLERS(MC_X_CASE)
#undef MC_X_CASE
    case MC_CONTROLLER_COUNT: break;
    }
    return MC_FAULT_NONFINITE;
}

/* ---- estimators ----------------------------------------------------- */

/* What the configured estimator provides; false for one outside the
 * list. */
static inline bool mc_dispatch_estimator_info(const mc_config_t *cfg,
                                              mc_estimator_info_t *info)
{
    switch (cfg->estimator) {
#define MC_X_CASE(name, NAME)                                                  \
    case MC_ESTIMATOR_##NAME: *info = mc_est_##name##_info(cfg); return true;
        MC_ESTIMATORS(MC_X_CASE)
#undef MC_X_CASE
    case MC_ESTIMATOR_COUNT: break;
    }
    return false;
}

static inline mc_status_t mc_dispatch_estimator_init(mc_app_t *app,
                                                     const mc_config_t *cfg,
                                                     const mc_timing_t *tm)
{
    switch (cfg->estimator) {
#define MC_X_CASE(name, NAME)                                                  \
    case MC_ESTIMATOR_##NAME:                                                  \
        return mc_est_##name##_init(&app->est.name, cfg, tm);
        MC_ESTIMATORS(MC_X_CASE)
#undef MC_X_CASE
    case MC_ESTIMATOR_COUNT: break;
    }
    return MC_ERR_PARAM;
}

MC_STATIC_FORCEINLINE void mc_dispatch_estimator_hold(mc_app_t *app,
                                                      float theta_e_rad)
{
    switch (app->cfg.estimator) {
#define MC_X_CASE(name, NAME)                                                  \
    case MC_ESTIMATOR_##NAME:                                                  \
        mc_est_##name##_hold(&app->est.name, theta_e_rad);                     \
        break;
        MC_ESTIMATORS(MC_X_CASE)
#undef MC_X_CASE
    case MC_ESTIMATOR_COUNT: break;
    }
}

/* Fault bits; NONFINITE for an estimator outside the list. */
MC_STATIC_FORCEINLINE uint32_t mc_dispatch_estimator_start(
    mc_app_t *app, float theta_e_rad, const mc_est_input_t *in)
{
    switch (app->cfg.estimator) {
#define MC_X_CASE(name, NAME)                                                  \
    case MC_ESTIMATOR_##NAME:                                                  \
        return mc_est_##name##_start(&app->est.name, theta_e_rad, in);
        MC_ESTIMATORS(MC_X_CASE)
#undef MC_X_CASE
    case MC_ESTIMATOR_COUNT: break;
    }
    return MC_FAULT_NONFINITE;
}

/* Fault bits; NONFINITE (and a NaN sine and cosine) for an estimator
 * outside the list. */
MC_STATIC_FORCEINLINE uint32_t
mc_dispatch_estimator_step(mc_app_t *app, const mc_est_input_t *in,
                           mc_telemetry_t *t, mc_est_sincos_t *sc)
{
    switch (app->cfg.estimator) {
#define MC_X_CASE(name, NAME)                                                  \
    case MC_ESTIMATOR_##NAME:                                                  \
        return mc_est_##name##_step(&app->est.name, in, t, sc);
        MC_ESTIMATORS(MC_X_CASE)
#undef MC_X_CASE
    case MC_ESTIMATOR_COUNT: break;
    }
    sc->sin_e = NAN;
    sc->cos_e = NAN;
    return MC_FAULT_NONFINITE;
}

#endif /* MC_APP_DISPATCH_H */
