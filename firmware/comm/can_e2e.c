/* E2E protection of the telemetry frames (mc/can_e2e.h). */
#include "mc/can_e2e.h"

#define CRC8_J1850_POLY 0x1Du
#define CRC8_J1850_INIT 0xFFu
#define CRC8_J1850_XOR  0xFFu
#define CAN_STD_ID_MASK 0x7FFu

/* MSB-first CRC-8 with polynomial 0x1D, without the final XOR. */
static uint8_t crc8_update(uint8_t crc, const uint8_t *data, uint32_t n)
{
    for (uint32_t i = 0u; i < n; ++i) {
        crc ^= data[i];
        for (uint32_t b = 0u; b < 8u; ++b) {
            crc = (crc & 0x80u)
                      ? (uint8_t)((uint8_t)(crc << 1) ^ CRC8_J1850_POLY)
                      : (uint8_t)(crc << 1);
        }
    }
    return crc;
}

uint8_t mc_can_crc8_j1850(const uint8_t *data, uint32_t n)
{
    return (uint8_t)(crc8_update(CRC8_J1850_INIT, data, n) ^ CRC8_J1850_XOR);
}

uint8_t mc_can_e2e_crc(uint32_t id, const uint8_t *data, uint32_t len)
{
    if (len < 1u || len > MC_CAN_E2E_MAX_LEN) {
        return 0u;
    }
    const uint32_t sid = id & CAN_STD_ID_MASK;
    const uint8_t data_id[2] = { (uint8_t)(sid & 0xFFu), (uint8_t)(sid >> 8) };
    uint8_t crc = crc8_update(CRC8_J1850_INIT, data_id, 2u);
    crc = crc8_update(crc, &data[1], len - 1u);
    return (uint8_t)(crc ^ CRC8_J1850_XOR);
}

bool mc_can_e2e_protect(uint32_t id, uint8_t *data, uint32_t len)
{
    if (len < 1u || len > MC_CAN_E2E_MAX_LEN) {
        return false;
    }
    data[0] = mc_can_e2e_crc(id, data, len);
    return true;
}

bool mc_can_e2e_check(uint32_t id, const uint8_t *data, uint32_t len)
{
    if (len < 1u || len > MC_CAN_E2E_MAX_LEN) {
        return false;
    }
    return data[0] == mc_can_e2e_crc(id, data, len);
}

uint8_t mc_can_e2e_counter_next(uint8_t c)
{
    return (c >= MC_CAN_E2E_COUNTER_MAX) ? 0u : (uint8_t)(c + 1u);
}
