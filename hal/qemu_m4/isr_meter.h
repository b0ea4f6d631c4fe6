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

/* Measure the instructions of fn(arg) like the ISR (for the counter's own
 * test). */
uint32_t isr_meter_measure(void (*fn)(void *), void *arg);

void isr_stats_reset(isr_stats_t *s);
void isr_stats_add(isr_stats_t *s, uint32_t instr);
/* Print "<label> n=.. min=.. mean=.. max=..\n" (mean with 1 decimal). */
void isr_stats_print(const char *label, const isr_stats_t *s);

#endif /* QEMU_M4_ISR_METER_H */
