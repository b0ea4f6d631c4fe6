/*
 * The image's ISR-path HAL functions as static inline accessors, the way a
 * board's binding reads and writes its peripheral registers: the build
 * defines HAL_INLINE_ACCESSORS="hal_qemu_inline.h" for everything linked
 * into the images (hal/qemu_m4/CMakeLists.txt), so the HAL headers include
 * this file instead of declaring those functions. The "registers" are the
 * engine's mailbox (hal/sim_mailbox), reached through one pointer that
 * hal_sim_bind sets before the engine first calls the firmware; the cycle
 * counter is SysTick (qemu_m4.h), extended to 32 bits.
 */
#ifndef HAL_QEMU_INLINE_H
#define HAL_QEMU_INLINE_H

#include <stdint.h>

#include "hal/adc.h"
#include "hal/encoder.h"
#include "hal/gpio.h"
#include "hal/pwm.h"
#include "hal/time.h"
#include "hal_sim_mailbox.h"
#include "qemu_m4.h"

/* hal_qemu.c: the bound mailbox, and the cycle counter's state (the raw
 * SysTick value at the previous read, the extended count). */
extern hal_sim_mailbox_t *hal_qemu_mailbox;
extern uint32_t hal_qemu_cc_last_raw;
extern uint32_t hal_qemu_cc_ticks;

#define HAL_SIM_ACCESSOR static inline __attribute__((always_inline))
#define HAL_SIM_MAILBOX  hal_qemu_mailbox
#include "hal_sim_accessors.h"

static inline __attribute__((always_inline)) uint32_t hal_cycle_counter(void)
{
    const uint32_t raw = qemu_m4_systick();
    hal_qemu_cc_ticks += qemu_m4_ticks_between(hal_qemu_cc_last_raw, raw);
    hal_qemu_cc_last_raw = raw;
    return hal_qemu_cc_ticks;
}

#endif /* HAL_QEMU_INLINE_H */
