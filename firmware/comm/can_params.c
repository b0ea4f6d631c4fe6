/* The configuration's parameters by CAN id (mc/can_params.h). */
#include "mc/can_params.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#define CRC16_INIT 0xFFFFu

/* CRC-16/CCITT-FALSE, four bits at a time: entry k is the CRC register
 * (polynomial 0x1021) of the nibble k shifted through it, k * 0x1021
 * without carries for k < 16. */
static const uint16_t crc16_nibble[16] = {
    0x0000u, 0x1021u, 0x2042u, 0x3063u, 0x4084u, 0x50A5u, 0x60C6u, 0x70E7u,
    0x8108u, 0x9129u, 0xA14Au, 0xB16Bu, 0xC18Cu, 0xD1ADu, 0xE1CEu, 0xF1EFu,
};

static uint16_t crc16_byte(uint16_t crc, uint8_t b)
{
    crc = (uint16_t)((uint16_t)(crc << 4) ^
                     crc16_nibble[((uint32_t)crc >> 12) ^ ((uint32_t)b >> 4)]);
    crc = (uint16_t)((uint16_t)(crc << 4) ^
                     crc16_nibble[((uint32_t)crc >> 12) ^ (b & 0x0Fu)]);
    return crc;
}

static uint16_t crc16_string(uint16_t crc, const char *s)
{
    for (uint32_t i = 0u; i < MC_CAN_PARAM_NAME_MAX && s[i] != '\0'; ++i) {
        crc = crc16_byte(crc, (uint8_t)s[i]);
    }
    return crc;
}

uint16_t mc_can_crc16_ccitt_false(const uint8_t *data, uint32_t n)
{
    uint16_t crc = CRC16_INIT;
    for (uint32_t i = 0u; i < n; ++i) {
        crc = crc16_byte(crc, data[i]);
    }
    return crc;
}

uint16_t mc_can_param_id(const char *block, const char *field)
{
    uint16_t crc = CRC16_INIT;
    if (block != NULL && block[0] != '\0') {
        crc = crc16_string(crc, block);
        crc = crc16_byte(crc, (uint8_t)'.');
    }
    return crc16_string(crc, field);
}

bool mc_can_param_find(uint16_t id, mc_can_param_ref_t *ref)
{
    for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; ++b) {
        for (const mc_param_t *p = b->params; p->name != NULL; ++p) {
            if (mc_can_param_id(b->name, p->name) == id) {
                *ref = (mc_can_param_ref_t){ .block = b, .param = p, .id = id };
                return true;
            }
        }
    }
    return false;
}

mc_can_param_type_t mc_can_param_wire_type(mc_param_type_t type)
{
    switch (type) {
    case MC_PARAM_F32: return MC_CAN_PARAM_TYPE_F32;
    case MC_PARAM_BOOL: return MC_CAN_PARAM_TYPE_BOOL;
    case MC_PARAM_U32:
    case MC_PARAM_CONTROLLER:
    case MC_PARAM_ESTIMATOR: return MC_CAN_PARAM_TYPE_U32;
    }
    return MC_CAN_PARAM_TYPE_U32; /* not reached: every type is listed */
}

/* Byte offset of the field in mc_config_t; false if it does not lie
 * inside (a ref not made by mc_can_param_find). */
static bool field_offset(const mc_can_param_ref_t *ref, size_t *offset)
{
    if (ref == NULL || ref->block == NULL || ref->param == NULL) {
        return false;
    }
    const size_t size = mc_param_size(ref->param->type);
    const size_t b = ref->block->offset, p = ref->param->offset;
    if (size == 0u || b > sizeof(mc_config_t) || p > sizeof(mc_config_t) - b ||
        size > sizeof(mc_config_t) - b - p) {
        return false;
    }
    *offset = b + p;
    return true;
}

mc_status_t mc_can_param_get(const mc_config_t *cfg,
                             const mc_can_param_ref_t *ref,
                             mc_can_param_value_t *out)
{
    size_t off;
    if (!field_offset(ref, &off)) {
        return MC_ERR_PARAM;
    }
    const uint8_t *src = (const uint8_t *)cfg + off;
    mc_can_param_value_t v = { .type =
                                   mc_can_param_wire_type(ref->param->type) };
    switch (ref->param->type) {
    case MC_PARAM_F32: memcpy(&v.f32, src, sizeof(v.f32)); break;
    case MC_PARAM_U32: memcpy(&v.u32, src, sizeof(v.u32)); break;
    case MC_PARAM_BOOL: memcpy(&v.b, src, sizeof(v.b)); break;
    case MC_PARAM_CONTROLLER: {
        mc_controller_t c;
        memcpy(&c, src, sizeof(c));
        v.u32 = (uint32_t)c;
        break;
    }
    case MC_PARAM_ESTIMATOR: {
        mc_estimator_t e;
        memcpy(&e, src, sizeof(e));
        v.u32 = (uint32_t)e;
        break;
    }
    }
    *out = v;
    return MC_OK;
}

mc_status_t mc_can_param_set(mc_config_t *cfg, const mc_can_param_ref_t *ref,
                             const mc_can_param_value_t *value)
{
    size_t off;
    if (!field_offset(ref, &off) ||
        value->type != mc_can_param_wire_type(ref->param->type)) {
        return MC_ERR_PARAM;
    }
    uint8_t *dst = (uint8_t *)cfg + off;
    switch (ref->param->type) {
    case MC_PARAM_F32:
        if (!isfinite(value->f32)) {
            return MC_ERR_NONFINITE;
        }
        memcpy(dst, &value->f32, sizeof(value->f32));
        break;
    case MC_PARAM_U32: memcpy(dst, &value->u32, sizeof(value->u32)); break;
    case MC_PARAM_BOOL: memcpy(dst, &value->b, sizeof(value->b)); break;
    case MC_PARAM_CONTROLLER: {
        if (value->u32 >= (uint32_t)MC_CONTROLLER_COUNT) {
            return MC_ERR_RANGE;
        }
        const mc_controller_t c = (mc_controller_t)value->u32;
        memcpy(dst, &c, sizeof(c));
        break;
    }
    case MC_PARAM_ESTIMATOR: {
        if (value->u32 >= (uint32_t)MC_ESTIMATOR_COUNT) {
            return MC_ERR_RANGE;
        }
        const mc_estimator_t e = (mc_estimator_t)value->u32;
        memcpy(dst, &e, sizeof(e));
        break;
    }
    }
    return MC_OK;
}
