/*
 * HAL binding of the QEMU image (the headers in hal/include/hal).
 *
 * The plant runs inside the image (host_sim/plant) and the closed loop is
 * host_sim/engine, compiled unchanged for the M4; the engine talks to the
 * HAL through the simulator mailbox (hal/sim_mailbox, shared with the host
 * binding). This file is the image's backend of it: a plain static binding
 * and the SysTick instruction counter of qemu_m4.h as the cycle counter.
 * Calling a HAL function while unbound is a test-bench wiring error: the
 * image prints it and exits with status QEMU_M4_EXIT_FAULT.
 */
#include <math.h>
#include <stddef.h>

#include "hal/time.h"
#include "hal_sim_mailbox.h"
#include "qemu_m4.h"
#include "semihost.h"

#define SYST_CSR               (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR               (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR               (*(volatile uint32_t *)0xE000E018u)
#define SYST_CSR_ENABLE        1u
#define SYST_CSR_CLKSOURCE_CPU 4u
#define SYST_RELOAD            0x00FFFFFFu

/* The shift this image was built for, readable from the ELF by tools that
 * start QEMU themselves (cycle_estimate.py). */
__attribute__((used)) const uint32_t qemu_m4_icount_shift =
    QEMU_M4_ICOUNT_SHIFT;

hal_sim_mailbox_t hal_qemu_regs;

/* Whether the engine has bound the mailbox (it binds it around each call
 * into the firmware). */
static bool mailbox_bound;

void qemu_m4_counter_init(void)
{
    SYST_CSR = 0u;
    SYST_RVR = SYST_RELOAD;
    SYST_CVR = 0u; /* any write clears: counting starts at the reload */
    SYST_CSR = SYST_CSR_ENABLE | SYST_CSR_CLKSOURCE_CPU;
}

/* ---- Mailbox binding (hal_sim_mailbox.h): one per image ----------------- */

hal_sim_mailbox_t *hal_sim_fixed_mailbox(void)
{
    return &hal_qemu_regs;
}

/* The accessors reach hal_qemu_regs directly: binding another mailbox is
 * a wiring error of the image. */
void hal_sim_bind(hal_sim_mailbox_t *mailbox)
{
    if (mailbox != NULL && mailbox != &hal_qemu_regs) {
        semihost_puts("FATAL: a mailbox other than the image's bound\n");
        semihost_exit(QEMU_M4_EXIT_FAULT);
    }
    mailbox_bound = (mailbox != NULL);
}

hal_sim_mailbox_t *hal_sim_bound(void)
{
    if (!mailbox_bound) {
        semihost_puts("FATAL: HAL called with no mailbox bound\n");
        semihost_exit(QEMU_M4_EXIT_FAULT);
    }
    return &hal_qemu_regs;
}

/* ---- Cycle counter ---------------------------------------------------------
 */

uint32_t hal_cycle_counter_hz(void)
{
    /* ticks per second of a QEMU_M4_CORE_HZ core at one instruction per
     * cycle: 168e6 * 2^6 / 40 = 268.8e6 (an integer for N >= 3). */
    return (uint32_t)(((uint64_t)QEMU_M4_CORE_HZ << QEMU_M4_ICOUNT_SHIFT) /
                      40u);
}

/* ---- Console --------------------------------------------------------------
 */

void qemu_m4_puts(const char *s)
{
    semihost_puts(s);
}

static void put_u64(uint64_t v)
{
    char buf[24];
    size_t i = sizeof buf - 1u;
    buf[i] = '\0';
    do {
        buf[--i] = (char)('0' + (int)(v % 10u));
        v /= 10u;
    } while (v != 0u);
    semihost_puts(&buf[i]);
}

void qemu_m4_put_u32(uint32_t v)
{
    put_u64(v);
}

void qemu_m4_put_i64(int64_t v)
{
    if (v < 0) {
        semihost_putc('-');
        put_u64((uint64_t)0 - (uint64_t)v);
    } else {
        put_u64((uint64_t)v);
    }
}

void qemu_m4_put_fixed(double x, unsigned decimals)
{
    if (isnan(x)) {
        semihost_puts("nan");
        return;
    }
    if (x < 0.0) {
        semihost_putc('-');
        x = -x;
    }
    if (isinf(x) || x >= 9.0e15) {
        semihost_puts("inf");
        return;
    }
    uint64_t scale = 1u;
    for (unsigned k = 0u; k < decimals; ++k) {
        scale *= 10u;
    }
    const uint64_t n = (uint64_t)llround(x * (double)scale);
    put_u64(n / scale);
    if (decimals > 0u) {
        char frac[24];
        uint64_t f = n % scale;
        frac[decimals] = '\0';
        for (unsigned k = decimals; k > 0u; --k) {
            frac[k - 1u] = (char)('0' + (int)(f % 10u));
            f /= 10u;
        }
        semihost_putc('.');
        semihost_puts(frac);
    }
}
