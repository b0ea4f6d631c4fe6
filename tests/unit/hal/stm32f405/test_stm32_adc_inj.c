/*
 * Current and bus sampling (hal/stm32f405/adc_inj.c) against RM0090
 * section 13 (ADC): the injected sequences of stm32_adc_map_for built
 * here with the JSQR layout of 13.13.12, and the registers
 * stm32_adc_inj_init leaves in the register fake checked with field
 * definitions written here (not the port's regs.h macros).
 */
#include "mc_test.h"

#include <stdbool.h>

#include "adc_inj.h"
#include "board.h"
#include "stm32_fake_regs.h"

#define FIELD(v, p, w) (((uint32_t)(v) >> (p)) & ((1u << (w)) - 1u))

/* RM0090 13.13.12 ADC_JSQR: JSQ1[4:0], JSQ2[9:5], JSQ3[14:10], JSQ4[19:15],
 * JL[21:20] = conversions - 1. A sequence of L conversions is converted
 * from JSQ(5-L) to JSQ4 (JL = 0: JSQ4 only; JL = 1: JSQ3, JSQ4; ...), its
 * results in JDR1 .. JDRL. */
#define RM_JSQ_POS(k) (5 * ((k)-1)) /* JSQk, k = 1..4 */
#define RM_JL_POS     20

/* RM0090 13.13.2 ADC_CR1: JEOCIE 7, SCAN 8 */
#define RM_CR1_JEOCIE (1u << 7)
#define RM_CR1_SCAN   (1u << 8)

/* RM0090 13.13.3 ADC_CR2: ADON 0, JEXTSEL[19:16] (0000: TIM1_CC4),
 * JEXTEN[21:20] (01: rising edge) */
#define RM_CR2_ADON        (1u << 0)
#define RM_CR2_JEXTSEL_POS 16
#define RM_CR2_JEXTEN_POS  20
#define RM_JEXTSEL_TIM1CC4 0u
#define RM_JEXTEN_RISING   1u

/* RM0090 13.13.4 / 13.13.5 ADC_SMPR1 / ADC_SMPR2: 3 bits per channel,
 * channels 10..18 in SMPR1 at 3 (ch - 10), 0..9 in SMPR2 at 3 ch;
 * 001: 15 cycles */
#define RM_SMP_15 1u

/* RM0090 13.13.17 ADC_CCR (common registers, 0x40012300 + 0x04):
 * MULTI[4:0] (10101: triple mode, injected simultaneous only),
 * ADCPRE[17:16] (01: PCLK2 / 4) */
#define RM_CCR_MULTI_TRIPLE_INJ 0x15u
#define RM_CCR_ADCPRE_POS       16
#define RM_ADCPRE_DIV4          1u

/* RM0090 8.4.1 GPIOx_MODER: 2 bits per pin, 11 analog */
#define RM_MODER_ANALOG 3u

/* RM0090 7.3.10 RCC_AHB1ENR: GPIOAEN 0, GPIOCEN 2; 7.3.14 RCC_APB2ENR:
 * ADC1EN 8, ADC2EN 9, ADC3EN 10 */
#define RM_AHB1ENR_GPIOAEN (1u << 0)
#define RM_AHB1ENR_GPIOCEN (1u << 2)
#define RM_APB2ENR_ADC1EN  (1u << 8)
#define RM_APB2ENR_ADC2EN  (1u << 9)
#define RM_APB2ENR_ADC3EN  (1u << 10)

/* RM0090 table 61: ADC1/2/3 global interrupt at position 18 */
#define RM_IRQ_ADC 18u

#define PA 0u
#define PC 2u

/* JSQR of a sequence seq[0..len-1] (RM0090 13.13.12). */
static uint32_t rm_jsqr(const uint8_t *seq, uint32_t len)
{
    uint32_t v = (len - 1u) << RM_JL_POS;
    for (uint32_t i = 0u; i < len; ++i) {
        const uint32_t k = 5u - len + i; /* JSQk, 1-based */
        v |= (uint32_t)seq[i] << RM_JSQ_POS(k);
    }
    return v;
}

/* The channel converted at rank r (0-based) of a JSQR. */
static uint32_t rm_jsqr_rank(uint32_t jsqr, uint32_t r)
{
    const uint32_t len = FIELD(jsqr, RM_JL_POS, 2) + 1u;
    return FIELD(jsqr, RM_JSQ_POS(5u - len + r), 5);
}

/* The scale factors of a board: 12-bit ADC, full scale vref. */
static void check_scales(const stm32_board_t *b, const stm32_adc_map_t *m)
{
    const double v_per_count = (double)b->adc_vref_V / 4096.0;
    const double apc = v_per_count / ((double)b->current_gain * b->shunt_ohm);
    assert_near(m->amps_per_count, apc, 1e-6 * apc);
    const double zero = (double)b->current_zero_V / v_per_count;
    assert_near(m->zero_counts, zero, 1e-6 * zero);
    const double vpc = v_per_count * b->vbus_divider;
    assert_near(m->volts_per_count, vpc, 1e-6 * vpc);
}

static void test_map_odrive(void **state)
{
    (void)state;
    const stm32_board_t *b = &stm32_board;
    stm32_adc_map_t m;
    assert_true(stm32_adc_map_for(b, &m));
    /* ADC1: [bus ch 6]; ADC2: [B ch 10]; ADC3: [C ch 11]; one each */
    const uint8_t s1[] = { 6u };
    const uint8_t s2[] = { 10u };
    const uint8_t s3[] = { 11u };
    assert_int_equal(m.jsqr[0], rm_jsqr(s1, 1u));
    assert_int_equal(m.jsqr[1], rm_jsqr(s2, 1u));
    assert_int_equal(m.jsqr[2], rm_jsqr(s3, 1u));
    /* spelled out: JL = 0, JSQ4 (bits 19:15) the channel */
    assert_int_equal(m.jsqr[0], 6u << 15);
    assert_int_equal(m.jsqr[1], 10u << 15);
    assert_int_equal(m.jsqr[2], 11u << 15);
    assert_int_equal(m.current_adc[0], 0u); /* A computed */
    assert_int_equal(m.current_adc[1], 2u);
    assert_int_equal(m.current_adc[2], 3u);
    assert_int_equal(m.current_jdr[1], 0u);
    assert_int_equal(m.current_jdr[2], 0u);
    assert_int_equal(m.vbus_jdr, 0u);
    check_scales(b, &m);
    /* the ODrive's numbers: 3.3 V / 4096 per count, 40 V/V, 0.5 mOhm, 19:1 */
    assert_near(m.amps_per_count, (3.3 / 4096.0) / (40.0 * 0.0005), 1e-7);
    assert_near(m.zero_counts, 1.65 / (3.3 / 4096.0), 1e-3);
    assert_near(m.volts_per_count, 3.3 / 4096.0 * 19.0, 1e-8);
}

/* Three shunts: A on ADC1 ch 0 (PA0), B on ADC2 ch 1 (PA1), C on ADC3 ch 2
 * (PA2), the bus on ADC1 ch 6. */
static stm32_board_t three_shunt_board(void)
{
    stm32_board_t b = stm32_board;
    b.current_channel[0] = 0u;
    b.current_channel[1] = 1u;
    b.current_channel[2] = 2u;
    b.current_adc[0] = 1u;
    b.current_adc[1] = 2u;
    b.current_adc[2] = 3u;
    b.current_pin[0] = (stm32_pin_t){ PA, 0u, 0u };
    b.current_pin[1] = (stm32_pin_t){ PA, 1u, 0u };
    b.current_pin[2] = (stm32_pin_t){ PA, 2u, 0u };
    return b;
}

static void test_map_three_shunts(void **state)
{
    (void)state;
    const stm32_board_t b = three_shunt_board();
    stm32_adc_map_t m;
    assert_true(stm32_adc_map_for(&b, &m));
    /* ADC1 [A, bus]: JL = 1, JSQ3 = 0, JSQ4 = 6 */
    const uint8_t s1[] = { 0u, 6u };
    assert_int_equal(m.jsqr[0], rm_jsqr(s1, 2u));
    assert_int_equal(m.jsqr[0], (1u << 20) | (0u << 10) | (6u << 15));
    /* ADC2 and ADC3 padded to two conversions (equal lengths in
     * simultaneous mode, RM0090 13.9.1), their current first (JDR1) */
    for (uint32_t a = 1u; a < 3u; ++a) {
        assert_int_equal(FIELD(m.jsqr[a], RM_JL_POS, 2), 1u);
        assert_int_equal(rm_jsqr_rank(m.jsqr[a], 0u), a); /* ch 1, ch 2 */
        assert_true(rm_jsqr_rank(m.jsqr[a], 1u) <= 18u);
        assert_int_equal(m.jsqr[a] & ~((3u << 20) | 0xFFFFFu), 0u);
    }
    assert_int_equal(m.current_adc[0], 1u);
    assert_int_equal(m.current_adc[1], 2u);
    assert_int_equal(m.current_adc[2], 3u);
    assert_int_equal(m.current_jdr[0], 0u);
    assert_int_equal(m.current_jdr[1], 0u);
    assert_int_equal(m.current_jdr[2], 0u);
    assert_int_equal(m.vbus_jdr, 1u);
    check_scales(&b, &m);
}

/* Every valid placement of two or three shunts on the ADCs: equal
 * lengths, the currents and the bus where the map says, and never one
 * channel on two ADCs in the same rank (RM0090 13.9.1: "Do not convert the
 * same channel on the two/three ADCs"). */
static void test_map_every_placement(void **state)
{
    (void)state;
    uint32_t valid = 0u;
    for (uint32_t measured = 3u; measured < 8u; ++measured) {
        if (measured == 4u) {
            continue; /* one current only */
        }
        for (uint32_t code = 0u; code < 27u; ++code) {
            stm32_board_t b = stm32_board;
            const uint32_t adc[3] = { code % 3u + 1u, code / 3u % 3u + 1u, code / 9u + 1u };
            for (uint32_t k = 0u; k < 3u; ++k) {
                b.current_adc[k] = (uint8_t)adc[k];
                b.current_channel[k] =
                    ((measured >> k) & 1u) ? (uint8_t)(k + 1u) : STM32_NO_ADC_CHANNEL;
            }
            bool distinct = true; /* no two measured phases on one ADC */
            for (uint32_t j = 0u; j < 3u; ++j) {
                for (uint32_t k = j + 1u; k < 3u; ++k) {
                    if (((measured >> j) & 1u) && ((measured >> k) & 1u) && adc[j] == adc[k]) {
                        distinct = false;
                    }
                }
            }
            stm32_adc_map_t m;
            const bool ok = stm32_adc_map_for(&b, &m);
            assert_int_equal(ok, distinct);
            if (!ok) {
                continue;
            }
            valid++;
            const uint32_t len = FIELD(m.jsqr[0], RM_JL_POS, 2) + 1u;
            for (uint32_t a = 1u; a < 3u; ++a) {
                assert_int_equal(FIELD(m.jsqr[a], RM_JL_POS, 2) + 1u, len);
            }
            for (uint32_t k = 0u; k < 3u; ++k) {
                if ((measured >> k) & 1u) {
                    assert_int_equal(m.current_adc[k], adc[k]);
                    assert_int_equal(rm_jsqr_rank(m.jsqr[adc[k] - 1u], m.current_jdr[k]), k + 1u);
                } else {
                    assert_int_equal(m.current_adc[k], 0u);
                }
            }
            assert_int_equal(rm_jsqr_rank(m.jsqr[0], m.vbus_jdr), 6u);
            for (uint32_t r = 0u; r < len; ++r) {
                const uint32_t c1 = rm_jsqr_rank(m.jsqr[0], r);
                const uint32_t c2 = rm_jsqr_rank(m.jsqr[1], r);
                const uint32_t c3 = rm_jsqr_rank(m.jsqr[2], r);
                assert_true(c1 != c2 && c1 != c3 && c2 != c3);
            }
        }
    }
    /* 3 two-shunt choices x 6 placements x 3 (the unmeasured phase's ADC,
     * ignored) + 6 three-shunt placements */
    assert_int_equal(valid, 3u * 6u * 3u + 6u);
}

static void test_map_rejections(void **state)
{
    (void)state;
    stm32_adc_map_t m;
    stm32_board_t b;

    b = stm32_board; /* B and C on ADC2 */
    b.current_adc[2] = 2u;
    assert_false(stm32_adc_map_for(&b, &m));

    b = three_shunt_board(); /* A and C on ADC1 */
    b.current_adc[2] = 1u;
    assert_false(stm32_adc_map_for(&b, &m));

    b = stm32_board;
    b.current_adc[1] = 0u;
    assert_false(stm32_adc_map_for(&b, &m));
    b = stm32_board;
    b.current_adc[2] = 4u;
    assert_false(stm32_adc_map_for(&b, &m));

    b = stm32_board; /* one current only */
    b.current_channel[2] = STM32_NO_ADC_CHANNEL;
    assert_false(stm32_adc_map_for(&b, &m));
    b.current_channel[1] = STM32_NO_ADC_CHANNEL;
    assert_false(stm32_adc_map_for(&b, &m));

    b = stm32_board; /* channels 0..18 only */
    b.current_channel[1] = 19u;
    assert_false(stm32_adc_map_for(&b, &m));
    b = stm32_board;
    b.vbus_channel = 19u;
    assert_false(stm32_adc_map_for(&b, &m));
    b = stm32_board;
    b.current_channel[2] = 18u;
    assert_true(stm32_adc_map_for(&b, &m));

    /* the scale factors' divisors: gain x shunt and the reference > 0 */
    b = stm32_board;
    b.current_gain = 0.0f;
    assert_false(stm32_adc_map_for(&b, &m));
    b = stm32_board;
    b.shunt_ohm = -0.0005f;
    assert_false(stm32_adc_map_for(&b, &m));
    b = stm32_board;
    b.shunt_ohm = NAN;
    assert_false(stm32_adc_map_for(&b, &m));
    b = stm32_board;
    b.adc_vref_V = 0.0f;
    assert_false(stm32_adc_map_for(&b, &m));
}

/* SMPR1/SMPR2 with 15 cycles for exactly the channels listed. */
static void expected_smpr(const uint8_t *ch, uint32_t n, uint32_t *smpr1, uint32_t *smpr2)
{
    *smpr1 = 0u;
    *smpr2 = 0u;
    for (uint32_t i = 0u; i < n; ++i) {
        if (ch[i] < 10u) {
            *smpr2 |= RM_SMP_15 << (3u * ch[i]);
        } else {
            *smpr1 |= RM_SMP_15 << (3u * (ch[i] - 10u));
        }
    }
}

/* What is common to every board: the common register, CR1, CR2, the
 * JSQRs, the clocks and the interrupt. */
static void check_init_common(const stm32_adc_map_t *m)
{
    const uint32_t ccr = stm32_fake_adc_common.CCR;
    assert_int_equal(FIELD(ccr, 0, 5), 0x15u);
    assert_int_equal(FIELD(ccr, RM_CCR_ADCPRE_POS, 2), RM_ADCPRE_DIV4);
    assert_int_equal(ccr, RM_CCR_MULTI_TRIPLE_INJ | (RM_ADCPRE_DIV4 << RM_CCR_ADCPRE_POS));

    /* ADC1, the master: TIM1_CC4 rising edge */
    const uint32_t cr2 = stm32_fake_adc[0].CR2;
    assert_int_equal(FIELD(cr2, RM_CR2_JEXTSEL_POS, 4), RM_JEXTSEL_TIM1CC4);
    assert_int_equal(FIELD(cr2, RM_CR2_JEXTEN_POS, 2), RM_JEXTEN_RISING);
    assert_int_equal(cr2, RM_CR2_ADON | (RM_JEXTSEL_TIM1CC4 << RM_CR2_JEXTSEL_POS) |
                              (RM_JEXTEN_RISING << RM_CR2_JEXTEN_POS));
    /* ADC2, ADC3: slaves, no trigger of their own */
    assert_int_equal(stm32_fake_adc[1].CR2, RM_CR2_ADON);
    assert_int_equal(stm32_fake_adc[2].CR2, RM_CR2_ADON);

    assert_int_equal(stm32_fake_adc[0].CR1, RM_CR1_SCAN | RM_CR1_JEOCIE);
    assert_int_equal(stm32_fake_adc[1].CR1, RM_CR1_SCAN);
    assert_int_equal(stm32_fake_adc[2].CR1, RM_CR1_SCAN);

    for (uint32_t a = 0u; a < 3u; ++a) {
        assert_int_equal(stm32_fake_adc[a].JSQR, m->jsqr[a]);
    }

    assert_int_equal(stm32_fake_rcc.APB2ENR,
                     RM_APB2ENR_ADC1EN | RM_APB2ENR_ADC2EN | RM_APB2ENR_ADC3EN);
    /* the priority set, the interrupt not yet enabled (the image enables
     * it once the drive is initialised: stm32_adc_irq_enable) */
    assert_int_equal(stm32_fake_nvic.ISER[0], 0u);
    assert_int_equal(stm32_fake_nvic.IPR[RM_IRQ_ADC], 0u);
}

static void test_init_odrive(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_fake_nvic.IPR[RM_IRQ_ADC] = 0xF0u; /* must come out as 0 */
    stm32_fake_nvic.IPR[RM_IRQ_ADC + 1u] = 0x50u;
    stm32_adc_map_t m;
    assert_true(stm32_adc_map_for(&stm32_board, &m));
    stm32_adc_inj_init(&stm32_board, &m);
    check_init_common(&m);
    assert_int_equal(stm32_fake_nvic.IPR[RM_IRQ_ADC + 1u], 0x50u);

    const uint8_t c1[] = { 6u };
    const uint8_t c2[] = { 10u };
    const uint8_t c3[] = { 11u };
    uint32_t s1, s2;
    expected_smpr(c1, 1u, &s1, &s2);
    assert_int_equal(stm32_fake_adc[0].SMPR1, s1);
    assert_int_equal(stm32_fake_adc[0].SMPR2, s2);
    assert_int_equal(stm32_fake_adc[0].SMPR2, 1u << 18); /* SMP6[20:18] */
    expected_smpr(c2, 1u, &s1, &s2);
    assert_int_equal(stm32_fake_adc[1].SMPR1, s1);
    assert_int_equal(stm32_fake_adc[1].SMPR2, s2);
    assert_int_equal(stm32_fake_adc[1].SMPR1, 1u << 0); /* SMP10[2:0] */
    expected_smpr(c3, 1u, &s1, &s2);
    assert_int_equal(stm32_fake_adc[2].SMPR1, s1);
    assert_int_equal(stm32_fake_adc[2].SMPR2, s2);
    assert_int_equal(stm32_fake_adc[2].SMPR1, 1u << 3); /* SMP11[5:3] */

    /* PC0, PC1, PA6 analog; nothing else */
    assert_int_equal(stm32_fake_gpio[PC].MODER,
                     (RM_MODER_ANALOG << (2 * 0)) | (RM_MODER_ANALOG << (2 * 1)));
    assert_int_equal(stm32_fake_gpio[PA].MODER, RM_MODER_ANALOG << (2 * 6));
    assert_int_equal(stm32_fake_gpio[PC].PUPDR, 0u);
    assert_int_equal(stm32_fake_gpio[PA].PUPDR, 0u);
    assert_int_equal(stm32_fake_rcc.AHB1ENR, RM_AHB1ENR_GPIOAEN | RM_AHB1ENR_GPIOCEN);
}

static void test_init_three_shunts(void **state)
{
    (void)state;
    stm32_fake_reset();
    const stm32_board_t b = three_shunt_board();
    stm32_adc_map_t m;
    assert_true(stm32_adc_map_for(&b, &m));
    stm32_adc_inj_init(&b, &m);
    check_init_common(&m);
    for (uint32_t a = 0u; a < 3u; ++a) {
        uint8_t ch[4];
        const uint32_t len = FIELD(m.jsqr[a], RM_JL_POS, 2) + 1u;
        for (uint32_t r = 0u; r < len; ++r) {
            ch[r] = (uint8_t)rm_jsqr_rank(m.jsqr[a], r);
        }
        uint32_t s1, s2;
        expected_smpr(ch, len, &s1, &s2);
        assert_int_equal(stm32_fake_adc[a].SMPR1, s1);
        assert_int_equal(stm32_fake_adc[a].SMPR2, s2);
    }
    /* ADC1: channels 0 and 6, SMP0[2:0] and SMP6[20:18] */
    assert_int_equal(stm32_fake_adc[0].SMPR2, (1u << 0) | (1u << 18));
    assert_int_equal(stm32_fake_adc[0].SMPR1, 0u);
    /* PA0, PA1, PA2, PA6 analog */
    assert_int_equal(stm32_fake_gpio[PA].MODER, (RM_MODER_ANALOG << 0) | (RM_MODER_ANALOG << 2) |
                                                    (RM_MODER_ANALOG << 4) |
                                                    (RM_MODER_ANALOG << 12));
    assert_int_equal(stm32_fake_rcc.AHB1ENR, RM_AHB1ENR_GPIOAEN);
}

/* The fast ISR on and off: the NVIC's set-enable and clear-enable
 * registers (ARMv7-M B3.4: ISER/ICER word n, bit m for interrupt 32 n + m;
 * writing 0 bits has no effect, so only the ADC's bit is written). */
static void test_irq_enable(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_adc_irq_enable(true);
    assert_int_equal(stm32_fake_nvic.ISER[RM_IRQ_ADC / 32u], 1u << (RM_IRQ_ADC % 32u));
    assert_int_equal(stm32_fake_nvic.ICER[RM_IRQ_ADC / 32u], 0u);
    stm32_fake_reset();
    stm32_adc_irq_enable(false);
    assert_int_equal(stm32_fake_nvic.ICER[RM_IRQ_ADC / 32u], 1u << (RM_IRQ_ADC % 32u));
    assert_int_equal(stm32_fake_nvic.ISER[RM_IRQ_ADC / 32u], 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_map_odrive),          cmocka_unit_test(test_map_three_shunts),
        cmocka_unit_test(test_map_every_placement), cmocka_unit_test(test_map_rejections),
        cmocka_unit_test(test_init_odrive),         cmocka_unit_test(test_init_three_shunts),
        cmocka_unit_test(test_irq_enable),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
