/* Pin set-up (gpio_cfg.h). */
#include "gpio_cfg.h"

void stm32_gpio_setup(const stm32_pin_t *pin, uint32_t mode, stm32_pull_t pull)
{
    STM32_RCC->AHB1ENR |= RCC_AHB1ENR_GPIO(pin->port);
    stm32_gpio_t *g = STM32_GPIO(pin->port);
    const uint32_t two = 2u * pin->pin;
    if (mode == GPIO_MODE_AF) {
        const uint32_t word = pin->pin / 8u;
        const uint32_t four = 4u * (pin->pin % 8u);
        g->AFR[word] =
            (g->AFR[word] & ~(0xFu << four)) | ((uint32_t)pin->af << four);
    }
    g->OSPEEDR |= 3u << two; /* very high speed */
    g->PUPDR = (g->PUPDR & ~(3u << two)) | ((uint32_t)pull << two);
    g->MODER = (g->MODER & ~(3u << two)) | (mode << two);
}
