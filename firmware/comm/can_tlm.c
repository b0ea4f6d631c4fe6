/* The CAN node's telemetry (mc/can_node.h): messages 16..24 from the
 * telemetry snapshot, saturated into the DBC ranges, E2E-protected. */
#include <math.h>
#include <stddef.h>

#include "can_node_internal.h"
#include "hal/can.h"
#include "mc/angle.h"
#include "mc/can_e2e.h"
#include "pmsm_can.h"
#include "pmsm_can_limits.h"

#define US_PER_S 1.0e6f

/* The fields the node fills by mask must hold what they carry. */
_Static_assert(MC_FAULT_ALL <= PMSM_CAN_TLM_STATUS_FAULTS_LATCHED_RAW_MAX,
               "Tlm_Status.Faults_latched cannot hold every fault bit");
_Static_assert(MC_FAULT_ALL <= PMSM_CAN_TLM_STATUS_FIRST_FAULT_RAW_MAX,
               "Tlm_Status.First_fault cannot hold every fault bit");
_Static_assert(PMSM_CAN_TLM_ERRORS_RX_UNKNOWN_RAW_MAX == 255u &&
                   PMSM_CAN_TLM_ERRORS_RX_BAD_DLC_RAW_MAX == 255u &&
                   PMSM_CAN_TLM_ERRORS_RX_BAD_VALUE_RAW_MAX == 255u &&
                   PMSM_CAN_TLM_ERRORS_RX_REFUSED_RAW_MAX == 255u &&
                   PMSM_CAN_TLM_ERRORS_RX_OVERRUN_RAW_MAX == 255u &&
                   PMSM_CAN_TLM_ERRORS_TX_DROP_RAW_MAX == 255u,
               "Tlm_Errors counts are modulo 256");

/* The telemetry rule: into [lo, hi]; NaN and +-Inf are sent as hi. */
static float sat_f(float v, float lo, float hi)
{
    if (!isfinite(v)) {
        return hi;
    }
    return (v < lo) ? lo : ((v > hi) ? hi : v);
}

#define SAT(v, SIG) sat_f((v), SIG##_MIN, SIG##_MAX)

static uint32_t sat_u(uint32_t v, uint32_t hi)
{
    return (v > hi) ? hi : v;
}

/* count modulo 256 (the Tlm_Errors fields) */
static uint8_t mod256(uint32_t v)
{
    return (uint8_t)(v & 0xFFu);
}

static void pack_status(const mc_can_tlm_input_t *in, uint8_t counter,
                        uint8_t *d)
{
    const mc_telemetry_t *t = in->tlm;
    const struct pmsm_can_tlm_status_t m = {
        .counter = counter,
        .state = (uint8_t)sat_u((uint32_t)t->state,
                                PMSM_CAN_TLM_STATUS_STATE_RAW_MAX),
        .mode =
            (uint8_t)sat_u((uint32_t)t->mode, PMSM_CAN_TLM_STATUS_MODE_RAW_MAX),
        .outputs_on = t->outputs_enabled ? 1u : 0u,
        .v_saturated = t->v_saturated ? 1u : 0u,
        .current_limited = t->current_limited ? 1u : 0u,
        .enabled = in->enabled ? 1u : 0u,
        .faults_latched =
            (uint16_t)(t->faults_latched &
                       PMSM_CAN_TLM_STATUS_FAULTS_LATCHED_RAW_MAX),
        .first_fault = (uint16_t)(t->first_fault &
                                  PMSM_CAN_TLM_STATUS_FIRST_FAULT_RAW_MAX),
        .controller = (uint8_t)sat_u(in->controller,
                                     PMSM_CAN_TLM_STATUS_CONTROLLER_RAW_MAX),
    };
    (void)pmsm_can_tlm_status_pack(d, &m, PMSM_CAN_TLM_STATUS_LENGTH);
}

static void pack_currents(const mc_can_tlm_input_t *in, uint8_t counter,
                          uint8_t *d)
{
    const mc_telemetry_t *t = in->tlm;
    const struct pmsm_can_tlm_currents_t m = {
        .counter = counter,
        .i_d = pmsm_can_tlm_currents_i_d_encode(
            SAT(t->i_d_A, PMSM_CAN_TLM_CURRENTS_I_D)),
        .i_q = pmsm_can_tlm_currents_i_q_encode(
            SAT(t->i_q_A, PMSM_CAN_TLM_CURRENTS_I_Q)),
        .v_dc = pmsm_can_tlm_currents_v_dc_encode(
            SAT(t->v_dc_V, PMSM_CAN_TLM_CURRENTS_V_DC)),
    };
    (void)pmsm_can_tlm_currents_pack(d, &m, PMSM_CAN_TLM_CURRENTS_LENGTH);
}

static void pack_voltages(const mc_can_tlm_input_t *in, uint8_t counter,
                          uint8_t *d)
{
    const mc_telemetry_t *t = in->tlm;
    const struct pmsm_can_tlm_voltages_t m = {
        .counter = counter,
        .v_d = pmsm_can_tlm_voltages_v_d_encode(
            SAT(t->v_d_V, PMSM_CAN_TLM_VOLTAGES_V_D)),
        .v_q = pmsm_can_tlm_voltages_v_q_encode(
            SAT(t->v_q_V, PMSM_CAN_TLM_VOLTAGES_V_Q)),
        .i_q_ref = pmsm_can_tlm_voltages_i_q_ref_encode(
            SAT(t->i_q_ref_A, PMSM_CAN_TLM_VOLTAGES_I_Q_REF)),
    };
    (void)pmsm_can_tlm_voltages_pack(d, &m, PMSM_CAN_TLM_VOLTAGES_LENGTH);
}

static void pack_motion(const mc_can_tlm_input_t *in, uint8_t counter,
                        uint8_t *d)
{
    const mc_telemetry_t *t = in->tlm;
    const struct pmsm_can_tlm_motion_t m = {
        .counter = counter,
        .omega_m = pmsm_can_tlm_motion_omega_m_encode(
            SAT(t->omega_m_rad_s, PMSM_CAN_TLM_MOTION_OMEGA_M)),
        .theta_m = pmsm_can_tlm_motion_theta_m_encode(
            SAT(t->theta_m_rad, PMSM_CAN_TLM_MOTION_THETA_M)),
    };
    (void)pmsm_can_tlm_motion_pack(d, &m, PMSM_CAN_TLM_MOTION_LENGTH);
}

static void pack_estimates(const mc_can_tlm_input_t *in, uint8_t counter,
                           uint8_t *d)
{
    const mc_telemetry_t *t = in->tlm;
    float th = mc_wrap_pi_f32(t->theta_e_rad); /* NaN when not finite */
    if (th < 0.0f) {
        th += MC_TWO_PI_F; /* [0, 2 pi) */
    }
    const struct pmsm_can_tlm_estimates_t m = {
        .counter = counter,
        .theta_e = pmsm_can_tlm_estimates_theta_e_encode(
            SAT(th, PMSM_CAN_TLM_ESTIMATES_THETA_E)),
        .tau_l_hat = pmsm_can_tlm_estimates_tau_l_hat_encode(
            SAT(t->tau_L_hat_Nm, PMSM_CAN_TLM_ESTIMATES_TAU_L_HAT)),
        .flux_ratio_sq = pmsm_can_tlm_estimates_flux_ratio_sq_encode(
            SAT(t->flux_ratio_sq, PMSM_CAN_TLM_ESTIMATES_FLUX_RATIO_SQ)),
    };
    (void)pmsm_can_tlm_estimates_pack(d, &m, PMSM_CAN_TLM_ESTIMATES_LENGTH);
}

static void pack_references(const mc_can_tlm_input_t *in, uint8_t counter,
                            uint8_t *d)
{
    const mc_telemetry_t *t = in->tlm;
    const struct pmsm_can_tlm_references_t m = {
        .counter = counter,
        .omega_ref = pmsm_can_tlm_references_omega_ref_encode(
            SAT(t->omega_m_ref_rad_s, PMSM_CAN_TLM_REFERENCES_OMEGA_REF)),
        .theta_ref = pmsm_can_tlm_references_theta_ref_encode(
            SAT(t->theta_m_ref_rad, PMSM_CAN_TLM_REFERENCES_THETA_REF)),
    };
    (void)pmsm_can_tlm_references_pack(d, &m, PMSM_CAN_TLM_REFERENCES_LENGTH);
}

static void pack_isr_cost(const mc_can_tlm_input_t *in, uint8_t counter,
                          uint8_t *d)
{
    const mc_telemetry_t *t = in->tlm;
    const struct pmsm_can_tlm_isr_cost_t m = {
        .counter = counter,
        .cost_last = pmsm_can_tlm_isr_cost_cost_last_encode(
            SAT(t->isr_cost_s * US_PER_S, PMSM_CAN_TLM_ISR_COST_COST_LAST)),
        .cost_max = pmsm_can_tlm_isr_cost_cost_max_encode(
            SAT(t->isr_cost_max_s * US_PER_S, PMSM_CAN_TLM_ISR_COST_COST_MAX)),
        .cost_avg = pmsm_can_tlm_isr_cost_cost_avg_encode(
            SAT(in->cost_avg_s * US_PER_S, PMSM_CAN_TLM_ISR_COST_COST_AVG)),
    };
    (void)pmsm_can_tlm_isr_cost_pack(d, &m, PMSM_CAN_TLM_ISR_COST_LENGTH);
}

static void pack_errors(const mc_can_tlm_input_t *in, uint8_t counter,
                        uint8_t *d)
{
    const uint32_t *rej = in->counters->rejected;
    const struct pmsm_can_tlm_errors_t m = {
        .counter = counter,
        .rx_unknown = mod256(rej[MC_CAN_REJ_UNKNOWN_MESSAGE]),
        .rx_bad_dlc = mod256(rej[MC_CAN_REJ_WRONG_DLC]),
        .rx_bad_value = mod256(rej[MC_CAN_REJ_BAD_VALUE]),
        .rx_refused = mod256(rej[MC_CAN_REJ_REFUSED_STATE]),
        .rx_overrun = mod256(in->stats.rx_overruns),
        .tx_drop = mod256(in->counters->tx_drops),
    };
    (void)pmsm_can_tlm_errors_pack(d, &m, PMSM_CAN_TLM_ERRORS_LENGTH);
}

static void pack_counters(const mc_can_tlm_input_t *in, uint8_t counter,
                          uint8_t *d)
{
    const struct pmsm_can_tlm_counters_t m = {
        .counter = counter,
        .isr_overruns = sat_u(in->tlm->isr_overruns,
                              PMSM_CAN_TLM_COUNTERS_ISR_OVERRUNS_RAW_MAX),
        .bus_errors = sat_u(in->stats.bus_errors,
                            PMSM_CAN_TLM_COUNTERS_BUS_ERRORS_RAW_MAX),
    };
    (void)pmsm_can_tlm_counters_pack(d, &m, PMSM_CAN_TLM_COUNTERS_LENGTH);
}

bool mc_can_tlm_frame(uint32_t node_id, uint32_t msg,
                      const mc_can_tlm_input_t *in, uint8_t counter,
                      hal_can_frame_t *f)
{
    *f = (hal_can_frame_t){
        .id = (node_id << MC_CAN_MSG_BITS) | (msg & MC_CAN_MSG_MASK),
        .dlc = HAL_CAN_MAX_DLC,
    };
    switch (msg) {
    case PMSM_CAN_TLM_STATUS_FRAME_ID: pack_status(in, counter, f->data); break;
    case PMSM_CAN_TLM_CURRENTS_FRAME_ID:
        pack_currents(in, counter, f->data);
        break;
    case PMSM_CAN_TLM_VOLTAGES_FRAME_ID:
        pack_voltages(in, counter, f->data);
        break;
    case PMSM_CAN_TLM_MOTION_FRAME_ID: pack_motion(in, counter, f->data); break;
    case PMSM_CAN_TLM_ESTIMATES_FRAME_ID:
        pack_estimates(in, counter, f->data);
        break;
    case PMSM_CAN_TLM_REFERENCES_FRAME_ID:
        pack_references(in, counter, f->data);
        break;
    case PMSM_CAN_TLM_ISR_COST_FRAME_ID:
        pack_isr_cost(in, counter, f->data);
        break;
    case PMSM_CAN_TLM_ERRORS_FRAME_ID: pack_errors(in, counter, f->data); break;
    case PMSM_CAN_TLM_COUNTERS_FRAME_ID:
        pack_counters(in, counter, f->data);
        break;
    default: return false;
    }
    (void)mc_can_e2e_protect(f->id, f->data, f->dlc);
    return true;
}

/* Every telemetry message is 8 bytes (the DLC mc_can_tlm_frame uses). */
_Static_assert(PMSM_CAN_TLM_STATUS_LENGTH == 8u &&
                   PMSM_CAN_TLM_CURRENTS_LENGTH == 8u &&
                   PMSM_CAN_TLM_VOLTAGES_LENGTH == 8u &&
                   PMSM_CAN_TLM_MOTION_LENGTH == 8u &&
                   PMSM_CAN_TLM_ESTIMATES_LENGTH == 8u &&
                   PMSM_CAN_TLM_REFERENCES_LENGTH == 8u &&
                   PMSM_CAN_TLM_ISR_COST_LENGTH == 8u &&
                   PMSM_CAN_TLM_ERRORS_LENGTH == 8u &&
                   PMSM_CAN_TLM_COUNTERS_LENGTH == 8u,
               "telemetry frames are 8 bytes");

/* The ISR cost mean: one sample per distinct snapshot, while Tlm_IsrCost
 * is on. */
static void accumulate_cost(mc_can_node_t *n, const mc_telemetry_t *t)
{
    const bool fresh = !n->have_snapshot || t->isr_count != n->last_isr_count;
    n->have_snapshot = true;
    n->last_isr_count = t->isr_count;
    const uint32_t k = PMSM_CAN_TLM_ISR_COST_FRAME_ID - MC_CAN_TLM_FIRST;
    if (fresh && n->cfg.decimation[k] != 0u && isfinite(t->isr_cost_s)) {
        n->cost_sum_s += t->isr_cost_s;
        n->cost_n++;
    }
}

void mc_can_node_telemetry(mc_can_node_t *n, const mc_telemetry_t *t)
{
    accumulate_cost(n, t);
    mc_can_tlm_input_t in = {
        .tlm = t,
        .enabled = n->cmd.enable,
        .controller = (uint32_t)n->drive_cfg.controller,
        .cost_avg_s =
            (n->cost_n > 0u) ? n->cost_sum_s / (float)n->cost_n : t->isr_cost_s,
        .counters = &n->counters,
    };
    hal_can_stats(&in.stats);
    for (uint32_t k = 0u; k < MC_CAN_TLM_COUNT; ++k) {
        const uint32_t dec = n->cfg.decimation[k];
        if (dec == 0u ||
            (n->tlm_sent[k] && t->isr_count - n->tlm_last_isr[k] < dec)) {
            continue;
        }
        const uint32_t msg = MC_CAN_TLM_FIRST + k;
        hal_can_frame_t f;
        (void)mc_can_tlm_frame(n->cfg.node_id, msg, &in, n->tlm_counter[k], &f);
        n->tlm_counter[k] = mc_can_e2e_counter_next(n->tlm_counter[k]);
        n->tlm_sent[k] = true;
        n->tlm_last_isr[k] = t->isr_count;
        mc_can_node_send(n, msg, f.data, f.dlc);
        if (msg == PMSM_CAN_TLM_ISR_COST_FRAME_ID) {
            n->cost_sum_s = 0.0f;
            n->cost_n = 0u;
        }
    }
}
