/*
 * The instruction counter against code of known length: functions made of
 * exactly 1000 and 3000 NOPs (assembler .rept; NOP is a 16-bit Thumb
 * instruction the core executes, never folded) must measure exactly 1000
 * and 3000 instructions more than an empty function, under -icount
 * shift=6. Also prints the counter's own overhead. Exit 0 on success.
 */
#include <stdint.h>

#include "isr_meter.h"
#include "qemu_m4.h"

static __attribute__((noinline)) void nop0(void *arg)
{
    (void)arg;
    __asm__ volatile("" ::: "memory");
}

static __attribute__((noinline)) void nop1000(void *arg)
{
    (void)arg;
    __asm__ volatile(".rept 1000\n\tnop\n\t.endr" ::: "memory");
}

static __attribute__((noinline)) void nop3000(void *arg)
{
    (void)arg;
    __asm__ volatile(".rept 3000\n\tnop\n\t.endr" ::: "memory");
}

static void report(const char *name, uint32_t v)
{
    qemu_m4_puts("CHECK ");
    qemu_m4_puts(name);
    qemu_m4_puts(" ");
    qemu_m4_put_u32(v);
    qemu_m4_puts("\n");
}

int main(void)
{
    const uint32_t e = isr_meter_measure(nop0, 0);
    const uint32_t a = isr_meter_measure(nop1000, 0);
    const uint32_t b = isr_meter_measure(nop3000, 0);
    report("overhead", isr_meter_overhead());
    report("empty", e);
    report("delta_1000", a - e);
    report("delta_3000", b - e);
    return (a - e == 1000u && b - e == 3000u) ? 0 : 1;
}
