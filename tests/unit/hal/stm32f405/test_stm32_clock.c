/*
 * The STM32F405 clock tree (hal/stm32f405/clock.c) against RM0090: the PLL
 * dividers checked with the PLL's formulas, and the register values of
 * stm32_clock_init on the register fake checked field by field with
 * definitions written out here from RM0090 (not the port's regs.h macros).
 */
#include "mc_test.h"

#include <stdbool.h>
#include <string.h>

#include "clock.h"
#include "stm32_fake_regs.h"

#define MHZ 1000000.0

/* Field of width w at bit p. */
#define FIELD(v, p, w) (((uint32_t)(v) >> (p)) & ((1u << (w)) - 1u))

/* RM0090 7.3.1 RCC_CR */
#define RM_RCC_CR_HSEON  (1u << 16)
#define RM_RCC_CR_HSERDY (1u << 17)
#define RM_RCC_CR_PLLON  (1u << 24)
#define RM_RCC_CR_PLLRDY (1u << 25)

/* RM0090 7.3.2 RCC_PLLCFGR: PLLM[5:0], PLLN[14:6], PLLP[17:16] (00: /2,
 * 01: /4, 10: /6, 11: /8), PLLSRC bit 22 (1: HSE), PLLQ[27:24] */
#define RM_PLLM_POS   0
#define RM_PLLM_W     6
#define RM_PLLN_POS   6
#define RM_PLLN_W     9
#define RM_PLLP_POS   16
#define RM_PLLP_W     2
#define RM_PLLSRC_HSE (1u << 22)
#define RM_PLLQ_POS   24
#define RM_PLLQ_W     4

/* RM0090 7.3.3 RCC_CFGR: SW[1:0] (00 HSI, 01 HSE, 10 PLL), SWS[3:2],
 * HPRE[7:4] (0xxx: /1), PPRE1[12:10], PPRE2[15:13] (0xx: /1, 100: /2,
 * 101: /4, 110: /8, 111: /16) */
#define RM_CFGR_SW_POS    0
#define RM_CFGR_SWS_POS   2
#define RM_CFGR_HPRE_POS  4
#define RM_CFGR_PPRE1_POS 10
#define RM_CFGR_PPRE2_POS 13
#define RM_SW_HSI         0u
#define RM_SW_PLL         2u

/* RM0090 3.9.1 FLASH_ACR: LATENCY[2:0], PRFTEN 8, ICEN 9, DCEN 10 */
#define RM_ACR_LATENCY_W 3
#define RM_ACR_PRFTEN    (1u << 8)
#define RM_ACR_ICEN      (1u << 9)
#define RM_ACR_DCEN      (1u << 10)

/* RM0090 5.4.1 PWR_CR: VOS bit 14 (1: scale 1, up to 168 MHz) */
#define RM_PWR_CR_VOS (1u << 14)

/* RM0090 7.3.13 RCC_APB1ENR: PWREN bit 28 */
#define RM_APB1ENR_PWREN (1u << 28)

#define WAIT 100u

/* APB prescaler of a PPREx code (RM0090 7.3.3). */
static uint32_t apb_div(uint32_t code)
{
    return (code < 4u) ? 1u : (1u << (code - 3u));
}

/* RM0090 7.2 (clock tree figure): a timer kernel clock is PCLK if the APB
 * prescaler is 1, else 2 PCLK. */
static uint32_t timer_clock(uint32_t pclk, uint32_t div)
{
    return (div == 1u) ? pclk : 2u * pclk;
}

static bool all_zero(const volatile void *p, size_t n)
{
    const volatile unsigned char *b = p;
    for (size_t k = 0; k < n; ++k) {
        if (b[k] != 0u) {
            return false;
        }
    }
    return true;
}

/* RM0090 6.3.3 / 7.3.2: f_VCO_in = f_in / M in [1, 2] MHz (2 recommended),
 * f_VCO = f_VCO_in N in [100, 432] MHz, SYSCLK = f_VCO / P, USB = f_VCO / Q,
 * 2 <= M <= 63, 50 <= N <= 432, P in {2, 4, 6, 8}, 2 <= Q <= 15. */
static void check_pll(uint32_t hse_hz, const stm32_pll_t *p)
{
    assert_true(p->m >= 2u && p->m <= 63u);
    assert_true(p->n >= 50u && p->n <= 432u);
    assert_true(p->p == 2u || p->p == 4u || p->p == 6u || p->p == 8u);
    assert_true(p->q >= 2u && p->q <= 15u);
    const double vco_in = (double)hse_hz / p->m;
    assert_true(vco_in >= 1.0 * MHZ && vco_in <= 2.0 * MHZ);
    const double vco = vco_in * p->n;
    assert_near(vco, 336.0 * MHZ, 1e-6);
    assert_near(vco / p->p, 168.0 * MHZ, 1e-6);
    assert_near(vco / p->q, 48.0 * MHZ, 1e-6);
}

static void test_pll_8mhz(void **state)
{
    (void)state;
    stm32_pll_t p;
    assert_true(stm32_clock_pll_for(8000000u, &p));
    assert_int_equal(p.m, 4);
    assert_int_equal(p.n, 168);
    assert_int_equal(p.p, 2);
    assert_int_equal(p.q, 7);
    const double vco = 8.0 * MHZ * p.n / p.m;
    assert_near(vco, 336.0 * MHZ, 1e-6);
    assert_near(vco / p.p, 168.0 * MHZ, 1e-6);
    assert_near(vco / p.q, 48.0 * MHZ, 1e-6);
    check_pll(8000000u, &p);
}

static void test_pll_25mhz(void **state)
{
    (void)state;
    stm32_pll_t p;
    assert_true(stm32_clock_pll_for(25000000u, &p));
    check_pll(25000000u, &p);
}

static void test_pll_every_whole_mhz(void **state)
{
    (void)state;
    for (uint32_t mhz = 4u; mhz <= 26u; ++mhz) {
        stm32_pll_t p;
        assert_true(stm32_clock_pll_for(mhz * 1000000u, &p));
        check_pll(mhz * 1000000u, &p);
        /* SYSCLK exactly 168 MHz in whole numbers */
        assert_int_equal(mhz * 1000000u / p.m * p.n / p.p, 168000000u);
    }
}

static void test_pll_rejects(void **state)
{
    (void)state;
    stm32_pll_t p;
    assert_false(stm32_clock_pll_for(3000000u, &p));
    assert_false(stm32_clock_pll_for(27000000u, &p));
    assert_false(stm32_clock_pll_for(8500000u, &p));
    assert_false(stm32_clock_pll_for(0u, &p));
}

/* The clocks reported after falling back to the HSI (16 MHz, all /1). */
static void check_on_hsi(const stm32_clocks_t *c)
{
    assert_int_equal(c->sysclk_hz, 16000000u);
    assert_int_equal(c->hclk_hz, 16000000u);
    assert_int_equal(c->pclk1_hz, 16000000u);
    assert_int_equal(c->pclk2_hz, 16000000u);
    assert_int_equal(c->tim_apb1_hz, 16000000u);
    assert_int_equal(c->tim_apb2_hz, 16000000u);
    const uint32_t cfgr = stm32_fake_rcc.CFGR;
    assert_int_equal(FIELD(cfgr, RM_CFGR_SW_POS, 2), RM_SW_HSI);
    assert_int_equal(FIELD(cfgr, RM_CFGR_HPRE_POS, 4) & 8u, 0u);
    assert_int_equal(apb_div(FIELD(cfgr, RM_CFGR_PPRE1_POS, 3)), 1u);
    assert_int_equal(apb_div(FIELD(cfgr, RM_CFGR_PPRE2_POS, 3)), 1u);
    assert_int_equal(stm32_fake_rcc.CR & (RM_RCC_CR_HSEON | RM_RCC_CR_PLLON), 0u);
}

static void test_init_ok(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_fake_rcc.CR = RM_RCC_CR_HSERDY | RM_RCC_CR_PLLRDY;
    stm32_fake_rcc.CFGR = RM_SW_PLL << RM_CFGR_SWS_POS; /* SWS = PLL */
    stm32_clocks_t c;
    stm32_clock_init(8000000u, WAIT, &c);
    assert_int_equal(c.status, STM32_CLOCK_OK);

    /* PLLCFGR: M = 4, N = 168, P = 2 (code 00), HSE, Q = 7; nothing else */
    const uint32_t pllcfgr = stm32_fake_rcc.PLLCFGR;
    assert_int_equal(FIELD(pllcfgr, RM_PLLM_POS, RM_PLLM_W), 4u);
    assert_int_equal(FIELD(pllcfgr, RM_PLLN_POS, RM_PLLN_W), 168u);
    assert_int_equal(FIELD(pllcfgr, RM_PLLP_POS, RM_PLLP_W), 0u);
    assert_int_equal(FIELD(pllcfgr, RM_PLLQ_POS, RM_PLLQ_W), 7u);
    assert_true((pllcfgr & RM_PLLSRC_HSE) != 0u);
    assert_int_equal(pllcfgr, (4u << RM_PLLM_POS) | (168u << RM_PLLN_POS) | (0u << RM_PLLP_POS) |
                                  RM_PLLSRC_HSE | (7u << RM_PLLQ_POS));

    /* CR: HSE and PLL on (the preset ready flags kept) */
    assert_int_equal(stm32_fake_rcc.CR,
                     RM_RCC_CR_HSEON | RM_RCC_CR_HSERDY | RM_RCC_CR_PLLON | RM_RCC_CR_PLLRDY);

    /* CFGR: SW = PLL, AHB /1, APB1 /4 (101), APB2 /2 (100), SWS kept */
    const uint32_t cfgr = stm32_fake_rcc.CFGR;
    assert_int_equal(FIELD(cfgr, RM_CFGR_SW_POS, 2), RM_SW_PLL);
    assert_int_equal(FIELD(cfgr, RM_CFGR_HPRE_POS, 4) & 8u, 0u);
    assert_int_equal(FIELD(cfgr, RM_CFGR_PPRE1_POS, 3), 5u);
    assert_int_equal(FIELD(cfgr, RM_CFGR_PPRE2_POS, 3), 4u);
    assert_int_equal(cfgr, (RM_SW_PLL << RM_CFGR_SW_POS) | (RM_SW_PLL << RM_CFGR_SWS_POS) |
                               (5u << RM_CFGR_PPRE1_POS) | (4u << RM_CFGR_PPRE2_POS));

    /* FLASH_ACR: 5 wait states (RM0090 table 10, 2.7-3.6 V, 150-168 MHz),
     * prefetch, instruction and data caches */
    const uint32_t acr = stm32_fake_flash.ACR;
    assert_int_equal(FIELD(acr, 0, RM_ACR_LATENCY_W), 5u);
    assert_int_equal(acr, 5u | RM_ACR_PRFTEN | RM_ACR_ICEN | RM_ACR_DCEN);

    /* PWR: scale 1, with the PWR clock on */
    assert_int_equal(stm32_fake_pwr.CR, RM_PWR_CR_VOS);
    assert_int_equal(stm32_fake_rcc.APB1ENR, RM_APB1ENR_PWREN);

    /* reported clocks, from the registers' dividers */
    const double sysclk = 8.0 * MHZ / FIELD(pllcfgr, RM_PLLM_POS, RM_PLLM_W) *
                          FIELD(pllcfgr, RM_PLLN_POS, RM_PLLN_W) /
                          (2u * (FIELD(pllcfgr, RM_PLLP_POS, RM_PLLP_W) + 1u));
    const uint32_t div1 = apb_div(FIELD(cfgr, RM_CFGR_PPRE1_POS, 3));
    const uint32_t div2 = apb_div(FIELD(cfgr, RM_CFGR_PPRE2_POS, 3));
    const uint32_t hclk = (uint32_t)sysclk;
    assert_int_equal(c.sysclk_hz, hclk);
    assert_int_equal(c.hclk_hz, hclk);
    assert_int_equal(c.pclk1_hz, hclk / div1);
    assert_int_equal(c.pclk2_hz, hclk / div2);
    assert_int_equal(c.tim_apb1_hz, timer_clock(hclk / div1, div1));
    assert_int_equal(c.tim_apb2_hz, timer_clock(hclk / div2, div2));
    /* the same in numbers */
    assert_int_equal(c.sysclk_hz, 168000000u);
    assert_int_equal(c.pclk1_hz, 42000000u);
    assert_int_equal(c.pclk2_hz, 84000000u);
    assert_int_equal(c.tim_apb1_hz, 84000000u);
    assert_int_equal(c.tim_apb2_hz, 168000000u);
}

static void test_init_ok_25mhz(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_fake_rcc.CR = RM_RCC_CR_HSERDY | RM_RCC_CR_PLLRDY;
    stm32_fake_rcc.CFGR = RM_SW_PLL << RM_CFGR_SWS_POS;
    stm32_clocks_t c;
    stm32_clock_init(25000000u, WAIT, &c);
    assert_int_equal(c.status, STM32_CLOCK_OK);
    const uint32_t pllcfgr = stm32_fake_rcc.PLLCFGR;
    const uint32_t m = FIELD(pllcfgr, RM_PLLM_POS, RM_PLLM_W);
    const uint32_t n = FIELD(pllcfgr, RM_PLLN_POS, RM_PLLN_W);
    const uint32_t p = 2u * (FIELD(pllcfgr, RM_PLLP_POS, RM_PLLP_W) + 1u);
    const uint32_t q = FIELD(pllcfgr, RM_PLLQ_POS, RM_PLLQ_W);
    assert_near(25.0 * MHZ / m * n / p, 168.0 * MHZ, 1e-6);
    assert_near(25.0 * MHZ / m * n / q, 48.0 * MHZ, 1e-6);
    assert_int_equal(c.sysclk_hz, 168000000u);
}

static void test_init_hse_timeout(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_clocks_t c;
    stm32_clock_init(8000000u, WAIT, &c);
    assert_int_equal(c.status, STM32_CLOCK_HSE_TIMEOUT);
    check_on_hsi(&c);
    assert_int_equal(stm32_fake_rcc.CR & RM_RCC_CR_HSEON, 0u);
}

static void test_init_pll_timeout(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_fake_rcc.CR = RM_RCC_CR_HSERDY;
    stm32_clocks_t c;
    stm32_clock_init(8000000u, WAIT, &c);
    assert_int_equal(c.status, STM32_CLOCK_PLL_TIMEOUT);
    check_on_hsi(&c);
    assert_int_equal(stm32_fake_rcc.CR & (RM_RCC_CR_PLLON | RM_RCC_CR_HSEON), 0u);
}

static void test_init_switch_timeout(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_fake_rcc.CR = RM_RCC_CR_HSERDY | RM_RCC_CR_PLLRDY; /* SWS stays HSI */
    stm32_clocks_t c;
    stm32_clock_init(8000000u, WAIT, &c);
    assert_int_equal(c.status, STM32_CLOCK_SWITCH_TIMEOUT);
    check_on_hsi(&c);
}

static void test_init_bad_crystal(void **state)
{
    (void)state;
    const uint32_t bad[] = { 3000000u, 27000000u, 8500000u };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        stm32_fake_reset();
        stm32_clocks_t c;
        memset(&c, 0xA5, sizeof c);
        stm32_clock_init(bad[k], WAIT, &c);
        assert_int_equal(c.status, STM32_CLOCK_BAD_CRYSTAL);
        assert_int_equal(c.sysclk_hz, 16000000u);
        assert_int_equal(c.hclk_hz, 16000000u);
        assert_int_equal(c.pclk1_hz, 16000000u);
        assert_int_equal(c.pclk2_hz, 16000000u);
        assert_int_equal(c.tim_apb1_hz, 16000000u);
        assert_int_equal(c.tim_apb2_hz, 16000000u);
        assert_true(all_zero(&stm32_fake_rcc, sizeof stm32_fake_rcc));
        assert_true(all_zero(&stm32_fake_flash, sizeof stm32_fake_flash));
        assert_true(all_zero(&stm32_fake_pwr, sizeof stm32_fake_pwr));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pll_8mhz),
        cmocka_unit_test(test_pll_25mhz),
        cmocka_unit_test(test_pll_every_whole_mhz),
        cmocka_unit_test(test_pll_rejects),
        cmocka_unit_test(test_init_ok),
        cmocka_unit_test(test_init_ok_25mhz),
        cmocka_unit_test(test_init_hse_timeout),
        cmocka_unit_test(test_init_pll_timeout),
        cmocka_unit_test(test_init_switch_timeout),
        cmocka_unit_test(test_init_bad_crystal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
