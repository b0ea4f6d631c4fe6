/*
 * Private to firmware/comm: the pieces of the CAN node (mc/can_node.h)
 * shared by its source files. Message numbers and lengths are the
 * generated codec's node-0 frame ids and lengths (pmsm_can.h).
 */
#ifndef MC_CAN_NODE_INTERNAL_H
#define MC_CAN_NODE_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>

#include "hal/can.h"
#include "mc/can_node.h"
#include "mc/can_params.h"

#define MC_CAN_MSG_BITS 5u /* message number bits */
#define MC_CAN_MSG_MASK ((1u << MC_CAN_MSG_BITS) - 1u)

/* Rsp_Param Status (the DBC's value table). */
typedef enum {
    MC_CAN_PARAM_OK = 0,
    MC_CAN_PARAM_UNKNOWN_ID = 1,
    MC_CAN_PARAM_REFUSED = 2,
    MC_CAN_PARAM_INVALID = 3,
    MC_CAN_PARAM_WRONG_TYPE = 4
} mc_can_param_status_t;

/* Queue a frame of this node's message msg (hal_can_send), counted in
 * tx_frames or tx_drops. */
void mc_can_node_send(mc_can_node_t *n, uint32_t msg, const uint8_t *data,
                      uint8_t dlc);

/* Parameter commands (can_node_param.c): the frame has passed the DLC
 * check. *answered: a Rsp_Param went out (then no Rsp_Error follows).
 * Returns the rejection cause, MC_CAN_REJ_NONE when accepted. */
mc_can_reject_t mc_can_node_param_read(mc_can_node_t *n,
                                       const hal_can_frame_t *f,
                                       bool *answered);
mc_can_reject_t mc_can_node_param_write(mc_can_node_t *n, mc_app_t *app,
                                        const hal_can_frame_t *f,
                                        bool *answered);
mc_can_reject_t mc_can_node_controller(mc_can_node_t *n, mc_app_t *app,
                                       const hal_can_frame_t *f,
                                       bool *answered);

/* What a telemetry frame is made of besides the snapshot. */
typedef struct {
    const mc_telemetry_t *tlm;
    bool enabled;        /* the node's command */
    uint32_t controller; /* the configuration in force */
    float cost_avg_s;    /* Tlm_IsrCost mean */
    const mc_can_counters_t *counters;
    hal_can_stats_t stats; /* hal_can_stats() */
} mc_can_tlm_input_t;

/* Build telemetry message msg (16..24) of node node_id: every signal from
 * in (saturated into its DBC range, non-finite = the maximum), Counter =
 * counter, then the E2E CRC. false for another msg. */
bool mc_can_tlm_frame(uint32_t node_id, uint32_t msg,
                      const mc_can_tlm_input_t *in, uint8_t counter,
                      hal_can_frame_t *f);

/* Send the telemetry that is due (can_tlm.c). */
void mc_can_node_telemetry(mc_can_node_t *n, const mc_telemetry_t *t);

#endif /* MC_CAN_NODE_INTERNAL_H */
