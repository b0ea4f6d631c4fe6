/*
 * The image's ISR-path HAL functions as static inline accessors, the way a
 * board's binding reads and writes its peripheral registers: the build
 * defines HAL_INLINE_ACCESSORS="hal_qemu_inline.h" for everything linked
 * into the images (hal/qemu_m4/CMakeLists.txt), so the HAL headers include
 * this file instead of declaring those functions. The "registers" are the
 * engine's mailbox (hal/sim_mailbox) at its fixed address; the cycle
 * counter is SysTick (qemu_m4.h), 24 bits wide.
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

/* hal_qemu.c: the mailbox, at a link-time address (its engine uses it:
 * hal_sim_fixed_mailbox), reached without a pointer, as registers. */
extern hal_sim_mailbox_t hal_qemu_regs;

#define HAL_SIM_ACCESSOR static inline __attribute__((always_inline))
#define HAL_SIM_MAILBOX  (&hal_qemu_regs)
#include "hal_sim_accessors.h"

/* SysTick counts down from its 24-bit reload: its complement counts up,
 * significant in the low 24 bits (hal/time.h). */
static inline __attribute__((always_inline)) uint32_t hal_cycle_counter(void)
{
    return ~qemu_m4_systick();
}

static inline __attribute__((always_inline)) uint32_t
hal_cycles_since(uint32_t start)
{
    return (hal_cycle_counter() - start) & 0x00FFFFFFu;
}

#endif /* HAL_QEMU_INLINE_H */
