/* Instruction count of mc_app_fast_isr (see isr_meter.h). */
#include "isr_meter.h"

#include "mc/app.h"
#include "qemu_m4.h"

void __real_mc_app_fast_isr(mc_app_t *app);
void __wrap_mc_app_fast_isr(mc_app_t *app);

static uint32_t last_instr;
static uint32_t overhead_instr;
static int overhead_known;

static uint32_t raw_instr(uint32_t t0, uint32_t t1)
{
    return qemu_m4_ticks_to_instr(qemu_m4_ticks_between(t0, t1));
}

uint32_t isr_meter_overhead(void)
{
    if (!overhead_known) {
        const uint32_t t0 = qemu_m4_systick();
        const uint32_t t1 = qemu_m4_systick();
        overhead_instr = raw_instr(t0, t1);
        overhead_known = 1;
    }
    return overhead_instr;
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
    const uint32_t t0 = qemu_m4_systick();
    __real_mc_app_fast_isr(app);
    const uint32_t t1 = qemu_m4_systick();
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
