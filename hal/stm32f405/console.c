/* The console (console.h). */
#include "console.h"

#include "gpio_cfg.h"
#include "regs.h"

/* Transmit-register-empty waits: a stuck USART must not hang the boot
 * (about 10 character times at 115200 Bd on the HSI). */
#define CONSOLE_WAIT_LOOPS 20000u

void stm32_console_init(const stm32_board_t *b, uint32_t pclk1_hz)
{
    if (b->console_baud == 0u) {
        return; /* no console: the USART stays off */
    }
    STM32_RCC->APB1ENR |= RCC_APB1ENR_USART2EN;
    stm32_gpio_setup(&b->console_tx, GPIO_MODE_AF, STM32_PULL_UP);
    stm32_usart_t *u = STM32_USART2;
    /* oversampling by 16: BRR = f_PCLK / baud, 12.4 fixed point */
    u->BRR = (pclk1_hz + b->console_baud / 2u) / b->console_baud;
    u->CR1 = USART_CR1_UE | USART_CR1_TE;
}

static void put_char(char c)
{
    stm32_usart_t *u = STM32_USART2;
    /* on a timeout the character is written anyway (and may be lost) */
    (void)stm32_wait_bits(&u->SR, USART_SR_TXE, USART_SR_TXE,
                          CONSOLE_WAIT_LOOPS);
    u->DR = (uint32_t)(unsigned char)c;
}

void stm32_console_puts(const char *s)
{
    for (; *s != '\0'; ++s) {
        put_char(*s);
    }
}

void stm32_console_put_i32(int32_t v)
{
    char buf[12];
    uint32_t n = 0u;
    uint32_t m = (v < 0) ? (uint32_t)(-(v + 1)) + 1u : (uint32_t)v;
    do {
        buf[n++] = (char)('0' + m % 10u);
        m /= 10u;
    } while (m != 0u);
    if (v < 0) {
        put_char('-');
    }
    while (n > 0u) {
        put_char(buf[--n]);
    }
}

void stm32_boot(const char *what, stm32_clocks_t *clk)
{
    stm32_clock_init(stm32_board.hse_hz, STM32_CLOCK_WAIT_LOOPS, clk);
    stm32_console_init(&stm32_board, clk->pclk1_hz);
    stm32_console_puts(what);
    stm32_console_puts(" ");
    stm32_console_puts(stm32_board.name);
    stm32_console_puts("\r\n");
}
