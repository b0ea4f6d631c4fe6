/* The clock tree (clock.h). */
#include "clock.h"

#include <stdbool.h>

#include "regs.h"

#define MHZ 1000000u

bool stm32_clock_pll_for(uint32_t hse_hz, stm32_pll_t *pll)
{
    if (hse_hz % MHZ != 0u || hse_hz < 4u * MHZ || hse_hz > 26u * MHZ) {
        return false;
    }
    const uint32_t mhz = hse_hz / MHZ;
    /* VCO input 2 MHz where the crystal allows (less jitter), else 1 MHz;
     * VCO 336 MHz; SYSCLK = VCO / 2; USB = VCO / 7 = 48 MHz */
    pll->m = (mhz % 2u == 0u) ? mhz / 2u : mhz;
    pll->n = 336u / (hse_hz / pll->m / MHZ);
    pll->p = 2u;
    pll->q = 7u;
    return true;
}

/* CFGR's fields the code sets: SW, HPRE, PPRE1, PPRE2 (read-modify-write:
 * the rest, SWS among them, as they are). */
#define CFGR_SET_MASK                                                          \
    (RCC_CFGR_SW_MASK | (0xFu << RCC_CFGR_HPRE_POS) |                          \
     (7u << RCC_CFGR_PPRE1_POS) | (7u << RCC_CFGR_PPRE2_POS))

/* PLLCFGR's reserved bits (15, 21:18, 23, 31:28; bit 29 resets to 1):
 * kept at their value, as RM0090 7.3.2 asks. */
#define PLLCFGR_RESERVED 0xF0BC8000u

/* What runs on the HSI with every prescaler at 1. */
static stm32_clocks_t hsi_clocks(stm32_clock_status_t status)
{
    return (stm32_clocks_t){
        .status = status,
        .sysclk_hz = STM32_HSI_HZ,
        .hclk_hz = STM32_HSI_HZ,
        .pclk1_hz = STM32_HSI_HZ,
        .pclk2_hz = STM32_HSI_HZ,
        .tim_apb1_hz = STM32_HSI_HZ,
        .tim_apb2_hz = STM32_HSI_HZ,
    };
}

/* Back to the HSI after a failed step: SW = HSI, prescalers 1, PLL and
 * HSE off. */
static void on_hsi(stm32_clock_status_t status, stm32_clocks_t *out)
{
    stm32_rcc_t *rcc = STM32_RCC;
    rcc->CFGR = (rcc->CFGR & ~CFGR_SET_MASK) | RCC_CFGR_SW_HSI; /* all /1 */
    rcc->CR &= ~(RCC_CR_PLLON | RCC_CR_HSEON);
    *out = hsi_clocks(status);
}

void stm32_clock_init(uint32_t hse_hz, uint32_t wait_loops, stm32_clocks_t *out)
{
    stm32_pll_t pll;
    if (!stm32_clock_pll_for(hse_hz, &pll)) {
        *out = hsi_clocks(STM32_CLOCK_BAD_CRYSTAL); /* nothing touched */
        return;
    }
    stm32_rcc_t *rcc = STM32_RCC;
    rcc->CR |= RCC_CR_HSEON;
    if (!stm32_wait_bits(&rcc->CR, RCC_CR_HSERDY, RCC_CR_HSERDY, wait_loops)) {
        on_hsi(STM32_CLOCK_HSE_TIMEOUT, out);
        return;
    }
    /* regulator scale 1 and the flash's wait states before the speed */
    rcc->APB1ENR |= RCC_APB1ENR_PWREN;
    STM32_PWR->CR |= PWR_CR_VOS;
    STM32_FLASH->ACR = 5u | FLASH_ACR_PRFTEN | FLASH_ACR_ICEN | FLASH_ACR_DCEN;
    rcc->CFGR = (rcc->CFGR & ~CFGR_SET_MASK) | (0u << RCC_CFGR_HPRE_POS) |
                (RCC_APB_DIV4 << RCC_CFGR_PPRE1_POS) |
                (RCC_APB_DIV2 << RCC_CFGR_PPRE2_POS) | RCC_CFGR_SW_HSI;
    rcc->PLLCFGR = (rcc->PLLCFGR & PLLCFGR_RESERVED) |
                   (pll.m << RCC_PLLCFGR_M_POS) | (pll.n << RCC_PLLCFGR_N_POS) |
                   ((pll.p / 2u - 1u) << RCC_PLLCFGR_P_POS) |
                   RCC_PLLCFGR_SRC_HSE | (pll.q << RCC_PLLCFGR_Q_POS);
    rcc->CR |= RCC_CR_PLLON;
    if (!stm32_wait_bits(&rcc->CR, RCC_CR_PLLRDY, RCC_CR_PLLRDY, wait_loops)) {
        on_hsi(STM32_CLOCK_PLL_TIMEOUT, out);
        return;
    }
    rcc->CFGR = (rcc->CFGR & ~RCC_CFGR_SW_MASK) | RCC_CFGR_SW_PLL;
    if (!stm32_wait_bits(&rcc->CFGR, RCC_CFGR_SWS_MASK, RCC_CFGR_SWS_PLL,
                         wait_loops)) {
        on_hsi(STM32_CLOCK_SWITCH_TIMEOUT, out);
        return;
    }
    const uint32_t sysclk = hse_hz / pll.m * pll.n / pll.p;
    *out = (stm32_clocks_t){
        .status = STM32_CLOCK_OK,
        .sysclk_hz = sysclk,
        .hclk_hz = sysclk,
        .pclk1_hz = sysclk / 4u,
        .pclk2_hz = sysclk / 2u,
        .tim_apb1_hz = sysclk / 2u,
        .tim_apb2_hz = sysclk,
    };
}
