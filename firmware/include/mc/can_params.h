/*
 * The configuration's parameters on the CAN protocol (tools/dbc/
 * pmsm_drive.dbc, Cmd_ParamRead / Cmd_ParamWrite / Rsp_Param): every field
 * of mc_config_params() (mc/params.h) by a 16-bit id, with its wire type.
 *
 * Parameter id: CRC-16/CCITT-FALSE (polynomial 0x1021, initial value
 * 0xFFFF, no reflection, no final XOR; check value 0x29B1 for ASCII
 * "123456789") of the parameter's name: "block.field" (e.g.
 * "cdobc.obs_pole_rad_s"), or "field" for the top level ("controller",
 * "estimator"), as the simulator's scenario keys spell them. The ids of
 * today's table are unique (asserted by tests/unit/firmware/comm); a
 * lookup returns the first match of the table.
 *
 * Wire types (Param_type): 0 float32 (MC_PARAM_F32), 1 uint32
 * (MC_PARAM_U32, and the controller and estimator ids of mc/controllers.h
 * and mc/estimators.h), 2 bool (MC_PARAM_BOOL).
 *
 * Get and set work on a caller's mc_config_t (the node keeps the
 * configuration in force and edits a copy); they judge only the type and
 * what the field's C type can hold. Whether a value is acceptable is
 * mc_config_validate()'s business (mc/config.h).
 *
 * Bounded time: a lookup walks the table once (about 100 parameters, names
 * of at most MC_CAN_PARAM_NAME_MAX characters each part), no allocation.
 */
#ifndef MC_CAN_PARAMS_H
#define MC_CAN_PARAMS_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/config.h"
#include "mc/params.h"
#include "mc/status.h"

#define MC_CAN_PARAM_NAME_MAX                                                  \
    64u /* characters hashed of a block or field                               \
           name (longer names are cut) */

/* Param_type of Cmd_ParamWrite / Rsp_Param (the DBC's value table). */
typedef enum {
    MC_CAN_PARAM_TYPE_F32 = 0,
    MC_CAN_PARAM_TYPE_U32 = 1,
    MC_CAN_PARAM_TYPE_BOOL = 2,
    MC_CAN_PARAM_TYPE_COUNT = 3
} mc_can_param_type_t;

/* A typed value: only the member of `type` is meaningful. */
typedef struct {
    mc_can_param_type_t type;
    float f32;
    uint32_t u32;
    bool b;
} mc_can_param_value_t;

/* A parameter found in mc_config_params(). */
typedef struct {
    const mc_param_block_t *block;
    const mc_param_t *param;
    uint16_t id;
} mc_can_param_ref_t;

/* CRC-16/CCITT-FALSE of data[0 .. n). Interrupt context: yes. */
uint16_t mc_can_crc16_ccitt_false(const uint8_t *data, uint32_t n);

/* The id of parameter `field` of block `block` ("" or NULL: the top
 * level): the CRC of "block.field" resp. "field". Interrupt context: yes. */
uint16_t mc_can_param_id(const char *block, const char *field);

/* Find the parameter with this id in mc_config_params(); false (ref
 * untouched) when none has it. Interrupt context: no (walks the table). */
bool mc_can_param_find(uint16_t id, mc_can_param_ref_t *ref);

/* The wire type of a table type. Interrupt context: yes. */
mc_can_param_type_t mc_can_param_wire_type(mc_param_type_t type);

/* Read the parameter's value from cfg, typed with its wire type.
 * MC_ERR_PARAM for a ref that does not lie inside mc_config_t (not from
 * mc_can_param_find). Interrupt context: no. */
mc_status_t mc_can_param_get(const mc_config_t *cfg,
                             const mc_can_param_ref_t *ref,
                             mc_can_param_value_t *out);

/* Write one parameter of cfg; nothing else of cfg changes, and nothing at
 * all on an error: MC_ERR_PARAM for a value of another wire type than the
 * parameter's (or a bad ref), MC_ERR_NONFINITE for a NaN/Inf float,
 * MC_ERR_RANGE for a controller / estimator id outside its list.
 * Interrupt context: no. */
mc_status_t mc_can_param_set(mc_config_t *cfg, const mc_can_param_ref_t *ref,
                             const mc_can_param_value_t *value);

#endif /* MC_CAN_PARAMS_H */
