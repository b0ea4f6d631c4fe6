/*
 * HAL contract: the few digital signals the drive firmware uses.
 */
#ifndef HAL_GPIO_H
#define HAL_GPIO_H

#include <stdbool.h>

#ifdef HAL_INLINE_ACCESSORS
#include HAL_INLINE_ACCESSORS /* the binding's static inline definitions */
#else
/* True while the external fault / safe-torque-off input is asserted (gate
 * driver fault, STO chain open, e-stop). Interrupt context:
 * yes. */
bool hal_gpio_fault_input_active(void);

/* Drive the power-stage enable (gate-driver enable) pin. The PWM outputs
 * switch only while this is enabled AND hal_pwm outputs are enabled.
 * Interrupt context: yes. */
void hal_gpio_power_stage_enable(bool enable);

/* Set the debug pin (scope timing of the ISR). Callable from interrupt
 * context: yes. */
void hal_gpio_debug_pin_set(bool level);
#endif

#endif /* HAL_GPIO_H */
