/* ARM semihosting calls (see semihost.h). */
#include "semihost.h"

uint32_t semihost_call(uint32_t op, uintptr_t arg)
{
    register uint32_t r0 __asm__("r0") = op;
    register uintptr_t r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void semihost_putc(char c)
{
    (void)semihost_call(SEMIHOST_SYS_WRITEC, (uintptr_t)&c);
}

void semihost_puts(const char *s)
{
    (void)semihost_call(SEMIHOST_SYS_WRITE0, (uintptr_t)s);
}

void semihost_exit(int status)
{
    const uint32_t block[2] = { SEMIHOST_ADP_STOPPED_APPLICATION_EXIT,
                                (uint32_t)status };
    (void)semihost_call(SEMIHOST_SYS_EXIT_EXTENDED, (uintptr_t)block);
    (void)semihost_call(SEMIHOST_SYS_EXIT,
                        status == 0
                            ? SEMIHOST_ADP_STOPPED_APPLICATION_EXIT
                            : SEMIHOST_ADP_STOPPED_RUNTIME_ERROR_UNKNOWN);
    for (;;) {
    }
}
