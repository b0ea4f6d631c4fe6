/* Instruction count of mc_app_fast_isr (see isr_meter.h). */
#include "isr_meter.h"

#include "mc/app.h"
#include "qemu_m4.h"

void __real_mc_app_fast_isr(mc_app_t *app);
void __wrap_mc_app_fast_isr(mc_app_t *app);

static uint32_t last_instr;
static uint32_t overhead_instr;
static int overhead_known;
static uint32_t phase_c; /* C of isr_meter.h, found by calibrate() */
static int phase_known;
static uint32_t meter_errors;

#define NS_PER_INSTR (1u << QEMU_M4_ICOUNT_SHIFT)
#define NS_PER_TICK  40u /* SysTick at 25 MHz */
#define CAL_READS    6

/* The sub-tick phase of a read (isr_meter.h); < NS_PER_TICK if the read
 * fits the calibration. */
static uint32_t phase(uint32_t raw)
{
    return (phase_c + NS_PER_TICK * raw) & (NS_PER_INSTR - 1u);
}

/* Exact instructions from raw value t0 to raw value t1 (isr_meter.h);
 * 0 if the reads do not fit the calibration. */
static int exact_instr(uint32_t t0, uint32_t t1, uint32_t *n)
{
    const uint32_t p0 = phase(t0);
    const uint32_t p1 = phase(t1);
    if (p0 >= NS_PER_TICK || p1 >= NS_PER_TICK) {
        return 0;
    }
    const int32_t ns = (int32_t)(NS_PER_TICK * qemu_m4_ticks_between(t0, t1)) +
                       (int32_t)p1 - (int32_t)p0;
    if (ns < 0 || ((uint32_t)ns & (NS_PER_INSTR - 1u)) != 0u) {
        return 0;
    }
    *n = (uint32_t)ns >> QEMU_M4_ICOUNT_SHIFT;
    return 1;
}

/* CAL_READS reads of SysTick in consecutive instructions, then the first C
 * for which every neighbouring pair is exactly one instruction apart. */
static void calibrate(void)
{
    uint32_t r[CAL_READS];
    __asm__ volatile("ldr %0, [%6]\n\t"
                     "ldr %1, [%6]\n\t"
                     "ldr %2, [%6]\n\t"
                     "ldr %3, [%6]\n\t"
                     "ldr %4, [%6]\n\t"
                     "ldr %5, [%6]"
                     : "=&r"(r[0]), "=&r"(r[1]), "=&r"(r[2]), "=&r"(r[3]),
                       "=&r"(r[4]), "=&r"(r[5])
                     : "r"(0xE000E018u)
                     : "memory");
    for (uint32_t c = 0u; c < NS_PER_INSTR && !phase_known; c++) {
        phase_c = c;
        int fits = 1;
        for (unsigned i = 0u; i + 1u < CAL_READS && fits; i++) {
            uint32_t n;
            fits = exact_instr(r[i], r[i + 1u], &n) && n == 1u;
        }
        phase_known = fits;
    }
    if (!phase_known) {
        meter_errors++;
    }
}

static uint32_t raw_instr(uint32_t t0, uint32_t t1)
{
    uint32_t n;
    if (phase_known && exact_instr(t0, t1, &n)) {
        return n;
    }
    meter_errors++;
    return qemu_m4_ticks_to_instr(qemu_m4_ticks_between(t0, t1));
}

uint32_t isr_meter_overhead(void)
{
    if (!overhead_known) {
        calibrate();
        const uint32_t t0 = qemu_m4_systick();
        const uint32_t t1 = qemu_m4_systick();
        overhead_instr = raw_instr(t0, t1);
        overhead_known = 1;
    }
    return overhead_instr;
}

uint32_t isr_meter_errors(void)
{
    return meter_errors;
}

static uint32_t net(uint32_t t0, uint32_t t1)
{
    const uint32_t gross = raw_instr(t0, t1);
    const uint32_t ovh = isr_meter_overhead();
    return gross > ovh ? gross - ovh : 0u;
}

void __wrap_mc_app_fast_isr(mc_app_t *app)
{
    (void)isr_meter_overhead();
    /* Read, call, read in one asm block: nothing but the call between the
     * two SysTick reads, whatever the compiler schedules around it
     * (cycle_estimate.py checks the code). The clobbers are what the
     * AAPCS lets the callee change. */
    register mc_app_t *a0 __asm__("r0") = app;
    register uint32_t addr __asm__("r4") = 0xE000E018u;
    register uint32_t t0 __asm__("r5");
    register uint32_t t1 __asm__("r6");
#define METER_CALL                                                             \
    "ldr %0, [%3]\n\t"                                                         \
    "bl __real_mc_app_fast_isr\n\t"                                            \
    "ldr %1, [%3]"
#if defined(__ARM_FP)
    __asm__ volatile(METER_CALL
                     : "=&r"(t0), "=&r"(t1), "+r"(a0)
                     : "r"(addr)
                     : "r1", "r2", "r3", "r12", "lr", "cc", "memory", "s0",
                       "s1", "s2", "s3", "s4", "s5", "s6", "s7", "s8", "s9",
                       "s10", "s11", "s12", "s13", "s14", "s15");
#else
    __asm__ volatile(METER_CALL
                     : "=&r"(t0), "=&r"(t1), "+r"(a0)
                     : "r"(addr)
                     : "r1", "r2", "r3", "r12", "lr", "cc", "memory");
#endif
    last_instr = net(t0, t1);
}

uint32_t isr_meter_measure(void (*fn)(void *), void *arg)
{
    (void)isr_meter_overhead();
    const uint32_t t0 = qemu_m4_systick();
    fn(arg);
    const uint32_t t1 = qemu_m4_systick();
    return net(t0, t1);
}

uint32_t isr_meter_last(void)
{
    return last_instr;
}

void isr_stats_reset(isr_stats_t *s)
{
    *s = (isr_stats_t){ .min = UINT32_MAX };
}

void isr_stats_add(isr_stats_t *s, uint32_t instr)
{
    s->n++;
    s->sum += instr;
    if (instr < s->min) {
        s->min = instr;
    }
    if (instr > s->max) {
        s->max = instr;
    }
}

void isr_stats_print(const char *label, const isr_stats_t *s)
{
    qemu_m4_puts(label);
    qemu_m4_puts(" n=");
    qemu_m4_put_u32(s->n);
    qemu_m4_puts(" min=");
    qemu_m4_put_u32(s->n ? s->min : 0u);
    qemu_m4_puts(" mean=");
    qemu_m4_put_fixed(s->n ? (double)s->sum / (double)s->n : 0.0, 1u);
    qemu_m4_puts(" max=");
    qemu_m4_put_u32(s->max);
    qemu_m4_puts("\n");
}
