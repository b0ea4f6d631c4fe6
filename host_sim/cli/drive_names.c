/* Names of the firmware's states and fault bits. */
#include "drive_names.h"

#include <stdio.h>

const char *drive_state_name(mc_state_t state)
{
    switch (state) {
    case MC_STATE_IDLE: return "idle";
    case MC_STATE_CALIBRATING: return "calibrating";
    case MC_STATE_RUN: return "run";
    case MC_STATE_FAULT: return "fault";
    case MC_STATE_ALIGN: return "align";
    }
    return "unknown";
}

static const struct {
    uint32_t bit;
    const char *name;
} fault_names[] = {
    { MC_FAULT_OVERCURRENT, "overcurrent" },
    { MC_FAULT_DC_OVERVOLTAGE, "dc_overvoltage" },
    { MC_FAULT_DC_UNDERVOLTAGE, "dc_undervoltage" },
    { MC_FAULT_NONFINITE, "nonfinite" },
    { MC_FAULT_ISR_OVERRUN, "isr_overrun" },
    { MC_FAULT_EXTERNAL, "external" },
    { MC_FAULT_CALIBRATION, "calibration" },
    { MC_FAULT_ENCODER, "encoder" },
    { MC_FAULT_ESTIMATE, "estimate" },
    { MC_FAULT_OVERSPEED, "overspeed" },
    { MC_FAULT_STALL, "stall" },
    { MC_FAULT_I2T, "i2t" },
    { MC_FAULT_CURRENT_SENSOR, "current_sensor" },
    { MC_FAULT_LOSS_OF_LOCK, "loss_of_lock" },
    { MC_FAULT_CURRENT_LIMIT, "current_limit" },
    { MC_FAULT_COMM_TIMEOUT, "comm_timeout" },
};

#define N_FAULT_NAMES (sizeof(fault_names) / sizeof(fault_names[0]))

size_t drive_fault_count(void)
{
    return N_FAULT_NAMES;
}

const char *drive_fault_name(size_t i, uint32_t *bit)
{
    *bit = fault_names[i].bit;
    return fault_names[i].name;
}

void drive_faults_text(uint32_t bits, char *buf, size_t size)
{
    size_t len = (size_t)snprintf(buf, size, "%s", bits == 0 ? "none" : "");
    for (size_t i = 0; i < N_FAULT_NAMES && len < size; i++) {
        if (bits & fault_names[i].bit) {
            len += (size_t)snprintf(buf + len, size - len, "%s%s", len > 0 ? " " : "",
                                    fault_names[i].name);
            bits &= ~fault_names[i].bit;
        }
    }
    if (bits != 0 && len < size) {
        snprintf(buf + len, size - len, "%s0x%x", len > 0 ? " " : "", (unsigned)bits);
    }
}
