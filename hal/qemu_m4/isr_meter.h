/*
 * Instruction count of every mc_app_fast_isr call in the QEMU image.
 *
 * Images link with -Wl,--wrap=mc_app_fast_isr (mc_add_qemu_image does):
 * every call, e.g. the one in host_sim/engine's sim_engine_step, goes
 * through __wrap_mc_app_fast_isr, which reads SysTick before and after the
 * real ISR and stores the instructions in between (minus the cost of the
 * two reads, measured once at start-up with nothing in between). The
 * count includes the call and return instructions of the ISR.
 * Thread context (the image runs the engine in its main loop).
 *
 * Exact conversion. Under -icount shift=N an instruction is P = 2^N ns
 * of virtual time and a SysTick tick T = 40 ns (25 MHz), so a read in
 * instruction k sees E = floor((P k + c) / T) ticks elapsed (c: a constant
 * of the run). Rounding the tick difference (qemu_m4_ticks_to_instr) is
 * off by one for some lengths and start phases (shift 6: a gross count
 * = 2 mod 5 can read one high, seen in about 1 in 25 ISRs). The sub-tick
 * phase of a read, d = (P k + c) mod T, is d = (C + T * raw) mod P for a
 * constant C (raw: the down-counting SysTick value; d < T for every
 * read), so
 *   instructions = (T * ticks + d(t1) - d(t0)) / P      exactly,
 * the division without remainder. C is found once at start-up: the first
 * C in [0, P) for which six SysTick reads in consecutive instructions
 * are each exactly one instruction apart (any such C gives the same
 * counts). A read that does not fit (d >= T or a remainder) is counted in
 * isr_meter_errors() and converted by rounding.
 */
#ifndef QEMU_M4_ISR_METER_H
#define QEMU_M4_ISR_METER_H

#include <stdint.h>

typedef struct {
    uint32_t n;
    uint32_t min, max;
    uint64_t sum;
} isr_stats_t;

/* Instructions of the latest mc_app_fast_isr call. */
uint32_t isr_meter_last(void);

/* Instructions the two SysTick reads add (subtracted from every count). */
uint32_t isr_meter_overhead(void);

/* Reads the exact conversion could not handle (0 when the counter behaves
 * as modelled above; the closed-loop images check it). */
uint32_t isr_meter_errors(void);

/* Measure the instructions of fn(arg) like the ISR (for the counter's own
 * test). */
uint32_t isr_meter_measure(void (*fn)(void *), void *arg);

void isr_stats_reset(isr_stats_t *s);
void isr_stats_add(isr_stats_t *s, uint32_t instr);
/* Print "<label> n=.. min=.. mean=.. max=..\n" (mean with 1 decimal). */
void isr_stats_print(const char *label, const isr_stats_t *s);

#endif /* QEMU_M4_ISR_METER_H */
