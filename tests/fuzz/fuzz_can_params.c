/*
 * libFuzzer harness: the parameter codec (mc/can_params.h) and the
 * configuration validation it feeds.
 *
 * Input layout (tests/fuzz/README.md): 8-byte operations
 *   0      op: bits 0..1 the operation, bits 2..3 a wire type (0..3)
 *   1..2   selector, little-endian (a raw id, or a parameter index)
 *   3..6   value, little-endian (float bits, u32, or bool in byte 3)
 *   7      extra (a name length for op 2)
 * operations: 0 look up the raw id; 1 set parameter (selector % count) to
 * the typed value on the working configuration, then get it back; 2 the id
 * of a name made of the following input bytes against the CRC of the
 * joined name; 3 validate the working configuration (and restore the
 * default one when it is invalid).
 *
 * Invariants (abort on violation): a found id is the CRC of its
 * "block.field" (and found again at the same place); set returns OK with
 * the value read back unchanged and nothing but the field's bytes
 * changed, or MC_ERR_PARAM for another wire type, MC_ERR_NONFINITE for a
 * NaN/Inf float, MC_ERR_RANGE for a controller / estimator id outside its
 * list, each leaving the configuration untouched; mc_config_validate
 * returns one of the three codes mc/config.h names (MC_OK,
 * MC_ERR_NONFINITE, MC_ERR_PARAM; README.md, findings). Plus ASan /
 * UBSan.
 */
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_check.h"
#include "mc/can_params.h"

#define OP_LEN  8u
#define MAX_OPS 256u

typedef struct {
    const mc_param_block_t *block;
    const mc_param_t *param;
} entry_t;

static entry_t table[512];
static uint32_t n_entries;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void build_table(void)
{
    if (n_entries != 0u) {
        return;
    }
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        for (const mc_param_t *p = b->params; p->name != NULL; ++p) {
            CHECK(n_entries < sizeof table / sizeof table[0]);
            table[n_entries++] = (entry_t){ b, p };
        }
    }
}

static void op_lookup(uint16_t id)
{
    mc_can_param_ref_t ref;
    if (mc_can_param_find(id, &ref)) {
        CHECK(ref.id == id);
        CHECK(mc_can_param_id(ref.block->name, ref.param->name) == id);
        mc_can_param_ref_t again;
        CHECK(mc_can_param_find(mc_can_param_id(ref.block->name, ref.param->name), &again));
        CHECK(again.block == ref.block && again.param == ref.param);
    }
}

static void op_set(mc_config_t *cfg, uint32_t sel, uint32_t type, uint32_t raw)
{
    const entry_t *e = &table[sel % n_entries];
    mc_can_param_ref_t ref;
    CHECK(mc_can_param_find(mc_can_param_id(e->block->name, e->param->name), &ref));
    mc_can_param_value_t v = { .type = (mc_can_param_type_t)(type % 3u) };
    memcpy(&v.f32, &raw, sizeof v.f32);
    v.u32 = raw;
    v.b = (raw & 1u) != 0u;
    const mc_config_t before = *cfg;
    const mc_status_t st = mc_can_param_set(cfg, &ref, &v);
    const mc_can_param_type_t wire = mc_can_param_wire_type(e->param->type);
    const uint32_t count = (e->param->type == MC_PARAM_CONTROLLER)  ? (uint32_t)MC_CONTROLLER_COUNT
                           : (e->param->type == MC_PARAM_ESTIMATOR) ? (uint32_t)MC_ESTIMATOR_COUNT
                                                                    : 0xFFFFFFFFu;
    mc_status_t expect = MC_OK;
    if (v.type != wire) {
        expect = MC_ERR_PARAM;
    } else if (wire == MC_CAN_PARAM_TYPE_F32 && !isfinite(v.f32)) {
        expect = MC_ERR_NONFINITE;
    } else if (count != 0xFFFFFFFFu && v.u32 >= count) {
        expect = MC_ERR_RANGE;
    }
    CHECK(st == expect);
    if (st != MC_OK) {
        CHECK(memcmp(cfg, &before, sizeof before) == 0);
        return;
    }
    mc_can_param_value_t got;
    CHECK(mc_can_param_get(cfg, &ref, &got) == MC_OK);
    CHECK(got.type == v.type);
    switch (wire) {
    case MC_CAN_PARAM_TYPE_F32: CHECK(memcmp(&got.f32, &v.f32, sizeof v.f32) == 0); break;
    case MC_CAN_PARAM_TYPE_U32: CHECK(got.u32 == v.u32); break;
    case MC_CAN_PARAM_TYPE_BOOL: CHECK(got.b == v.b); break;
    case MC_CAN_PARAM_TYPE_COUNT: CHECK(false); break;
    }
    const size_t off = e->block->offset + e->param->offset;
    const size_t sz = mc_param_size(e->param->type);
    const uint8_t *x = (const uint8_t *)&before, *y = (const uint8_t *)cfg;
    for (size_t i = 0; i < sizeof before; ++i) {
        CHECK((i >= off && i < off + sz) || x[i] == y[i]);
    }
}

/* The id of a name from the input: block and field (each shorter than the
 * hashing limit, no NUL) against the CRC of "block.field". */
static size_t op_name(const uint8_t *p, size_t left, uint32_t extra)
{
    char block[MC_CAN_PARAM_NAME_MAX], field[MC_CAN_PARAM_NAME_MAX];
    uint8_t joined[2u * MC_CAN_PARAM_NAME_MAX + 1u];
    const size_t nb = (extra & 0x0Fu) * 3u % MC_CAN_PARAM_NAME_MAX;
    const size_t nf = ((extra >> 4) * 3u + 1u) % MC_CAN_PARAM_NAME_MAX;
    if (left < nb + nf) {
        return left;
    }
    size_t j = 0;
    for (size_t i = 0; i < nb; ++i) {
        block[i] = (char)(p[i] | 1u); /* no NUL */
        joined[j++] = (uint8_t)block[i];
    }
    block[nb] = '\0';
    if (nb > 0u) {
        joined[j++] = '.';
    }
    for (size_t i = 0; i < nf; ++i) {
        field[i] = (char)(p[nb + i] | 1u);
        joined[j++] = (uint8_t)field[i];
    }
    field[nf] = '\0';
    CHECK(mc_can_param_id(block, field) == mc_can_crc16_ccitt_false(joined, (uint32_t)j));
    return nb + nf;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    build_table();
    mc_config_t cfg;
    mc_config_init_default(&cfg);
    size_t pos = 0;
    for (uint32_t k = 0; k < MAX_OPS && pos + OP_LEN <= size; ++k) {
        const uint8_t *p = data + pos;
        pos += OP_LEN;
        const uint32_t sel = (uint32_t)p[1] | ((uint32_t)p[2] << 8);
        const uint32_t raw = (uint32_t)p[3] | ((uint32_t)p[4] << 8) | ((uint32_t)p[5] << 16) |
                             ((uint32_t)p[6] << 24);
        switch (p[0] & 3u) {
        case 0: op_lookup((uint16_t)sel); break;
        case 1: op_set(&cfg, sel, (p[0] >> 2) & 3u, raw); break;
        case 2: pos += op_name(data + pos, size - pos, p[7]); break;
        default: {
            const mc_status_t st = mc_config_validate(&cfg);
            CHECK(st == MC_OK || st == MC_ERR_NONFINITE || st == MC_ERR_PARAM);
            if (st != MC_OK) {
                mc_config_init_default(&cfg);
            }
            break;
        }
        }
    }
    const mc_status_t st = mc_config_validate(&cfg);
    CHECK(st == MC_OK || st == MC_ERR_NONFINITE || st == MC_ERR_PARAM);
    return 0;
}
