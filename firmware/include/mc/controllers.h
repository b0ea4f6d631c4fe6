/*
 * THE list of controllers. A controller is one entry here plus its own
 * files: its blocks (firmware/control/), its glue (mc/ctl_<name>.h,
 * firmware/app/ctl_<name>.c, the interface of mc/drive.h) and, for the
 * simulator, its scenario keys (they come from its parameter table).
 * Everything else (the enum, the configuration member cfg.<name>, the
 * instance, the dispatch, the names in scenario files) is generated from
 * this list (firmware/README.md, "Adding a controller").
 *
 * X(name, NAME): name is the configuration key and the scenario name.
 */
#ifndef MC_CONTROLLERS_H
#define MC_CONTROLLERS_H

#include "mc/ctl_cdobc.h"
#include "mc/ctl_eeo.h"
#include "mc/ctl_foc_pi.h"
#include "mc/ctl_idapbc.h"

#define MC_CONTROLLERS(X)                                                      \
    X(foc_pi, FOC_PI)                                                          \
    X(idapbc, IDAPBC)                                                          \
    X(eeo, EEO)                                                                \
    X(cdobc, CDOBC)

typedef enum {
#define MC_X_ENUM(name, NAME) MC_CONTROLLER_##NAME,
    MC_CONTROLLERS(MC_X_ENUM)
#undef MC_X_ENUM
        MC_CONTROLLER_COUNT
} mc_controller_t;

/* The instance of the selected controller. */
typedef union {
#define MC_X_MEMBER(name, NAME) mc_ctl_##name##_t name;
    MC_CONTROLLERS(MC_X_MEMBER)
#undef MC_X_MEMBER
} mc_controller_instance_t;

/* Name of a controller ("foc_pi"), NULL for an unknown value.
 * Interrupt context: yes. */
const char *mc_controller_name(mc_controller_t id);

#endif /* MC_CONTROLLERS_H */
