/* Pin set-up (RM0090 8.4): clock of the port, mode, alternate function,
 * speed, pull; and the fast set/reset of an output through BSRR. */
#ifndef STM32_GPIO_CFG_H
#define STM32_GPIO_CFG_H

#include <stdbool.h>

#include "board.h"
#include "regs.h"

typedef enum {
    STM32_PULL_NONE = 0,
    STM32_PULL_UP = 1,
    STM32_PULL_DOWN = 2
} stm32_pull_t;

/* The port's clock on, the pin in `mode` (GPIO_MODE_*) with its alternate
 * function (pin->af, used in GPIO_MODE_AF), very high speed for outputs,
 * the pull. */
void stm32_gpio_setup(const stm32_pin_t *pin, uint32_t mode, stm32_pull_t pull);

/* Drive an output: one BSRR write (atomic, no read-modify-write). */
static inline void stm32_gpio_write(const stm32_pin_t *pin, bool high)
{
    STM32_GPIO(pin->port)->BSRR =
        high ? (1u << pin->pin) : (1u << (pin->pin + 16u));
}

static inline bool stm32_gpio_read(const stm32_pin_t *pin)
{
    return (STM32_GPIO(pin->port)->IDR & (1u << pin->pin)) != 0u;
}

#endif /* STM32_GPIO_CFG_H */
