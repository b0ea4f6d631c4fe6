/*
 * libFuzzer harness: the CAN node (mc/can_node.h) polled on a real drive
 * over the simulator-mailbox HAL, fed with frames decoded from the input.
 *
 * Input layout (tests/fuzz/README.md):
 *   byte 0   node_id (bits 0..5), an apply callback is given (bit 6), the
 *            callback refuses every configuration with MC_ERR_PARAM (bit 7)
 *   byte 1   timeout = (1 + bits 0..3) ms; telemetry decimations from bits
 *            4..7 (0: all off, v: decimation[k] = (v + k) % 5)
 *   then 14-byte chunks, one frame each:
 *     0..3   identifier, little-endian, as is (may break hal/can.h limits)
 *     4      bit 0 extended, bit 1 RTR, bit 2 poll after this frame, bit 3
 *            run one fast ISR before that poll, bits 4..7: n, the simulated
 *            time advances by n * n * 100 us before it
 *     5      DLC, as is (0..255: a DLC over 8 breaks hal/can.h)
 *     6..13  data
 *   A final ISR and poll end every input.
 *
 * Invariants (abort on violation): rx_frames == rx_accepted + the sum of
 * rejected[] (rejected[0] == 0); the configuration in force changes only
 * through an apply call that returned MC_OK, always to the configuration
 * that call received, which mc_config_validate accepts, and only while the
 * drive is stopped (IDLE/FAULT, command disabled); comm_lost only while
 * enabled; the command's mode and references stay valid (finite, within
 * the DBC ranges); every frame the node sends is a standard frame of its
 * node, a message it may send with its DLC, E2E-correct telemetry whose
 * counter runs 0..14 in sequence, replies with in-range fields; every
 * frame the node sent reached the queue (tx_frames == frames collected);
 * rejections <= replies <= frames taken, per poll. Plus ASan / UBSan.
 */
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_check.h"
#include "hal_host.h"
#include "mc/app.h"
#include "mc/can_e2e.h"
#include "mc/can_node.h"

#define CHUNK      14u
#define MAX_FRAMES 400u

static hal_sim_mailbox_t mb;
static mc_app_t app;
static mc_can_node_t node;
static mc_config_t in_force; /* the expectation of node.drive_cfg */
static bool apply_fails;
static uint32_t collected;  /* frames taken from the transmit queue */
static int last_counter[9]; /* per telemetry message, -1: none yet */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static mc_status_t apply_cb(void *ctx, const mc_config_t *cfg)
{
    (void)ctx;
    CHECK(mc_config_validate(cfg) == MC_OK);
    mc_telemetry_t t;
    CHECK(mc_app_get_telemetry(&app, &t) == MC_OK);
    CHECK(t.state == MC_STATE_IDLE || t.state == MC_STATE_FAULT);
    CHECK(!node.cmd.enable);
    if (apply_fails) {
        return MC_ERR_PARAM;
    }
    const mc_status_t st = mc_app_init(&app, cfg);
    if (st == MC_OK) {
        in_force = *cfg;
    } else {
        CHECK(mc_app_init(&app, &in_force) == MC_OK); /* the old one back */
    }
    return st;
}

/* Take what the node sent; the number of replies (not telemetry). */
static uint32_t check_sent(void)
{
    uint32_t replies = 0u;
    hal_can_frame_t f;
    while (hal_sim_can_collect(&mb, &f)) {
        collected++;
        const uint32_t msg = f.id & 31u;
        CHECK(!f.extended && !f.rtr && f.id <= 0x7FFu);
        CHECK((f.id >> 5) == node.cfg.node_id);
        if (msg >= MC_CAN_TLM_FIRST && msg < MC_CAN_TLM_FIRST + MC_CAN_TLM_COUNT) {
            CHECK(f.dlc == 8u);
            CHECK(mc_can_e2e_check(f.id, f.data, f.dlc));
            const int c = f.data[1] & 0x0F;
            const uint32_t k = msg - MC_CAN_TLM_FIRST;
            CHECK(c <= 14);
            CHECK(last_counter[k] < 0 || c == (last_counter[k] + 1) % 15);
            last_counter[k] = c;
            continue;
        }
        replies++;
        if (msg == 25u) { /* Rsp_Param: type 0..2, status 0..4 */
            CHECK(f.dlc == 8u && f.data[2] <= 2u && f.data[3] <= 4u);
        } else { /* Rsp_Error: message 0..31, cause 1..6, DLC 0..8 */
            CHECK(msg == 26u);
            CHECK(f.dlc == 3u && f.data[0] <= 31u && f.data[1] >= 1u && f.data[1] <= 6u &&
                  f.data[2] <= 8u);
        }
    }
    return replies;
}

static uint32_t rejected_sum(const mc_can_counters_t *c)
{
    uint32_t s = 0;
    for (unsigned k = 0; k < MC_CAN_REJ_COUNT; ++k) {
        s += c->rejected[k];
    }
    return s;
}

static bool in_range(float v, float lim)
{
    return isfinite(v) && v >= -lim && v <= lim;
}

static void poll_and_check(void)
{
    const mc_can_counters_t before = node.counters;
    mc_can_node_poll(&node, &app);
    const uint32_t replies = check_sent();
    const mc_can_counters_t *c = mc_can_node_counters(&node);
    CHECK(c->rejected[0] == 0u);
    CHECK(c->rx_frames == c->rx_accepted + rejected_sum(c));
    CHECK(c->tx_frames == collected && c->tx_drops == 0u);
    CHECK(memcmp(&node.drive_cfg, &in_force, sizeof in_force) == 0);
    CHECK(!node.cmd.comm_lost || node.cmd.enable);
    CHECK(node.cmd.mode == MC_MODE_CURRENT || node.cmd.mode == MC_MODE_SPEED ||
          node.cmd.mode == MC_MODE_POSITION);
    CHECK(in_range(node.cmd.i_d_ref_A, 1000.0f) && in_range(node.cmd.i_q_ref_A, 1000.0f));
    CHECK(in_range(node.cmd.omega_m_ref_rad_s, 10000.0f));
    CHECK(in_range(node.cmd.theta_m_ref_rad, 1000000.0f));
    /* one reply per rejected frame, at most one per frame taken */
    const uint32_t taken = c->rx_frames - before.rx_frames;
    CHECK(taken <= MC_CAN_NODE_RX_PER_POLL);
    CHECK(rejected_sum(c) - rejected_sum(&before) <= replies);
    CHECK(replies <= taken);
    CHECK(c->timeouts - before.timeouts <= 1u);
    mc_telemetry_t t;
    CHECK(mc_app_get_telemetry(&app, &t) == MC_OK);
    CHECK((uint32_t)t.state <= (uint32_t)MC_STATE_ALIGN);
}

static void isr(void)
{
    mc_app_fast_isr(&app);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2u) {
        return 0;
    }
    hal_sim_mailbox_reset(&mb);
    mb.pwm_f_Hz = 20000.0f;
    mb.pwm_delay_periods = 1.0f;
    mb.encoder_cpr = 10000u;
    mb.adc.v_dc_V = 48.0f;
    mb.sim_time_ns = 1000000u;
    hal_sim_bind(&mb);
    CHECK(hal_can_init(1000000u) == HAL_OK);
    mc_config_init_default(&in_force);
    in_force.timing.calib_time_s = 8.0f / 20000.0f;
    in_force.timing.isr_overrun_limit = MC_TIMING_OVERRUN_LIMIT_MAX; /* host time */
    CHECK(mc_app_init(&app, &in_force) == MC_OK);

    mc_can_node_config_t nc;
    mc_can_node_config_default(&nc);
    nc.node_id = data[0] & 63u;
    nc.timeout_s = 0.001f * (float)(1u + (data[1] & 15u));
    const uint32_t v = data[1] >> 4;
    for (uint32_t k = 0; k < MC_CAN_TLM_COUNT; ++k) {
        nc.decimation[k] = (uint16_t)((v == 0u) ? 0u : (v + k) % 5u);
    }
    const bool with_apply = (data[0] & 0x40u) != 0u;
    apply_fails = (data[0] & 0x80u) != 0u;
    CHECK(mc_can_node_init(&node, &nc, &in_force, with_apply ? apply_cb : NULL, NULL) == MC_OK);
    collected = 0u;
    for (unsigned k = 0; k < 9u; ++k) {
        last_counter[k] = -1;
    }

    const uint8_t *p = data + 2;
    size_t n = (size - 2u) / CHUNK;
    if (n > MAX_FRAMES) {
        n = MAX_FRAMES;
    }
    for (size_t i = 0; i < n; ++i, p += CHUNK) {
        hal_can_frame_t f = {
            .id = (uint32_t)p[0] | ((uint32_t)p[1] << 8) | ((uint32_t)p[2] << 16) |
                  ((uint32_t)p[3] << 24),
            .extended = (p[4] & 1u) != 0u,
            .rtr = (p[4] & 2u) != 0u,
            .dlc = p[5],
        };
        memcpy(f.data, p + 6, 8);
        (void)hal_sim_can_deliver(&mb, &f); /* a full queue counts an overrun */
        if ((p[4] & 4u) != 0u) {
            const uint32_t adv = (uint32_t)(p[4] >> 4);
            mb.sim_time_ns += (uint64_t)adv * adv * 100000u;
            if ((p[4] & 8u) != 0u) {
                isr();
            }
            poll_and_check();
        }
    }
    mb.sim_time_ns += 50000u;
    isr();
    while (mb.can_rx.count > 0u) {
        poll_and_check();
    }
    poll_and_check();
    hal_sim_bind(NULL);
    return 0;
}
