/*
 * Parameter tables: the configuration's fields by name, type and place, so
 * that readers of the configuration (the simulator's scenario files, a
 * parameter protocol) take the names from the firmware instead of keeping
 * their own copy. Ranges are not here: mc_config_validate() is the one
 * judge of values (it runs every block's own checks).
 *
 * A block table is an array of mc_param_t ended by an entry with a NULL
 * name; offsets are relative to the block's configuration struct.
 */
#ifndef MC_PARAMS_H
#define MC_PARAMS_H

#include <stddef.h>
#include <stdint.h>

typedef enum {
    MC_PARAM_F32 = 0,    /* float */
    MC_PARAM_U32,        /* uint32_t */
    MC_PARAM_BOOL,       /* bool */
    MC_PARAM_CONTROLLER, /* mc_controller_t, by mc_controller_name() */
    MC_PARAM_ESTIMATOR   /* mc_estimator_t, by mc_estimator_name() */
} mc_param_type_t;

typedef struct {
    const char *name; /* the field name, units in it (NULL: end) */
    mc_param_type_t type;
    uint32_t offset; /* bytes from the start of the block */
} mc_param_t;

#define MC_PARAM(block_type, member, type)                                     \
    {                                                                          \
#member, (type), (uint32_t)offsetof(block_type, member)                \
    }
#define MC_PARAM_END                                                           \
    {                                                                          \
        NULL, MC_PARAM_F32, 0u                                                 \
    }

/* Bytes of a field of this type (0 for an unknown type). Interrupt
 * context: yes. */
size_t mc_param_size(mc_param_type_t type);

typedef struct {
    const char *name; /* block key ("" for the top level) */
    uint32_t offset;  /* bytes from the start of mc_config_t */
    const mc_param_t *params;
} mc_param_block_t;

#endif /* MC_PARAMS_H */
