/*
 * The smaller drivers of the STM32F405 port against their references, with
 * field definitions written out here (not the port's regs.h macros): the
 * TIM3 encoder and the GPIO set-up (RM0090 sections 18, 8), the DRV8301's
 * SPI frame (the DRV8301 datasheet), the independent watchdog (RM0090
 * section 21) and the MPU stack guard (ARMv7-M Architecture Reference
 * Manual B3.5, Cortex-M4 programming manual PM0214 4.2 and 4.4).
 */
#include "mc_test.h"

#include <stdbool.h>
#include <string.h>

#include "board.h"
#include "console.h"
#include "drv8301.h"
#include "encoder_tim.h"
#include "gpio_cfg.h"
#include "iwdg.h"
#include "stack_guard.h"
#include "stm32_fake_regs.h"

#define FIELD(v, p, w) (((uint32_t)(v) >> (p)) & ((1u << (w)) - 1u))

#define PA 0u
#define PB 1u
#define PC 2u
#define PD 3u

/* RM0090 8.4.1 GPIOx_MODER (2 bits per pin: 00 input, 01 output, 10
 * alternate function, 11 analog), 8.4.3 OSPEEDR (2 bits, 11 very high),
 * 8.4.4 PUPDR (2 bits: 00 none, 01 pull-up, 10 pull-down), 8.4.7 BSRR
 * (BSy bit y, BRy bit y + 16), 8.4.9 / 8.4.10 AFRL / AFRH (4 bits per pin,
 * pins 0..7 / 8..15) */
#define RM_MODER_IN     0u
#define RM_MODER_OUT    1u
#define RM_MODER_AF     2u
#define RM_MODER_ANALOG 3u
#define RM_OSPEED_VHIGH 3u
#define RM_PUPD_NONE    0u
#define RM_PUPD_UP      1u
#define RM_PUPD_DOWN    2u

/* RM0090 7.3.10 RCC_AHB1ENR: GPIOxEN at bit x (A = 0); 7.3.13 RCC_APB1ENR:
 * TIM3EN 1 */
#define RM_APB1ENR_TIM3EN (1u << 1)

/* RM0090 18.4.1 TIMx_CR1: CEN 0; 18.4.3 TIMx_SMCR: SMS[2:0] (011: encoder
 * mode 3, both inputs' edges); 18.4.7 TIMx_CCMR1 (input capture): CC1S[1:0]
 * (01: IC1 on TI1), IC1F[7:4], CC2S[9:8] (01: IC2 on TI2), IC2F[15:12];
 * 18.4.9 TIMx_CCER: CC1P 1, CC1NP 3, CC2P 5, CC2NP 7 */
#define RM_CR1_CEN        (1u << 0)
#define RM_SMCR_SMS_ENC3  3u
#define RM_CCS_TI         1u
#define RM_CCMR1_CC1S_POS 0
#define RM_CCMR1_IC1F_POS 4
#define RM_CCMR1_CC2S_POS 8
#define RM_CCMR1_IC2F_POS 12
#define RM_CCER_POLARITY  ((1u << 1) | (1u << 3) | (1u << 5) | (1u << 7))

/* TIM3_CH1 / TIM3_CH2 on PB4 / PB5: AF2 (STM32F405 datasheet, alternate
 * function mapping) */
#define RM_AF_TIM3 2u

static bool bytes_zero(const volatile void *p, size_t n)
{
    const volatile unsigned char *b = p;
    for (size_t k = 0; k < n; ++k) {
        if (b[k] != 0u) {
            return false;
        }
    }
    return true;
}

/* ---- encoder --------------------------------------------------------- */

static void test_encoder_init(void **state)
{
    (void)state;
    stm32_fake_reset();
    assert_true(stm32_encoder_init(&stm32_board));
    const stm32_tim_t *t = &stm32_fake_tim3;
    assert_int_equal(FIELD(t->SMCR, 0, 3), RM_SMCR_SMS_ENC3);
    assert_int_equal(t->SMCR, RM_SMCR_SMS_ENC3);
    assert_int_equal(FIELD(t->CCMR1, RM_CCMR1_CC1S_POS, 2), RM_CCS_TI);
    assert_int_equal(FIELD(t->CCMR1, RM_CCMR1_CC2S_POS, 2), RM_CCS_TI);
    /* the same input filter on both channels, nothing else in CCMR1 */
    const uint32_t f1 = FIELD(t->CCMR1, RM_CCMR1_IC1F_POS, 4);
    assert_int_equal(FIELD(t->CCMR1, RM_CCMR1_IC2F_POS, 4), f1);
    assert_int_equal(t->CCMR1, (RM_CCS_TI << RM_CCMR1_CC1S_POS) | (f1 << RM_CCMR1_IC1F_POS) |
                                   (RM_CCS_TI << RM_CCMR1_CC2S_POS) | (f1 << RM_CCMR1_IC2F_POS));
    assert_int_equal(t->CCER & RM_CCER_POLARITY, 0u);
    /* the count within a revolution: 0 .. cpr - 1 */
    assert_int_equal(t->ARR, stm32_board.encoder_counts_per_rev - 1u);
    assert_int_equal(t->ARR, 8191u);
    assert_int_equal(t->PSC, 0u);
    assert_int_equal(t->CR1, RM_CR1_CEN);
    assert_int_equal(stm32_fake_rcc.APB1ENR, RM_APB1ENR_TIM3EN);
    assert_int_equal(stm32_fake_rcc.AHB1ENR, 1u << PB);

    /* PB4, PB5: alternate function 2 (AFRL pin 4 bits 19:16, pin 5 bits
     * 23:20), MODER 10 */
    const stm32_gpio_t *g = &stm32_fake_gpio[PB];
    assert_int_equal(g->AFR[0], (RM_AF_TIM3 << 16) | (RM_AF_TIM3 << 20));
    assert_int_equal(g->AFR[1], 0u);
    assert_int_equal(g->MODER, (RM_MODER_AF << 8) | (RM_MODER_AF << 10));
}

static void test_encoder_range(void **state)
{
    (void)state;
    stm32_board_t b = stm32_board;
    const uint32_t bad[] = { 0u, 3u, 65537u, 100000u };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        stm32_fake_reset();
        b.encoder_counts_per_rev = bad[k];
        assert_false(stm32_encoder_init(&b));
        assert_true(bytes_zero(&stm32_fake_tim3, sizeof stm32_fake_tim3));
        assert_int_equal(stm32_fake_rcc.APB1ENR, 0u);
    }
    /* the ends: TIM3 is 16 bits (ARR up to 65535) */
    stm32_fake_reset();
    b.encoder_counts_per_rev = 65536u;
    assert_true(stm32_encoder_init(&b));
    assert_int_equal(stm32_fake_tim3.ARR, 65535u);
    stm32_fake_reset();
    b.encoder_counts_per_rev = 4u;
    assert_true(stm32_encoder_init(&b));
    assert_int_equal(stm32_fake_tim3.ARR, 3u);
}

/* ---- DRV8301 SPI frame ----------------------------------------------- */

/* DRV8301 datasheet, SPI input data word: bit 15 R/W (1 read, 0 write),
 * bits 14:11 the register address A3..A0, bits 10:0 the data D10..D0 */
#define DRV_RW_READ  (1u << 15)
#define DRV_ADDR_POS 11
#define DRV_ADDR_W   4
#define DRV_DATA_W   11

static void test_drv8301_frame(void **state)
{
    (void)state;
    /* control register 1 is address 0x02, control register 2 0x03 */
    assert_int_equal(drv8301_frame(true, 2u, 0u), DRV_RW_READ | (2u << DRV_ADDR_POS));
    assert_int_equal(drv8301_frame(true, 2u, 0u), 0x9000u);
    assert_int_equal(drv8301_frame(false, 3u, 0x7FFu), (3u << DRV_ADDR_POS) | 0x7FFu);
    assert_int_equal(drv8301_frame(false, 3u, 0x7FFu), 0x1FFFu);
    for (uint32_t addr = 0u; addr < 16u; ++addr) {
        for (uint32_t data = 0u; data < 0x800u; data += 0x55u) {
            for (int rd = 0; rd < 2; ++rd) {
                const uint16_t f = drv8301_frame(rd != 0, addr, data);
                assert_int_equal(FIELD(f, 15, 1), (uint32_t)rd);
                assert_int_equal(FIELD(f, DRV_ADDR_POS, DRV_ADDR_W), addr);
                assert_int_equal(FIELD(f, 0, DRV_DATA_W), data);
            }
        }
    }
    /* out-of-range data and addresses stay in their fields */
    assert_int_equal(drv8301_frame(false, 2u, 0x800u), 2u << DRV_ADDR_POS);
    assert_int_equal(drv8301_frame(false, 0x12u, 0u), 2u << DRV_ADDR_POS);
}

/* ---- IWDG ------------------------------------------------------------ */

/* RM0090 21.4.1 IWDG_KR KEY[15:0] (0xCCCC start, 0x5555 write access to
 * PR/RLR, 0xAAAA reload), 21.4.2 IWDG_PR PR[2:0] (011: /32), 21.4.3
 * IWDG_RLR RL[11:0], 21.4.4 IWDG_SR PVU 0, RVU 1 */
#define RM_KR_RELOAD 0xAAAAu
#define RM_PR_DIV32  3u
#define RM_SR_PVU    (1u << 0)
#define RM_SR_RVU    (1u << 1)

/* The fake keeps only the last value written to KR: the order of the keys
 * (0xCCCC, 0x5555, then PR and RLR, then 0xAAAA) is not observable here;
 * the last key, the reload, is. */
static void test_iwdg_start(void **state)
{
    (void)state;
    stm32_fake_reset();
    assert_true(stm32_iwdg_start());
    assert_int_equal(stm32_fake_iwdg.KR, RM_KR_RELOAD);
    assert_int_equal(FIELD(stm32_fake_iwdg.PR, 0, 3), RM_PR_DIV32);
    assert_int_equal(stm32_fake_iwdg.PR, RM_PR_DIV32);
    /* 50 ms at the typical LSI, 32 kHz: 32 kHz / 32 = 1 kHz, 50 counts */
    assert_int_equal(stm32_fake_iwdg.RLR, (uint32_t)lround(0.050 * 32000.0 / 32.0));
    assert_true(stm32_fake_iwdg.RLR <= 0xFFFu);

    stm32_fake_iwdg.KR = 0u;
    stm32_iwdg_refresh();
    assert_int_equal(stm32_fake_iwdg.KR, RM_KR_RELOAD);
}

static void test_iwdg_busy(void **state)
{
    (void)state;
    const uint32_t busy[] = { RM_SR_PVU, RM_SR_RVU, RM_SR_PVU | RM_SR_RVU };
    for (size_t k = 0; k < sizeof busy / sizeof busy[0]; ++k) {
        stm32_fake_reset();
        stm32_fake_iwdg.SR = busy[k];
        assert_false(stm32_iwdg_start());
        assert_int_equal(stm32_fake_iwdg.KR, RM_KR_RELOAD);
    }
}

/* ---- MPU stack guard ------------------------------------------------- */

/* ARMv7-M ARM B3.5.8 MPU_RBAR: ADDR[31:5] (region base), VALID 4,
 * REGION[3:0]; B3.5.9 MPU_RASR: ENABLE 0, SIZE[5:1] (2^(SIZE + 1) bytes),
 * SRD[15:8], B 16, C 17, S 18, TEX[21:19], AP[26:24] (000: no access), XN
 * 28; B3.5.7 MPU_CTRL: ENABLE 0, HFNMIENA 1, PRIVDEFENA 2; B3.2.13
 * SHCSR: MEMFAULTENA 16, BUSFAULTENA 17, USGFAULTENA 18 */
#define RM_RBAR_VALID       (1u << 4)
#define RM_RASR_ENABLE      (1u << 0)
#define RM_RASR_SIZE_POS    1
#define RM_RASR_AP_POS      24
#define RM_RASR_XN          (1u << 28)
#define RM_MPU_CTRL_ENABLE  (1u << 0)
#define RM_MPU_CTRL_HFNMI   (1u << 1)
#define RM_MPU_CTRL_PRIVDEF (1u << 2)
#define RM_SHCSR_MEMFAULT   (1u << 16)
#define RM_SHCSR_BUSFAULT   (1u << 17)

static void test_stack_guard(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_fake_scb.SHCSR = RM_SHCSR_BUSFAULT; /* kept */
    stm32_fake_mpu.RNR = 5u;
    stm32_stack_guard_init(0x20001000u);
    const stm32_mpu_t *m = &stm32_fake_mpu;
    assert_int_equal(m->RNR, 0u);
    assert_int_equal(m->RBAR, 0x20001000u);
    assert_int_equal(m->RBAR & (RM_RBAR_VALID | 0xFu), 0u); /* region from RNR */
    /* 32 bytes: 2^(SIZE + 1) = 32, SIZE = 4 */
    const uint32_t size_code = (uint32_t)lround(log2(32.0)) - 1u;
    assert_int_equal(FIELD(m->RASR, RM_RASR_SIZE_POS, 5), size_code);
    assert_int_equal(FIELD(m->RASR, RM_RASR_AP_POS, 3), 0u);
    assert_true((m->RASR & RM_RASR_XN) != 0u);
    assert_true((m->RASR & RM_RASR_ENABLE) != 0u);
    /* no sub-region disabled, TEX/S/C/B 0 */
    assert_int_equal(m->RASR, RM_RASR_XN | (size_code << RM_RASR_SIZE_POS) | RM_RASR_ENABLE);
    assert_int_equal(m->CTRL, RM_MPU_CTRL_ENABLE | RM_MPU_CTRL_PRIVDEF);
    assert_int_equal(m->CTRL & RM_MPU_CTRL_HFNMI, 0u);
    assert_int_equal(stm32_fake_scb.SHCSR, RM_SHCSR_MEMFAULT | RM_SHCSR_BUSFAULT);

    /* an unaligned address: the region is the 32-byte block containing it */
    stm32_fake_reset();
    stm32_stack_guard_init(0x2000101Fu);
    assert_int_equal(stm32_fake_mpu.RBAR, 0x20001000u);
}

/* ---- GPIO set-up ----------------------------------------------------- */

#define PATTERN_A 0xA5A5A5A5u
#define PATTERN_B 0x5A5A5A5Au

static void preset_port(uint32_t port)
{
    stm32_gpio_t *g = &stm32_fake_gpio[port];
    g->MODER = PATTERN_A;
    g->OTYPER = PATTERN_B;
    g->OSPEEDR = PATTERN_B;
    g->PUPDR = PATTERN_A;
    g->AFR[0] = PATTERN_A;
    g->AFR[1] = PATTERN_B;
}

static uint32_t with_field(uint32_t v, uint32_t pos, uint32_t width, uint32_t field)
{
    const uint32_t mask = ((1u << width) - 1u) << pos;
    return (v & ~mask) | (field << pos);
}

/* One pin set up over the patterns: its fields as RM0090 encodes them, every
 * other pin's fields as they were. */
static void check_pin(stm32_pin_t pin, uint32_t mode, stm32_pull_t pull, uint32_t rm_mode,
                      uint32_t rm_pull)
{
    stm32_fake_reset();
    preset_port(pin.port);
    stm32_gpio_setup(&pin, mode, pull);
    const stm32_gpio_t *g = &stm32_fake_gpio[pin.port];
    const uint32_t two = 2u * pin.pin;
    assert_int_equal(g->MODER, with_field(PATTERN_A, two, 2, rm_mode));
    assert_int_equal(g->PUPDR, with_field(PATTERN_A, two, 2, rm_pull));
    assert_int_equal(g->OSPEEDR, with_field(PATTERN_B, two, 2, RM_OSPEED_VHIGH));
    assert_int_equal(g->OTYPER, PATTERN_B);
    if (rm_mode == RM_MODER_AF) {
        const uint32_t word = pin.pin / 8u;
        const uint32_t four = 4u * (pin.pin % 8u);
        const uint32_t pat[2] = { PATTERN_A, PATTERN_B };
        assert_int_equal(g->AFR[word], with_field(pat[word], four, 4, pin.af));
        assert_int_equal(g->AFR[1u - word], pat[1u - word]);
    } else {
        assert_int_equal(g->AFR[0], PATTERN_A);
        assert_int_equal(g->AFR[1], PATTERN_B);
    }
    assert_int_equal(stm32_fake_rcc.AHB1ENR, 1u << pin.port);
    for (uint32_t p = 0u; p < 9u; ++p) {
        if (p != pin.port) {
            assert_true(bytes_zero(&stm32_fake_gpio[p], sizeof stm32_fake_gpio[p]));
        }
    }
}

static void test_gpio_setup(void **state)
{
    (void)state;
    /* alternate functions in AFRH and AFRL */
    check_pin((stm32_pin_t){ PB, 9u, 9u }, GPIO_MODE_AF, STM32_PULL_NONE, RM_MODER_AF,
              RM_PUPD_NONE);
    check_pin((stm32_pin_t){ PB, 8u, 9u }, GPIO_MODE_AF, STM32_PULL_UP, RM_MODER_AF, RM_PUPD_UP);
    check_pin((stm32_pin_t){ PA, 2u, 7u }, GPIO_MODE_AF, STM32_PULL_DOWN, RM_MODER_AF,
              RM_PUPD_DOWN);
    check_pin((stm32_pin_t){ PC, 15u, 14u }, GPIO_MODE_AF, STM32_PULL_UP, RM_MODER_AF, RM_PUPD_UP);
    check_pin((stm32_pin_t){ PA, 0u, 1u }, GPIO_MODE_AF, STM32_PULL_NONE, RM_MODER_AF,
              RM_PUPD_NONE);
    check_pin((stm32_pin_t){ PC, 7u, 15u }, GPIO_MODE_AF, STM32_PULL_NONE, RM_MODER_AF,
              RM_PUPD_NONE);
    /* the other modes leave AFR alone */
    check_pin((stm32_pin_t){ PC, 13u, 5u }, GPIO_MODE_OUTPUT, STM32_PULL_NONE, RM_MODER_OUT,
              RM_PUPD_NONE);
    check_pin((stm32_pin_t){ PC, 0u, 3u }, GPIO_MODE_ANALOG, STM32_PULL_NONE, RM_MODER_ANALOG,
              RM_PUPD_NONE);
    check_pin((stm32_pin_t){ PD, 2u, 0u }, GPIO_MODE_INPUT, STM32_PULL_UP, RM_MODER_IN, RM_PUPD_UP);
}

static void test_gpio_write_read(void **state)
{
    (void)state;
    stm32_fake_reset();
    const stm32_pin_t pin = { PC, 13u, 0u };
    stm32_gpio_write(&pin, true);
    assert_int_equal(stm32_fake_gpio[PC].BSRR, 1u << 13); /* BS13 */
    stm32_gpio_write(&pin, false);
    assert_int_equal(stm32_fake_gpio[PC].BSRR, 1u << (13 + 16)); /* BR13 */
    stm32_fake_gpio[PC].IDR = 1u << 13;
    assert_true(stm32_gpio_read(&pin));
    stm32_fake_gpio[PC].IDR = ~(1u << 13);
    assert_false(stm32_gpio_read(&pin));
}

/* The console (USART2, RM0090 30.6): BRR = f_PCLK / baud (oversampling
 * by 16, 12.4 fixed point, rounded), CR1 UE (bit 13) and TE (bit 3),
 * RCC APB1ENR USART2EN (bit 17); a board baud of 0 leaves it all
 * untouched. */
static void test_console_init(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_console_init(&stm32_board, 42000000u);
    assert_int_equal(stm32_fake_usart2.BRR, 365u); /* 42e6 / 115200 = 364.6 */
    assert_int_equal(stm32_fake_usart2.CR1, (1u << 13) | (1u << 3));
    assert_true((stm32_fake_rcc.APB1ENR & (1u << 17)) != 0u);

    stm32_fake_reset();
    stm32_board_t b = stm32_board;
    b.console_baud = 0u;
    stm32_console_init(&b, 42000000u);
    assert_int_equal(stm32_fake_usart2.BRR, 0u);
    assert_int_equal(stm32_fake_usart2.CR1, 0u);
    assert_int_equal(stm32_fake_rcc.APB1ENR, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_encoder_init),  cmocka_unit_test(test_encoder_range),
        cmocka_unit_test(test_drv8301_frame), cmocka_unit_test(test_iwdg_start),
        cmocka_unit_test(test_iwdg_busy),     cmocka_unit_test(test_stack_guard),
        cmocka_unit_test(test_gpio_setup),    cmocka_unit_test(test_gpio_write_read),
        cmocka_unit_test(test_console_init),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
