/* The CAN node (mc/can_node.h): frame filter, the motion commands, the
 * command timeout and the poll. Parameter commands: can_node_param.c;
 * telemetry: can_tlm.c. */
#include <math.h>
#include <stddef.h>

#include "can_node_internal.h"
#include "hal/time.h"
#include "pmsm_can.h"

#define TIMEOUT_MAX_S       60.0f
#define US_PER_S            1000000u
#define DEFAULT_TIMEOUT_S   0.1f
#define DEFAULT_STATUS_DECI 1000u

void mc_can_node_config_default(mc_can_node_config_t *cfg)
{
    *cfg = (mc_can_node_config_t){
        .node_id = 0u,
        .timeout_s = DEFAULT_TIMEOUT_S,
    };
    cfg->decimation[PMSM_CAN_TLM_STATUS_FRAME_ID - MC_CAN_TLM_FIRST] =
        DEFAULT_STATUS_DECI;
}

mc_status_t mc_can_node_init(mc_can_node_t *n, const mc_can_node_config_t *cfg,
                             const mc_config_t *drive_cfg,
                             mc_can_apply_config_fn apply, void *apply_ctx)
{
    if (n == NULL || cfg == NULL || drive_cfg == NULL ||
        cfg->node_id > MC_CAN_NODE_ID_MAX || !isfinite(cfg->timeout_s) ||
        !(cfg->timeout_s > 0.0f) || !(cfg->timeout_s <= TIMEOUT_MAX_S)) {
        return MC_ERR_PARAM;
    }
    const uint32_t hz = hal_time_tick_hz();
    if (hz == 0u) {
        return MC_ERR_PARAM;
    }
    /* timeout in whole microseconds (<= 6e7), then ticks: <= 6e7 * 2^32,
     * far from 2^64 */
    uint32_t us = (uint32_t)(cfg->timeout_s * (float)US_PER_S + 0.5f);
    if (us == 0u) {
        us = 1u;
    }
    *n = (mc_can_node_t){
        .cfg = *cfg,
        .drive_cfg = *drive_cfg,
        .apply = apply,
        .apply_ctx = apply_ctx,
        .cmd = { .mode = MC_MODE_CURRENT },
        .timeout_ticks = (uint64_t)us * hz / US_PER_S,
    };
    return MC_OK;
}

const mc_can_counters_t *mc_can_node_counters(const mc_can_node_t *n)
{
    return &n->counters;
}

void mc_can_node_send(mc_can_node_t *n, uint32_t msg, const uint8_t *data,
                      uint8_t dlc)
{
    hal_can_frame_t f = {
        .id = (n->cfg.node_id << MC_CAN_MSG_BITS) | (msg & MC_CAN_MSG_MASK),
        .dlc = dlc,
    };
    for (uint32_t i = 0u; i < dlc && i < HAL_CAN_MAX_DLC; ++i) {
        f.data[i] = data[i];
    }
    if (hal_can_send(&f) == HAL_OK) {
        n->counters.tx_frames++;
    } else {
        n->counters.tx_drops++;
    }
}

static void reply_error(mc_can_node_t *n, uint32_t msg, mc_can_reject_t cause,
                        uint8_t dlc)
{
    const struct pmsm_can_rsp_error_t r = {
        .rejected_cmd = (uint8_t)msg,
        .cause = (uint8_t)cause,
        .rejected_dlc =
            (dlc > HAL_CAN_MAX_DLC) ? (uint8_t)HAL_CAN_MAX_DLC : dlc,
    };
    uint8_t data[PMSM_CAN_RSP_ERROR_LENGTH];
    (void)pmsm_can_rsp_error_pack(data, &r, sizeof(data));
    mc_can_node_send(n, PMSM_CAN_RSP_ERROR_FRAME_ID, data, sizeof(data));
}

/* ---- which frames are ours ---------------------------------------------- */

typedef enum {
    FRAME_IGNORE,  /* not for us: not counted */
    FRAME_UNKNOWN, /* ours, extended or remote: rejected */
    FRAME_COMMAND  /* ours, a data frame to handle */
} frame_class_t;

static bool sent_by_drive(uint32_t msg)
{
    return (msg >= MC_CAN_TLM_FIRST &&
            msg < MC_CAN_TLM_FIRST + MC_CAN_TLM_COUNT) ||
           msg == PMSM_CAN_RSP_PARAM_FRAME_ID ||
           msg == PMSM_CAN_RSP_ERROR_FRAME_ID;
}

static frame_class_t classify(const mc_can_node_t *n, const hal_can_frame_t *f)
{
    if (f->id > HAL_CAN_STD_ID_MAX ||
        (f->id >> MC_CAN_MSG_BITS) != n->cfg.node_id ||
        sent_by_drive(f->id & MC_CAN_MSG_MASK)) {
        return FRAME_IGNORE;
    }
    return (f->extended || f->rtr) ? FRAME_UNKNOWN : FRAME_COMMAND;
}

/* The DBC length of command msg; false: not a command. */
static bool command_length(uint32_t msg, uint8_t *len)
{
    switch (msg) {
    case PMSM_CAN_CMD_ENABLE_FRAME_ID: *len = PMSM_CAN_CMD_ENABLE_LENGTH; break;
    case PMSM_CAN_CMD_MODE_FRAME_ID: *len = PMSM_CAN_CMD_MODE_LENGTH; break;
    case PMSM_CAN_CMD_CURRENT_FRAME_ID:
        *len = PMSM_CAN_CMD_CURRENT_LENGTH;
        break;
    case PMSM_CAN_CMD_SPEED_FRAME_ID: *len = PMSM_CAN_CMD_SPEED_LENGTH; break;
    case PMSM_CAN_CMD_POSITION_FRAME_ID:
        *len = PMSM_CAN_CMD_POSITION_LENGTH;
        break;
    case PMSM_CAN_CMD_CLEAR_FAULTS_FRAME_ID:
        *len = PMSM_CAN_CMD_CLEAR_FAULTS_LENGTH;
        break;
    case PMSM_CAN_CMD_PARAM_READ_FRAME_ID:
        *len = PMSM_CAN_CMD_PARAM_READ_LENGTH;
        break;
    case PMSM_CAN_CMD_PARAM_WRITE_FRAME_ID:
        *len = PMSM_CAN_CMD_PARAM_WRITE_LENGTH;
        break;
    case PMSM_CAN_CMD_CONTROLLER_FRAME_ID:
        *len = PMSM_CAN_CMD_CONTROLLER_LENGTH;
        break;
    case PMSM_CAN_CMD_TELEMETRY_RATE_FRAME_ID:
        *len = PMSM_CAN_CMD_TELEMETRY_RATE_LENGTH;
        break;
    default: return false;
    }
    return true;
}

/* ---- the motion commands ------------------------------------------------ */

/* a float32 command value: finite and inside the DBC range */
static bool value_ok(float v, bool in_range)
{
    return isfinite(v) && in_range;
}

static mc_can_reject_t cmd_enable(mc_can_node_t *n, const uint8_t *d)
{
    struct pmsm_can_cmd_enable_t m;
    (void)pmsm_can_cmd_enable_unpack(&m, d, PMSM_CAN_CMD_ENABLE_LENGTH);
    if (!pmsm_can_cmd_enable_enable_is_in_range(m.enable)) {
        return MC_CAN_REJ_BAD_VALUE;
    }
    n->cmd.enable = (m.enable != 0u);
    return MC_CAN_REJ_NONE;
}

static mc_can_reject_t cmd_mode(mc_can_node_t *n, const uint8_t *d)
{
    struct pmsm_can_cmd_mode_t m;
    (void)pmsm_can_cmd_mode_unpack(&m, d, PMSM_CAN_CMD_MODE_LENGTH);
    if (!pmsm_can_cmd_mode_mode_is_in_range(m.mode)) {
        return MC_CAN_REJ_BAD_VALUE;
    }
    switch (m.mode) {
    case PMSM_CAN_CMD_MODE_MODE_CURRENT_CHOICE:
        n->cmd.mode = MC_MODE_CURRENT;
        break;
    case PMSM_CAN_CMD_MODE_MODE_SPEED_CHOICE:
        n->cmd.mode = MC_MODE_SPEED;
        break;
    case PMSM_CAN_CMD_MODE_MODE_POSITION_CHOICE:
        n->cmd.mode = MC_MODE_POSITION;
        break;
    default: return MC_CAN_REJ_BAD_VALUE; /* a range the DBC widened */
    }
    return MC_CAN_REJ_NONE;
}

static mc_can_reject_t cmd_current(mc_can_node_t *n, const uint8_t *d)
{
    struct pmsm_can_cmd_current_t m;
    (void)pmsm_can_cmd_current_unpack(&m, d, PMSM_CAN_CMD_CURRENT_LENGTH);
    const float i_d = pmsm_can_cmd_current_i_d_ref_decode(m.i_d_ref);
    const float i_q = pmsm_can_cmd_current_i_q_ref_decode(m.i_q_ref);
    if (!value_ok(i_d, pmsm_can_cmd_current_i_d_ref_is_in_range(m.i_d_ref)) ||
        !value_ok(i_q, pmsm_can_cmd_current_i_q_ref_is_in_range(m.i_q_ref))) {
        return MC_CAN_REJ_BAD_VALUE;
    }
    n->cmd.i_d_ref_A = i_d;
    n->cmd.i_q_ref_A = i_q;
    return MC_CAN_REJ_NONE;
}

static mc_can_reject_t cmd_speed(mc_can_node_t *n, const uint8_t *d)
{
    struct pmsm_can_cmd_speed_t m;
    (void)pmsm_can_cmd_speed_unpack(&m, d, PMSM_CAN_CMD_SPEED_LENGTH);
    const float w = pmsm_can_cmd_speed_omega_ref_decode(m.omega_ref);
    if (!value_ok(w, pmsm_can_cmd_speed_omega_ref_is_in_range(m.omega_ref))) {
        return MC_CAN_REJ_BAD_VALUE;
    }
    n->cmd.omega_m_ref_rad_s = w;
    return MC_CAN_REJ_NONE;
}

static mc_can_reject_t cmd_position(mc_can_node_t *n, const uint8_t *d)
{
    struct pmsm_can_cmd_position_t m;
    (void)pmsm_can_cmd_position_unpack(&m, d, PMSM_CAN_CMD_POSITION_LENGTH);
    const float th = pmsm_can_cmd_position_theta_ref_decode(m.theta_ref);
    if (!value_ok(th,
                  pmsm_can_cmd_position_theta_ref_is_in_range(m.theta_ref))) {
        return MC_CAN_REJ_BAD_VALUE;
    }
    n->cmd.theta_m_ref_rad = th;
    return MC_CAN_REJ_NONE;
}

static mc_can_reject_t cmd_clear_faults(mc_can_node_t *n)
{
    n->cmd.clear_fault = true;
    n->clear_pending = true;
    n->clear_armed = false; /* a snapshot after this raise is needed */
    return MC_CAN_REJ_NONE;
}

static mc_can_reject_t cmd_telemetry_rate(mc_can_node_t *n, const uint8_t *d)
{
    struct pmsm_can_cmd_telemetry_rate_t m;
    (void)pmsm_can_cmd_telemetry_rate_unpack(
        &m, d, PMSM_CAN_CMD_TELEMETRY_RATE_LENGTH);
    if (!pmsm_can_cmd_telemetry_rate_telemetry_msg_is_in_range(
            m.telemetry_msg) ||
        !pmsm_can_cmd_telemetry_rate_decimation_is_in_range(m.decimation) ||
        m.telemetry_msg < MC_CAN_TLM_FIRST ||
        m.telemetry_msg >= MC_CAN_TLM_FIRST + MC_CAN_TLM_COUNT) {
        return MC_CAN_REJ_BAD_VALUE;
    }
    n->cfg.decimation[m.telemetry_msg - MC_CAN_TLM_FIRST] = m.decimation;
    return MC_CAN_REJ_NONE;
}

/* One frame of ours that is a data frame: the cause, MC_CAN_REJ_NONE when
 * accepted. */
static mc_can_reject_t handle_command(mc_can_node_t *n, mc_app_t *app,
                                      const hal_can_frame_t *f, uint32_t msg,
                                      bool *answered)
{
    uint8_t len;
    if (!command_length(msg, &len)) {
        return MC_CAN_REJ_UNKNOWN_MESSAGE;
    }
    if (f->dlc != len) {
        return MC_CAN_REJ_WRONG_DLC;
    }
    switch (msg) {
    case PMSM_CAN_CMD_ENABLE_FRAME_ID: return cmd_enable(n, f->data);
    case PMSM_CAN_CMD_MODE_FRAME_ID: return cmd_mode(n, f->data);
    case PMSM_CAN_CMD_CURRENT_FRAME_ID: return cmd_current(n, f->data);
    case PMSM_CAN_CMD_SPEED_FRAME_ID: return cmd_speed(n, f->data);
    case PMSM_CAN_CMD_POSITION_FRAME_ID: return cmd_position(n, f->data);
    case PMSM_CAN_CMD_CLEAR_FAULTS_FRAME_ID: return cmd_clear_faults(n);
    case PMSM_CAN_CMD_PARAM_READ_FRAME_ID:
        return mc_can_node_param_read(n, f, answered);
    case PMSM_CAN_CMD_PARAM_WRITE_FRAME_ID:
        return mc_can_node_param_write(n, app, f, answered);
    case PMSM_CAN_CMD_CONTROLLER_FRAME_ID:
        return mc_can_node_controller(n, app, f, answered);
    case PMSM_CAN_CMD_TELEMETRY_RATE_FRAME_ID:
        return cmd_telemetry_rate(n, f->data);
    default: return MC_CAN_REJ_UNKNOWN_MESSAGE; /* not reached */
    }
}

static void hand_command(mc_can_node_t *n, mc_app_t *app)
{
    (void)mc_app_set_command(app, &n->cmd); /* the mode is always valid */
}

static void handle_frame(mc_can_node_t *n, mc_app_t *app,
                         const hal_can_frame_t *f)
{
    const frame_class_t c = classify(n, f);
    if (c == FRAME_IGNORE) {
        return;
    }
    n->counters.rx_frames++;
    const uint32_t msg = f->id & MC_CAN_MSG_MASK;
    bool answered = false;
    const mc_can_reject_t cause =
        (c == FRAME_UNKNOWN) ? MC_CAN_REJ_UNKNOWN_MESSAGE
                             : handle_command(n, app, f, msg, &answered);
    if (cause != MC_CAN_REJ_NONE) {
        n->counters.rejected[cause]++;
        if (!answered) {
            reply_error(n, msg, cause, f->dlc);
        }
        return;
    }
    n->counters.rx_accepted++;
    n->last_valid_ticks = hal_time_ticks();
    n->have_valid = true;
    n->cmd.comm_lost = false;
    hand_command(n, app);
}

/* ---- timeout, the clear pulse, the poll --------------------------------- */

static void check_timeout(mc_can_node_t *n, mc_app_t *app)
{
    if (!n->cmd.enable || n->cmd.comm_lost) {
        return;
    }
    const uint64_t now = hal_time_ticks();
    const uint64_t elapsed =
        (now >= n->last_valid_ticks) ? now - n->last_valid_ticks : 0u;
    if (elapsed > n->timeout_ticks) {
        n->cmd.comm_lost = true;
        n->counters.timeouts++;
        hand_command(n, app);
    }
}

/* Lower clear_fault once an ISR has run after the raise (see the header). */
static void clear_pulse(mc_can_node_t *n, mc_app_t *app,
                        const mc_telemetry_t *t)
{
    if (!n->clear_pending) {
        return;
    }
    if (!n->clear_armed) {
        n->clear_armed = true;
        n->clear_isr_count = t->isr_count;
    } else if (t->isr_count != n->clear_isr_count) {
        n->clear_pending = false;
        n->cmd.clear_fault = false;
        hand_command(n, app);
    }
}

void mc_can_node_poll(mc_can_node_t *n, mc_app_t *app)
{
    for (uint32_t k = 0u; k < MC_CAN_NODE_RX_PER_POLL; ++k) {
        hal_can_frame_t f;
        if (hal_can_receive(&f) != HAL_OK) {
            break;
        }
        handle_frame(n, app, &f);
    }
    check_timeout(n, app);
    mc_telemetry_t t;
    if (mc_app_get_telemetry(app, &t) != MC_OK) {
        return;
    }
    clear_pulse(n, app, &t);
    mc_can_node_telemetry(n, &t);
}
