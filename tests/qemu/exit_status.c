/* The semihosting exit status reaches the host: main returns 42 (the ctest
 * requires exactly 42, so an exit path that always reports 0 or 1 fails). */
#include "qemu_m4.h"

int main(void)
{
    qemu_m4_puts("exit status 42\n");
    return 42;
}
