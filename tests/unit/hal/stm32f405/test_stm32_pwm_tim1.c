/*
 * TIM1 PWM (hal/stm32f405/pwm_tim1.c) against RM0090 section 17 (advanced
 * control timers TIM1/TIM8): the dead-time generator's encoding decoded
 * with the rule of 17.4.18 written out here, and the registers
 * stm32_pwm_tim1_init leaves in the register fake checked field by field
 * with definitions written here (not the port's regs.h macros). The
 * period and dead time are derived from the physics, not copied from the
 * driver.
 */
#include "mc_test.h"

#include <stdbool.h>

#include "pwm_tim1.h"
#include "stm32_fake_regs.h"

#define FIELD(v, p, w) (((uint32_t)(v) >> (p)) & ((1u << (w)) - 1u))

/* RM0090 17.4.1 TIMx_CR1: CEN 0, DIR 4, CMS[6:5] (01: centre-aligned
 * mode 1), ARPE 7 */
#define RM_CR1_CEN     (1u << 0)
#define RM_CR1_DIR     (1u << 4)
#define RM_CR1_CMS_POS 5
#define RM_CR1_ARPE    (1u << 7)

/* RM0090 17.4.6 TIMx_EGR: UG 0 */
#define RM_EGR_UG (1u << 0)

/* RM0090 17.4.7 / 17.4.8 TIMx_CCMR1/2 (output compare mode): per channel
 * byte CCxS[1:0] (00: output), OCxPE bit 3, OCxM[6:4] (110: PWM mode 1);
 * the second channel of the register in bits 15:8 */
#define RM_CCMR_CCS_POS 0
#define RM_CCMR_OCPE    (1u << 3)
#define RM_CCMR_OCM_POS 4
#define RM_OCM_PWM1     6u

/* RM0090 17.4.9 TIMx_CCER: CC1E 0, CC1P 1, CC1NE 2, CC1NP 3, CC2E 4, CC2P 5,
 * CC2NE 6, CC2NP 7, CC3E 8, CC3P 9, CC3NE 10, CC3NP 11, CC4E 12, CC4P 13 */
#define RM_CCER_CC1E  (1u << 0)
#define RM_CCER_CC1P  (1u << 1)
#define RM_CCER_CC1NE (1u << 2)
#define RM_CCER_CC1NP (1u << 3)
#define RM_CCER_CC2E  (1u << 4)
#define RM_CCER_CC2P  (1u << 5)
#define RM_CCER_CC2NE (1u << 6)
#define RM_CCER_CC2NP (1u << 7)
#define RM_CCER_CC3E  (1u << 8)
#define RM_CCER_CC3P  (1u << 9)
#define RM_CCER_CC3NE (1u << 10)
#define RM_CCER_CC3NP (1u << 11)
#define RM_CCER_CC4E  (1u << 12)
#define RM_CCER_CC4P  (1u << 13)

/* RM0090 17.4.18 TIMx_BDTR: DTG[7:0], LOCK[9:8], OSSI 10, OSSR 11, BKE 12,
 * BKP 13 (1: break input active high), AOE 14, MOE 15 */
#define RM_BDTR_DTG_W    8
#define RM_BDTR_LOCK_POS 8
#define RM_BDTR_OSSI     (1u << 10)
#define RM_BDTR_OSSR     (1u << 11)
#define RM_BDTR_BKE      (1u << 12)
#define RM_BDTR_BKP      (1u << 13)
#define RM_BDTR_AOE      (1u << 14)
#define RM_BDTR_MOE      (1u << 15)

/* RM0090 7.3.14 RCC_APB2ENR: TIM1EN 0 */
#define RM_APB2ENR_TIM1EN (1u << 0)

#define TIM_CLK 168000000u

/* The dead time of a DTG code in t_DTS clocks (RM0090 17.4.18, CKD = 00 so
 * t_DTG = t_DTS): DTG[7] = 0: DTG[7:0]; DTG[7:6] = 10: (64 + DTG[5:0]) 2;
 * DTG[7:5] = 110: (32 + DTG[4:0]) 8; DTG[7:5] = 111: (32 + DTG[4:0]) 16. */
static uint32_t rm_dtg_clocks(uint32_t dtg)
{
    if ((dtg & 0x80u) == 0u) {
        return dtg;
    }
    if ((dtg & 0xC0u) == 0x80u) {
        return (64u + (dtg & 0x3Fu)) * 2u;
    }
    if ((dtg & 0xE0u) == 0xC0u) {
        return (32u + (dtg & 0x1Fu)) * 8u;
    }
    return (32u + (dtg & 0x1Fu)) * 16u;
}

/* The driver rounds the request up to whole clocks after taking 1e-3
 * clock off (so that a request of exactly n clocks, not representable in
 * float, gives n): a realised time may be short of the request by at most
 * that, 6 ps at 168 MHz. */
#define DT_SLACK_CLOCKS 1e-3

/* The shortest encodable dead time (in clocks) >= req_clocks, by
 * enumerating all 256 codes; UINT32_MAX if none. */
static uint32_t shortest_clocks(double req_clocks)
{
    uint32_t best = UINT32_MAX;
    for (uint32_t code = 0u; code < 256u; ++code) {
        const uint32_t c = rm_dtg_clocks(code);
        if ((double)c >= req_clocks - DT_SLACK_CLOCKS && c < best) {
            best = c;
        }
    }
    return best;
}

/* One request: the decoded code equals the reported time, is >= the
 * request and is the shortest such. */
static void check_dead_time(float dt_s, uint32_t clk)
{
    uint32_t dtg = 0xFFFFFFFFu;
    float realised = -1.0f;
    const double req = (double)dt_s * clk;
    const uint32_t want = shortest_clocks(req);
    if (want == UINT32_MAX) {
        assert_false(stm32_tim_dtg_for(dt_s, clk, &dtg, &realised));
        return;
    }
    assert_true(stm32_tim_dtg_for(dt_s, clk, &dtg, &realised));
    assert_true(dtg <= 0xFFu);
    const uint32_t got = rm_dtg_clocks(dtg);
    assert_near(realised, (double)got / clk, 1e-6 * ((double)got / clk) + 1e-15);
    assert_true((double)got >= req - DT_SLACK_CLOCKS);
    assert_int_equal(got, want);
}

static void test_dtg_named_times(void **state)
{
    (void)state;
    const float times[] = { 0.0f,    1e-9f, 5e-9f,   6e-9f, 10e-9f, 100e-9f, 500e-9f,
                            750e-9f, 1e-6f, 1.5e-6f, 2e-6f, 3e-6f,  5e-6f,   5.9e-6f };
    for (size_t k = 0; k < sizeof times / sizeof times[0]; ++k) {
        check_dead_time(times[k], TIM_CLK);
        check_dead_time(times[k], TIM_CLK / 2u);
    }
    /* 500 ns at 168 MHz: 84 clocks, code 84 (DTG[7] = 0) */
    uint32_t dtg;
    float realised;
    assert_true(stm32_tim_dtg_for(500e-9f, TIM_CLK, &dtg, &realised));
    assert_int_equal(rm_dtg_clocks(dtg), 84u);
    /* 1 us: 168 clocks, (64 + 20) 2 */
    assert_true(stm32_tim_dtg_for(1e-6f, TIM_CLK, &dtg, &realised));
    assert_int_equal(rm_dtg_clocks(dtg), 168u);
    /* 2 us: 336 clocks, (32 + 10) 8 */
    assert_true(stm32_tim_dtg_for(2e-6f, TIM_CLK, &dtg, &realised));
    assert_int_equal(rm_dtg_clocks(dtg), 336u);
    /* 5 us: 840 clocks, (32 + 21) 16 = 848 */
    assert_true(stm32_tim_dtg_for(5e-6f, TIM_CLK, &dtg, &realised));
    assert_int_equal(rm_dtg_clocks(dtg), 848u);
}

/* Every quarter clock from 0 to 1010 clocks (past the end of the range). */
static void test_dtg_sweep(void **state)
{
    (void)state;
    for (uint32_t q = 0u; q <= 4u * 1010u; ++q) {
        check_dead_time((float)(q / 4.0 / TIM_CLK), TIM_CLK);
    }
}

static void test_dtg_range_end(void **state)
{
    (void)state;
    uint32_t dtg;
    float realised;
    /* 1008 clocks: the longest, code 0xFF */
    assert_true(stm32_tim_dtg_for((float)(1008.0 / TIM_CLK), TIM_CLK, &dtg, &realised));
    assert_int_equal(rm_dtg_clocks(dtg), 1008u);
    assert_false(stm32_tim_dtg_for((float)(1008.5 / TIM_CLK), TIM_CLK, &dtg, &realised));
    assert_false(stm32_tim_dtg_for((float)(1009.0 / TIM_CLK), TIM_CLK, &dtg, &realised));
    assert_false(stm32_tim_dtg_for(7e-6f, TIM_CLK, &dtg, &realised));
    assert_false(stm32_tim_dtg_for(1.0f, TIM_CLK, &dtg, &realised));
    assert_false(stm32_tim_dtg_for(NAN, TIM_CLK, &dtg, &realised));
    assert_false(stm32_tim_dtg_for(-1e-9f, TIM_CLK, &dtg, &realised));
    assert_false(stm32_tim_dtg_for(-INFINITY, TIM_CLK, &dtg, &realised));
    assert_false(stm32_tim_dtg_for(INFINITY, TIM_CLK, &dtg, &realised));
}

static stm32_pwm_cfg_t cfg_20k(void)
{
    return (stm32_pwm_cfg_t){ .tim_clk_hz = TIM_CLK,
                              .f_pwm_Hz = 20000.0f,
                              .dead_time_s = 500e-9f,
                              .break_enable = false,
                              .break_active_high = false };
}

/* Everything but the break bits, for a configuration at 168 MHz, 20 kHz,
 * 500 ns. */
static void check_20k_registers(const stm32_pwm_t *out)
{
    const stm32_tim_t *t = &stm32_fake_tim1;
    /* centre-aligned: the counter goes 0 -> ARR -> 0, a period of 2 ARR
     * clocks (RM0090 17.3.2 figure "center-aligned"), so ARR = f_tim /
     * (2 f_pwm) */
    const uint32_t arr = (uint32_t)lround(168e6 / (2.0 * 20e3));
    assert_int_equal(arr, 4200u);
    assert_int_equal(t->ARR, arr);
    assert_int_equal(t->PSC, 0u);
    assert_int_equal(t->RCR, 0u);

    assert_int_equal(FIELD(t->CR1, RM_CR1_CMS_POS, 2), 1u);
    assert_int_equal(t->CR1 & RM_CR1_DIR, 0u);
    assert_int_equal(t->CR1, RM_CR1_CEN | (1u << RM_CR1_CMS_POS) | RM_CR1_ARPE);
    assert_int_equal(t->CR2, 0u); /* idle levels OISx/OISxN low */

    const uint32_t pwm1 = (RM_OCM_PWM1 << RM_CCMR_OCM_POS) | RM_CCMR_OCPE;
    assert_int_equal(FIELD(t->CCMR1, RM_CCMR_OCM_POS, 3), RM_OCM_PWM1);
    assert_int_equal(FIELD(t->CCMR1, 8 + RM_CCMR_OCM_POS, 3), RM_OCM_PWM1);
    assert_int_equal(t->CCMR1, pwm1 | (pwm1 << 8));
    assert_int_equal(t->CCMR2 & 0xFFu, pwm1);
    /* channel 4: output compare (CC4S = 00) so that CCR4 produces the CC4
     * event the ADC triggers on */
    assert_int_equal(FIELD(t->CCMR2, 8 + RM_CCMR_CCS_POS, 2), 0u);

    const uint32_t ccer =
        RM_CCER_CC1E | RM_CCER_CC1NE | RM_CCER_CC2E | RM_CCER_CC2NE | RM_CCER_CC3E | RM_CCER_CC3NE;
    const uint32_t polarities = RM_CCER_CC1P | RM_CCER_CC1NP | RM_CCER_CC2P | RM_CCER_CC2NP |
                                RM_CCER_CC3P | RM_CCER_CC3NP | RM_CCER_CC4P;
    assert_int_equal(t->CCER & polarities, 0u);
    assert_int_equal(t->CCER & RM_CCER_CC4E, 0u);
    assert_int_equal(t->CCER, ccer);

    assert_int_equal(t->CCR[0], arr / 2u);
    assert_int_equal(t->CCR[1], arr / 2u);
    assert_int_equal(t->CCR[2], arr / 2u);
    assert_int_equal(t->CCR[3], arr - 1u);

    /* dead time: 500 ns at 168 MHz = 84 clocks; the code must decode to the
     * shortest encodable time >= that */
    const uint32_t dtg = FIELD(t->BDTR, 0, RM_BDTR_DTG_W);
    assert_int_equal(rm_dtg_clocks(dtg), shortest_clocks(500e-9 * 168e6));
    assert_int_equal(rm_dtg_clocks(dtg), 84u);
    assert_true((t->BDTR & RM_BDTR_OSSI) != 0u);
    assert_true((t->BDTR & RM_BDTR_OSSR) != 0u);
    assert_int_equal(t->BDTR & RM_BDTR_MOE, 0u);
    assert_int_equal(t->BDTR & RM_BDTR_AOE, 0u);
    assert_int_equal(FIELD(t->BDTR, RM_BDTR_LOCK_POS, 2), 0u);

    assert_true((t->EGR & RM_EGR_UG) != 0u);
    assert_true((stm32_fake_rcc.APB2ENR & RM_APB2ENR_TIM1EN) != 0u);

    assert_int_equal(out->arr, arr);
    assert_int_equal(out->dtg, dtg);
    /* float results: to a few float epsilons */
    assert_near(out->period_s, 2.0 * arr / 168e6, 4e-7 * 50e-6);
    assert_near(out->period_s, 1.0 / 20e3, 4e-7 * 50e-6);
    assert_near(out->dead_time_s, 84.0 / 168e6, 4e-7 * 500e-9);
    assert_near(out->delay_periods, 1.0, 0.0);
}

static void test_init_20k_no_break(void **state)
{
    (void)state;
    stm32_fake_reset();
    const stm32_pwm_cfg_t cfg = cfg_20k();
    stm32_pwm_t out;
    assert_int_equal(stm32_pwm_tim1_init(&cfg, &out), STM32_PWM_OK);
    check_20k_registers(&out);
    const uint32_t bdtr = stm32_fake_tim1.BDTR;
    assert_int_equal(bdtr & (RM_BDTR_BKE | RM_BDTR_BKP), 0u);
    /* nothing else: DTG, OSSI, OSSR */
    assert_int_equal(bdtr, (bdtr & 0xFFu) | RM_BDTR_OSSI | RM_BDTR_OSSR);
}

static void test_init_break_active_high(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_pwm_cfg_t cfg = cfg_20k();
    cfg.break_enable = true;
    cfg.break_active_high = true;
    stm32_pwm_t out;
    assert_int_equal(stm32_pwm_tim1_init(&cfg, &out), STM32_PWM_OK);
    check_20k_registers(&out);
    assert_int_equal(stm32_fake_tim1.BDTR & (RM_BDTR_BKE | RM_BDTR_BKP), RM_BDTR_BKE | RM_BDTR_BKP);
}

static void test_init_break_active_low(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_pwm_cfg_t cfg = cfg_20k();
    cfg.break_enable = true;
    cfg.break_active_high = false;
    stm32_pwm_t out;
    assert_int_equal(stm32_pwm_tim1_init(&cfg, &out), STM32_PWM_OK);
    check_20k_registers(&out);
    assert_int_equal(stm32_fake_tim1.BDTR & (RM_BDTR_BKE | RM_BDTR_BKP), RM_BDTR_BKE);
}

/* The ends of ARR's range [100, 65535]: ARR = f_tim / (2 f) rounded. */
static void test_init_arr_range_ends(void **state)
{
    (void)state;
    stm32_pwm_cfg_t cfg = cfg_20k();
    stm32_pwm_t out;
    stm32_fake_reset();
    cfg.f_pwm_Hz = (float)(168e6 / (2.0 * 100.0));
    assert_int_equal(stm32_pwm_tim1_init(&cfg, &out), STM32_PWM_OK);
    assert_int_equal(stm32_fake_tim1.ARR, 100u);
    stm32_fake_reset();
    cfg.f_pwm_Hz = (float)(168e6 / (2.0 * 65535.0));
    assert_int_equal(stm32_pwm_tim1_init(&cfg, &out), STM32_PWM_OK);
    assert_int_equal(stm32_fake_tim1.ARR, 65535u);
}

static bool tim1_untouched(void)
{
    const volatile unsigned char *b = (const volatile unsigned char *)&stm32_fake_tim1;
    for (size_t k = 0; k < sizeof stm32_fake_tim1; ++k) {
        if (b[k] != 0u) {
            return false;
        }
    }
    return stm32_fake_rcc.APB2ENR == 0u;
}

static void check_rejected(const stm32_pwm_cfg_t *cfg, stm32_pwm_status_t want)
{
    stm32_fake_reset();
    stm32_pwm_t out;
    assert_int_equal(stm32_pwm_tim1_init(cfg, &out), want);
    assert_true(tim1_untouched());
}

static void test_init_rejections(void **state)
{
    (void)state;
    stm32_pwm_cfg_t cfg = cfg_20k();
    const float bad_f[] = {
        (float)(168e6 / (2.0 * 99.0)),    /* ARR 99 */
        (float)(168e6 / (2.0 * 65536.0)), /* ARR 65536 */
        1e6f,                             /* ARR 84 */
        1000.0f,                          /* ARR 84000 */
        0.0f,
        -20000.0f,
        NAN,
        INFINITY,
    };
    for (size_t k = 0; k < sizeof bad_f / sizeof bad_f[0]; ++k) {
        cfg.f_pwm_Hz = bad_f[k];
        check_rejected(&cfg, STM32_PWM_BAD_FREQUENCY);
    }
    cfg = cfg_20k();
    cfg.tim_clk_hz = 0u;
    check_rejected(&cfg, STM32_PWM_BAD_FREQUENCY);

    cfg = cfg_20k();
    const float bad_dt[] = { 7e-6f, (float)(1009.0 / 168e6), -1e-9f, NAN, INFINITY };
    for (size_t k = 0; k < sizeof bad_dt / sizeof bad_dt[0]; ++k) {
        cfg.dead_time_s = bad_dt[k];
        check_rejected(&cfg, STM32_PWM_BAD_DEAD_TIME);
    }
}

static void test_ccr(void **state)
{
    (void)state;
    const float arr = 4200.0f;
    assert_int_equal(stm32_pwm_ccr(0.0f, arr), 0u);
    assert_int_equal(stm32_pwm_ccr(1.0f, arr), 4200u);
    assert_int_equal(stm32_pwm_ccr(0.5f, arr), 2100u);
    assert_int_equal(stm32_pwm_ccr(-0.1f, arr), 0u);
    assert_int_equal(stm32_pwm_ccr(-0.0f, arr), 0u);
    assert_int_equal(stm32_pwm_ccr(1.7f, arr), 4200u);
    assert_int_equal(stm32_pwm_ccr(NAN, arr), 2100u);
    assert_int_equal(stm32_pwm_ccr(INFINITY, arr), 4200u);
    assert_int_equal(stm32_pwm_ccr(-INFINITY, arr), 0u);
    /* to the nearest count: k + 0.4 counts -> k, k + 0.6 -> k + 1 */
    for (uint32_t k = 0u; k < 4200u; ++k) {
        assert_int_equal(stm32_pwm_ccr((float)((k + 0.4) / 4200.0), arr), k);
        assert_int_equal(stm32_pwm_ccr((float)((k + 0.6) / 4200.0), arr), k + 1u);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dtg_named_times),
        cmocka_unit_test(test_dtg_sweep),
        cmocka_unit_test(test_dtg_range_end),
        cmocka_unit_test(test_init_20k_no_break),
        cmocka_unit_test(test_init_break_active_high),
        cmocka_unit_test(test_init_break_active_low),
        cmocka_unit_test(test_init_arr_range_ends),
        cmocka_unit_test(test_init_rejections),
        cmocka_unit_test(test_ccr),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
