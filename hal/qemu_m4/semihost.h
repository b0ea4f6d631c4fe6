/*
 * ARM semihosting for the QEMU image (qemu-system-arm
 * -semihosting-config enable=on,target=native): console output and the
 * exit status. Thread context only (BKPT 0xAB traps to the debugger/QEMU);
 * never from the fast ISR.
 */
#ifndef QEMU_M4_SEMIHOST_H
#define QEMU_M4_SEMIHOST_H

#include <stdint.h>

/* Operation numbers (ARM "Semihosting for AArch32 and AArch64", 2.0). */
#define SEMIHOST_SYS_WRITEC        0x03u
#define SEMIHOST_SYS_WRITE0        0x04u
#define SEMIHOST_SYS_EXIT          0x18u
#define SEMIHOST_SYS_EXIT_EXTENDED 0x20u
/* angel_SWIreason_ReportException reason codes. */
#define SEMIHOST_ADP_STOPPED_APPLICATION_EXIT      0x20026u
#define SEMIHOST_ADP_STOPPED_RUNTIME_ERROR_UNKNOWN 0x20023u

/* Raw call: r0 = op, r1 = arg; returns r0. */
uint32_t semihost_call(uint32_t op, uintptr_t arg);

/* SYS_WRITEC: one character. */
void semihost_putc(char c);

/* SYS_WRITE0: a NUL-terminated string. */
void semihost_puts(const char *s);

/* Terminate QEMU with this exit status. On 32-bit ARM, SYS_EXIT takes the
 * reason code in r1 directly and cannot carry a status (QEMU: 0 for
 * ADP_Stopped_ApplicationExit, 1 otherwise), so the status goes through
 * SYS_EXIT_EXTENDED (0x20, semihosting 2.0; QEMU >= 5.0): r1 points to
 * { ADP_Stopped_ApplicationExit, status }. Should a host not support it,
 * SYS_EXIT follows: status 0 -> ApplicationExit, else
 * RunTimeErrorUnknown (exit status 1). Never returns. */
__attribute__((noreturn)) void semihost_exit(int status);

#endif /* QEMU_M4_SEMIHOST_H */
