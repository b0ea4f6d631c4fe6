/* The DRV8301 over SPI3 (drv8301.h). */
#include "drv8301.h"

#include "gpio_cfg.h"
#include "regs.h"

#define SPI_WAIT_LOOPS 10000u /* one 16-bit frame is ~500 cycles */
#define SPI_BR_DIV8    2u     /* f_PCLK / 8 */

/* One frame out, one in; false on a timeout. nSCS framed around it. */
static bool transfer(const stm32_board_t *b, uint16_t out, uint16_t *in)
{
    stm32_spi_t *spi = STM32_SPI3;
    stm32_gpio_write(&b->spi_cs, false);
    spi->DR = out;
    const bool done =
        stm32_wait_bits(&spi->SR, SPI_SR_RXNE, SPI_SR_RXNE, SPI_WAIT_LOOPS);
    *in = (uint16_t)spi->DR;
    (void)stm32_wait_bits(&spi->SR, SPI_SR_BSY, 0u, SPI_WAIT_LOOPS);
    stm32_gpio_write(&b->spi_cs, true);
    return done;
}

stm32_drv_status_t stm32_drv8301_setup(const stm32_board_t *b)
{
    STM32_RCC->APB1ENR |= RCC_APB1ENR_SPI3EN;
    stm32_gpio_setup(&b->spi_cs, GPIO_MODE_OUTPUT, STM32_PULL_NONE);
    stm32_gpio_write(&b->spi_cs, true);
    stm32_gpio_setup(&b->spi_sck, GPIO_MODE_AF, STM32_PULL_NONE);
    stm32_gpio_setup(&b->spi_miso, GPIO_MODE_AF, STM32_PULL_UP);
    stm32_gpio_setup(&b->spi_mosi, GPIO_MODE_AF, STM32_PULL_NONE);
    STM32_SPI3->CR1 = SPI_CR1_CPHA | SPI_CR1_MSTR |
                      (SPI_BR_DIV8 << SPI_CR1_BR_POS) | SPI_CR1_SSI |
                      SPI_CR1_SSM | SPI_CR1_DFF | SPI_CR1_SPE;
    const uint16_t frames[4] = {
        drv8301_frame(false, DRV8301_ADDR_CTRL1, b->drv_ctrl1),
        drv8301_frame(false, DRV8301_ADDR_CTRL2, b->drv_ctrl2),
        drv8301_frame(true, DRV8301_ADDR_CTRL1, 0u),
        drv8301_frame(true, DRV8301_ADDR_CTRL2, 0u),
    };
    uint16_t in[5];
    for (uint32_t k = 0u; k < 4u; ++k) {
        if (!transfer(b, frames[k], &in[k])) {
            return STM32_DRV_SPI_TIMEOUT;
        }
    }
    /* the answer to the second read comes with a fifth frame */
    if (!transfer(b, drv8301_frame(true, DRV8301_ADDR_CTRL2, 0u), &in[4])) {
        return STM32_DRV_SPI_TIMEOUT;
    }
    /* answers: bit 15 frame error, bits 14:11 address, 10:0 data */
    const bool ok1 =
        in[3] == drv8301_frame(false, DRV8301_ADDR_CTRL1, b->drv_ctrl1);
    const bool ok2 =
        in[4] == drv8301_frame(false, DRV8301_ADDR_CTRL2, b->drv_ctrl2);
    return (ok1 && ok2) ? STM32_DRV_OK : STM32_DRV_READBACK;
}
