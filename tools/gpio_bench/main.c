/*
 * pmsm-gpio-bench: HIL bench helper on a Linux host wired to the drive
 * (README.md beside this file).
 */
#include "gb_main.h"

#include <stdio.h>

int main(int argc, char **argv)
{
    return gb_main(argc, argv, stdout, stderr);
}
