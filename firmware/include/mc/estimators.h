/*
 * THE list of angle/speed estimators. An estimator is one entry here plus
 * its own files: its blocks (firmware/observers/), its glue
 * (mc/est_<name>.h, firmware/app/est_<name>.c, the interface of
 * mc/estimator.h). The enum, the configuration member cfg.<name>, the
 * instance, the dispatch and the scenario names come from this list.
 *
 * X(name, NAME): name is the configuration key and the scenario name.
 */
#ifndef MC_ESTIMATORS_H
#define MC_ESTIMATORS_H

#include "mc/est_encoder.h"
#include "mc/est_flux_ii.h"
#include "mc/est_flux_pll.h"

#define MC_ESTIMATORS(X)                                                       \
    X(encoder, ENCODER)                                                        \
    X(flux_ii, FLUX_II)                                                        \
    X(flux_pll, FLUX_PLL)

typedef enum {
#define MC_X_ENUM(name, NAME) MC_ESTIMATOR_##NAME,
    MC_ESTIMATORS(MC_X_ENUM)
#undef MC_X_ENUM
        MC_ESTIMATOR_COUNT
} mc_estimator_t;

/* The instance of the selected estimator. */
typedef union {
#define MC_X_MEMBER(name, NAME) mc_est_##name##_t name;
    MC_ESTIMATORS(MC_X_MEMBER)
#undef MC_X_MEMBER
} mc_estimator_instance_t;

/* Name of an estimator ("flux_ii"), NULL for an unknown value.
 * Interrupt context: yes. */
const char *mc_estimator_name(mc_estimator_t id);

#endif /* MC_ESTIMATORS_H */
