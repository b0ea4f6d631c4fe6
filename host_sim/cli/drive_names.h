/* Names of the firmware's states and fault bits, for reports. */
#ifndef PMSM_SIM_DRIVE_NAMES_H
#define PMSM_SIM_DRIVE_NAMES_H

#include <stddef.h>
#include <stdint.h>

#include "mc/app.h"

const char *drive_state_name(mc_state_t state);

/* Name of fault bit i (i < drive_fault_count()), and its mask. */
size_t drive_fault_count(void);
const char *drive_fault_name(size_t i, uint32_t *bit);

/* "none", or the latched faults separated by spaces; bits without a name
 * (a fault added to the firmware later) are shown as hex. */
void drive_faults_text(uint32_t bits, char *buf, size_t size);

#endif /* PMSM_SIM_DRIVE_NAMES_H */
