/* The CAN node's parameter commands (mc/can_node.h): Cmd_ParamRead,
 * Cmd_ParamWrite, Cmd_Controller, each answered with Rsp_Param once the
 * frame itself is well-formed. */
#include <math.h>
#include <stddef.h>

#include "can_node_internal.h"
#include "pmsm_can.h"

static void reply_param(mc_can_node_t *n, uint16_t id,
                        const mc_can_param_value_t *v,
                        mc_can_param_status_t status)
{
    struct pmsm_can_rsp_param_t r = {
        .param_id = id,
        .param_type = (uint8_t)v->type,
        .status = (uint8_t)status,
    };
    switch (v->type) {
    case MC_CAN_PARAM_TYPE_F32: r.value_f32 = v->f32; break;
    case MC_CAN_PARAM_TYPE_U32: r.value_u32 = v->u32; break;
    case MC_CAN_PARAM_TYPE_BOOL: r.value_bool = v->b ? 1u : 0u; break;
    case MC_CAN_PARAM_TYPE_COUNT: break;
    }
    uint8_t data[PMSM_CAN_RSP_PARAM_LENGTH];
    (void)pmsm_can_rsp_param_pack(data, &r, sizeof(data));
    mc_can_node_send(n, PMSM_CAN_RSP_PARAM_FRAME_ID, data, sizeof(data));
}

/* The reply to a rejection: the value in force of a known parameter, a
 * zero of the requested type for an unknown id. */
static mc_can_reject_t refuse(mc_can_node_t *n, uint16_t id,
                              const mc_can_param_ref_t *ref,
                              mc_can_param_type_t type,
                              mc_can_param_status_t status,
                              mc_can_reject_t cause, bool *answered)
{
    mc_can_param_value_t v = { .type = type };
    if (ref != NULL) {
        (void)mc_can_param_get(&n->drive_cfg, ref, &v);
    }
    reply_param(n, id, &v, status);
    *answered = true;
    return cause;
}

/* Writes are allowed only while the drive is stopped and its command does
 * not enable it (see the header). */
static bool drive_stopped(const mc_can_node_t *n, const mc_app_t *app)
{
    mc_telemetry_t t;
    return n->apply != NULL && !n->cmd.enable &&
           mc_app_get_telemetry(app, &t) == MC_OK &&
           (t.state == MC_STATE_IDLE || t.state == MC_STATE_FAULT);
}

mc_can_reject_t mc_can_node_param_read(mc_can_node_t *n,
                                       const hal_can_frame_t *f, bool *answered)
{
    struct pmsm_can_cmd_param_read_t m;
    (void)pmsm_can_cmd_param_read_unpack(&m, f->data,
                                         PMSM_CAN_CMD_PARAM_READ_LENGTH);
    if (!pmsm_can_cmd_param_read_param_id_is_in_range(m.param_id)) {
        return MC_CAN_REJ_BAD_VALUE;
    }
    mc_can_param_ref_t ref;
    if (!mc_can_param_find(m.param_id, &ref)) {
        return refuse(n, m.param_id, NULL, MC_CAN_PARAM_TYPE_F32,
                      MC_CAN_PARAM_UNKNOWN_ID, MC_CAN_REJ_UNKNOWN_PARAM,
                      answered);
    }
    mc_can_param_value_t v;
    if (mc_can_param_get(&n->drive_cfg, &ref, &v) != MC_OK) {
        return refuse(n, m.param_id, NULL, MC_CAN_PARAM_TYPE_F32,
                      MC_CAN_PARAM_UNKNOWN_ID, MC_CAN_REJ_UNKNOWN_PARAM,
                      answered);
    }
    reply_param(n, m.param_id, &v, MC_CAN_PARAM_OK);
    *answered = true;
    return MC_CAN_REJ_NONE;
}

/* Put one parameter value in force: find, type, state, validation,
 * apply. */
static mc_can_reject_t write_value(mc_can_node_t *n, mc_app_t *app, uint16_t id,
                                   const mc_can_param_value_t *v,
                                   bool *answered)
{
    mc_can_param_ref_t ref;
    if (!mc_can_param_find(id, &ref)) {
        return refuse(n, id, NULL, v->type, MC_CAN_PARAM_UNKNOWN_ID,
                      MC_CAN_REJ_UNKNOWN_PARAM, answered);
    }
    if (v->type != mc_can_param_wire_type(ref.param->type)) {
        return refuse(n, id, &ref, v->type, MC_CAN_PARAM_WRONG_TYPE,
                      MC_CAN_REJ_WRONG_PARAM_TYPE, answered);
    }
    if (!drive_stopped(n, app)) {
        return refuse(n, id, &ref, v->type, MC_CAN_PARAM_REFUSED,
                      MC_CAN_REJ_REFUSED_STATE, answered);
    }
    mc_config_t next = n->drive_cfg;
    if (mc_can_param_set(&next, &ref, v) != MC_OK ||
        mc_config_validate(&next) != MC_OK) {
        return refuse(n, id, &ref, v->type, MC_CAN_PARAM_INVALID,
                      MC_CAN_REJ_BAD_VALUE, answered);
    }
    const mc_status_t st = n->apply(n->apply_ctx, &next);
    /* a re-initialised drive starts with a zero command: hand ours again
     * (it does not enable the drive: drive_stopped) */
    (void)mc_app_set_command(app, &n->cmd);
    if (st == MC_ERR_STATE) {
        return refuse(n, id, &ref, v->type, MC_CAN_PARAM_REFUSED,
                      MC_CAN_REJ_REFUSED_STATE, answered);
    }
    if (st != MC_OK) {
        return refuse(n, id, &ref, v->type, MC_CAN_PARAM_INVALID,
                      MC_CAN_REJ_BAD_VALUE, answered);
    }
    n->drive_cfg = next;
    mc_can_param_value_t now;
    (void)mc_can_param_get(&n->drive_cfg, &ref, &now);
    reply_param(n, id, &now, MC_CAN_PARAM_OK);
    *answered = true;
    return MC_CAN_REJ_NONE;
}

mc_can_reject_t mc_can_node_param_write(mc_can_node_t *n, mc_app_t *app,
                                        const hal_can_frame_t *f,
                                        bool *answered)
{
    struct pmsm_can_cmd_param_write_t m;
    (void)pmsm_can_cmd_param_write_unpack(&m, f->data,
                                          PMSM_CAN_CMD_PARAM_WRITE_LENGTH);
    if (!pmsm_can_cmd_param_write_param_id_is_in_range(m.param_id) ||
        !pmsm_can_cmd_param_write_param_type_is_in_range(m.param_type)) {
        return MC_CAN_REJ_BAD_VALUE;
    }
    mc_can_param_value_t v = { .type = MC_CAN_PARAM_TYPE_F32 };
    switch (m.param_type) {
    case PMSM_CAN_CMD_PARAM_WRITE_PARAM_TYPE_F32_CHOICE:
        v.type = MC_CAN_PARAM_TYPE_F32;
        v.f32 = pmsm_can_cmd_param_write_value_f32_decode(m.value_f32);
        if (!isfinite(v.f32) ||
            !pmsm_can_cmd_param_write_value_f32_is_in_range(m.value_f32)) {
            return MC_CAN_REJ_BAD_VALUE;
        }
        break;
    case PMSM_CAN_CMD_PARAM_WRITE_PARAM_TYPE_U32_CHOICE:
        v.type = MC_CAN_PARAM_TYPE_U32;
        if (!pmsm_can_cmd_param_write_value_u32_is_in_range(m.value_u32)) {
            return MC_CAN_REJ_BAD_VALUE;
        }
        v.u32 = m.value_u32;
        break;
    case PMSM_CAN_CMD_PARAM_WRITE_PARAM_TYPE_BOOL_CHOICE:
        v.type = MC_CAN_PARAM_TYPE_BOOL;
        if (!pmsm_can_cmd_param_write_value_bool_is_in_range(m.value_bool)) {
            return MC_CAN_REJ_BAD_VALUE;
        }
        v.b = (m.value_bool != 0u);
        break;
    default: return MC_CAN_REJ_BAD_VALUE; /* a range the DBC widened */
    }
    return write_value(n, app, m.param_id, &v, answered);
}

mc_can_reject_t mc_can_node_controller(mc_can_node_t *n, mc_app_t *app,
                                       const hal_can_frame_t *f, bool *answered)
{
    struct pmsm_can_cmd_controller_t m;
    (void)pmsm_can_cmd_controller_unpack(&m, f->data,
                                         PMSM_CAN_CMD_CONTROLLER_LENGTH);
    if (!pmsm_can_cmd_controller_controller_is_in_range(m.controller)) {
        return MC_CAN_REJ_BAD_VALUE;
    }
    const mc_can_param_value_t v = { .type = MC_CAN_PARAM_TYPE_U32,
                                     .u32 = m.controller };
    return write_value(n, app, mc_can_param_id("", "controller"), &v, answered);
}
