/*
 * The QEMU Cortex-M4 image (mps2-an386): instruction counter, console
 * helpers and the exit status. See README.md in this directory.
 *
 * Instruction counter: SysTick, clocked by the processor clock (25 MHz on
 * the board model), run under `-icount shift=QEMU_M4_ICOUNT_SHIFT`; QEMU
 * then advances virtual time 2^N ns per instruction, so SysTick counts
 * 2^N / 40 ticks per instruction, deterministically, and
 *   instructions = round(ticks * 40 / 2^N)   (exact for N >= 6).
 * N = 6: 1.6 ticks per instruction; the 24-bit counter wraps after
 * 10.4 M instructions, far more than one fast ISR (~ 1-3 k) or one plant
 * period. Without -icount SysTick follows host time: the counts are then
 * meaningless (the qemu tests always pass -icount).
 *
 * hal_cycle_counter() (hal/time.h) is this counter's complement (counting
 * up, 24 bits significant), hal_cycles_since its difference modulo 2^24:
 * intervals shorter than 10.4 M instructions, true for an ISR.
 * hal_cycle_counter_hz() reports QEMU_M4_CORE_HZ * 2^N / 40, i.e. the
 * firmware's own ISR-cost measurement reads "instructions / 168 MHz": the
 * cost of the ISR on a 168 MHz Cortex-M4F at one cycle per instruction (a
 * lower bound; README.md gives the cycle estimate).
 *
 * Thread context only; nothing here is an interrupt handler.
 */
#ifndef QEMU_M4_H
#define QEMU_M4_H

#include <stdint.h>

/* QEMU_M4_ICOUNT_SHIFT comes from the build (MC_QEMU_ICOUNT_SHIFT,
 * cmake/McQemuImage.cmake), the value QEMU runs with. */
#ifndef QEMU_M4_ICOUNT_SHIFT
#error "QEMU_M4_ICOUNT_SHIFT is defined by the build (MC_QEMU_ICOUNT_SHIFT)"
#endif
#define QEMU_M4_CORE_HZ 168000000u /* modelled STM32F4-class core clock */

/* Exit status of a HardFault/BusFault/... (startup.c). */
#define QEMU_M4_EXIT_FAULT 99

/* Start SysTick: reload 0xFFFFFF, processor clock, no interrupt. Called by
 * the reset handler before main. */
void qemu_m4_counter_init(void);

/* Raw SysTick current value (24 bit, counts DOWN). */
static inline uint32_t qemu_m4_systick(void)
{
    return *(volatile uint32_t *)0xE000E018u;
}

/* Ticks elapsed from raw value `start` to raw value `end` (one wrap at
 * most). */
static inline uint32_t qemu_m4_ticks_between(uint32_t start, uint32_t end)
{
    return (start - end) & 0x00FFFFFFu;
}

/* Ticks -> instructions, round(ticks * 40 / 2^N). */
static inline uint32_t qemu_m4_ticks_to_instr(uint32_t ticks)
{
    return (uint32_t)(((uint64_t)ticks * 40u +
                       (1u << (QEMU_M4_ICOUNT_SHIFT - 1u))) >>
                      QEMU_M4_ICOUNT_SHIFT);
}

/* Console (semihosting SYS_WRITE0): a string, an unsigned / signed
 * integer, a double with `decimals` digits after the point (|x| < 9e15;
 * NaN/Inf print as "nan"/"inf"). No printf: nothing that allocates. */
void qemu_m4_puts(const char *s);
void qemu_m4_put_u32(uint32_t v);
void qemu_m4_put_i64(int64_t v);
void qemu_m4_put_fixed(double x, unsigned decimals);

#endif /* QEMU_M4_H */
