/*
 * CAN1 (hal/stm32f405/bxcan.c) against RM0090 section 32 (bxCAN): the bit
 * timing checked against every valid timing enumerated here with the
 * formula of 32.7.7, and the mailbox, filter and control registers in the
 * register fake checked with field definitions written here (not the
 * port's regs.h macros).
 *
 * The fake cannot acknowledge a mode change (MSR.INAK follows MCR.INRQ on
 * the chip): stm32_can_init is exercised up to the point where it waits
 * for the controller, and its HAL_ERR_HW for a controller that does not
 * answer is what the test sees.
 */
#include "mc_test.h"

#include <stdbool.h>
#include <string.h>

#include "bxcan.h"
#include "stm32_fake_regs.h"

#define FIELD(v, p, w) (((uint32_t)(v) >> (p)) & ((1u << (w)) - 1u))

/* RM0090 32.9.2 CAN_MCR: INRQ 0, SLEEP 1, TXFP 2, ABOM 6; CAN_MSR: INAK 0 */
#define RM_MCR_INRQ  (1u << 0)
#define RM_MCR_SLEEP (1u << 1)
#define RM_MCR_TXFP  (1u << 2)
#define RM_MCR_ABOM  (1u << 6)
#define RM_MSR_INAK  (1u << 0)

/* RM0090 32.9.2 CAN_TSR: CODE[25:24] (the next empty mailbox), TME0..2 at
 * 26..28 */
#define RM_TSR_CODE_POS 24
#define RM_TSR_TME(k)   (1u << (26 + (k)))

/* RM0090 32.9.2 CAN_RF0R: FMP0[1:0], FOVR0 4, RFOM0 5 */
#define RM_RF0R_FOVR0 (1u << 4)
#define RM_RF0R_RFOM0 (1u << 5)

/* RM0090 32.9.2 CAN_ESR: LEC[6:4] (0 none, 1..6 an error, 7 set by
 * software) */
#define RM_ESR_LEC_POS 4

/* RM0090 32.9.2 CAN_BTR: BRP[9:0] (t_q = (BRP + 1) t_PCLK), TS1[19:16]
 * (t_BS1 = (TS1 + 1) t_q), TS2[22:20] (t_BS2 = (TS2 + 1) t_q), SJW[25:24],
 * LBKM 30, SILM 31 */
#define RM_BTR_BRP_W   10
#define RM_BTR_TS1_POS 16
#define RM_BTR_TS2_POS 20
#define RM_BTR_SJW_POS 24
#define RM_BTR_LBKM    (1u << 30)
#define RM_BTR_SILM    (1u << 31)

/* RM0090 32.9.3 CAN_TIxR / CAN_RIxR: TXRQ 0 (TIxR only), RTR 1, IDE 2,
 * EXID[17:0] at 20:3, STID[10:0] / EXID[28:18] at 31:21 */
#define RM_IR_TXRQ     (1u << 0)
#define RM_IR_RTR      (1u << 1)
#define RM_IR_IDE      (1u << 2)
#define RM_IR_EXID_POS 3
#define RM_IR_STID_POS 21

/* RM0090 32.9.4 CAN_FMR: FINIT 0 */
#define RM_FMR_FINIT (1u << 0)

/* RM0090 7.3.13 RCC_APB1ENR: CAN1EN 25 */
#define RM_APB1ENR_CAN1EN (1u << 25)

/* RM0090 8.4.1 / 8.4.10 GPIO MODER (10: alternate function), AFRH (4 bits
 * per pin 8..15, AF9: CAN1 on PB8/PB9 per the STM32F405 datasheet) */
#define RM_MODER_AF 2u
#define RM_AF_CAN1  9u
#define PB          1u

#define PCLK1 42000000u

/* ---- bit timing ------------------------------------------------------ */

/* RM0090 32.7.7: NominalBitTime = t_q (1 + t_BS1 + t_BS2) with t_q = brp
 * t_PCLK (brp the divider, BRP + 1). The sample point is after SYNC_SEG and
 * BS1: (1 + tseg1) / quanta. The best |sample point - 87.5 %| over every
 * valid exact timing (8..25 quanta, tseg1 1..16, tseg2 1..8, brp 1..1024);
 * negative if there is none. */
static double best_sample_point_error(uint32_t pclk, uint32_t bitrate)
{
    double best = -1.0;
    for (uint32_t brp = 1u; brp <= 1024u; ++brp) {
        for (uint32_t t1 = 1u; t1 <= 16u; ++t1) {
            for (uint32_t t2 = 1u; t2 <= 8u; ++t2) {
                const uint32_t q = 1u + t1 + t2;
                if (q < 8u || q > 25u || (uint64_t)brp * q * bitrate != pclk) {
                    continue;
                }
                const double err = fabs((1.0 + t1) / q - 0.875);
                if (best < 0.0 || err < best) {
                    best = err;
                }
            }
        }
    }
    return best;
}

static void check_timing(uint32_t pclk, uint32_t bitrate)
{
    stm32_can_timing_t t;
    assert_true(stm32_can_timing_for(pclk, bitrate, &t));
    const uint32_t q = 1u + t.tseg1 + t.tseg2;
    assert_true(t.brp >= 1u && t.brp <= 1024u);
    assert_true(t.tseg1 >= 1u && t.tseg1 <= 16u);
    assert_true(t.tseg2 >= 1u && t.tseg2 <= 8u);
    assert_true(t.sjw >= 1u && t.sjw <= 4u && t.sjw <= t.tseg2);
    assert_true(q >= 8u && q <= 25u);
    /* exact bit rate: pclk / (brp quanta) */
    assert_int_equal((uint64_t)t.brp * q * bitrate, pclk);
    const double best = best_sample_point_error(pclk, bitrate);
    assert_true(best >= 0.0);
    assert_near(fabs((1.0 + t.tseg1) / q - 0.875), best, 1e-12);
}

static void test_timing_42mhz(void **state)
{
    (void)state;
    check_timing(PCLK1, 1000000u);
    check_timing(PCLK1, 500000u);
    check_timing(PCLK1, 250000u);
    check_timing(PCLK1, 125000u);
    /* 250 kbit/s: 8 quanta of 21 clocks give 87.5 % exactly */
    stm32_can_timing_t t;
    assert_true(stm32_can_timing_for(PCLK1, 250000u, &t));
    assert_near((1.0 + t.tseg1) / (1.0 + t.tseg1 + t.tseg2), 0.875, 1e-12);
}

static void test_timing_none(void **state)
{
    (void)state;
    stm32_can_timing_t t;
    /* 900 kbit/s: 42e6 / 900e3 = 46.67 clocks per bit, no exact timing */
    assert_true(best_sample_point_error(PCLK1, 900000u) < 0.0);
    assert_false(stm32_can_timing_for(PCLK1, 900000u, &t));
    assert_false(stm32_can_timing_for(PCLK1, 0u, &t));
    /* 42e6 / 5e6 = 8.4: none */
    assert_true(best_sample_point_error(PCLK1, 5000000u) < 0.0);
    assert_false(stm32_can_timing_for(PCLK1, 5000000u, &t));
}

/* Every bit rate of whole kbit/s from 10 kbit/s to 1 Mbit/s: found exactly
 * when an exact timing exists, and then the best one. */
static void test_timing_sweep(void **state)
{
    (void)state;
    for (uint32_t kbps = 10u; kbps <= 1000u; ++kbps) {
        const uint32_t rate = 1000u * kbps;
        stm32_can_timing_t t;
        const bool any = best_sample_point_error(PCLK1, rate) >= 0.0;
        assert_int_equal(stm32_can_timing_for(PCLK1, rate, &t), any);
        if (any) {
            check_timing(PCLK1, rate);
        }
    }
}

/* ---- transmit -------------------------------------------------------- */

static bool mailbox_zero(const stm32_can_mailbox_t *m)
{
    return m->IR == 0u && m->DTR == 0u && m->DLR == 0u && m->DHR == 0u;
}

/* All three mailboxes empty, CODE = code. */
static void tx_ready(uint32_t code)
{
    stm32_fake_reset();
    stm32_fake_can1.TSR = RM_TSR_TME(0) | RM_TSR_TME(1) | RM_TSR_TME(2) | (code << RM_TSR_CODE_POS);
}

static void test_send_standard(void **state)
{
    (void)state;
    tx_ready(1u);
    const hal_can_frame_t f = {
        .id = 0x123u, .extended = false, .rtr = false, .dlc = 3u, .data = { 0x11u, 0x22u, 0x33u }
    };
    assert_int_equal(stm32_can_send(&f), HAL_OK);
    const stm32_can_mailbox_t *m = &stm32_fake_can1.TX[1];
    /* mailbox 1 at 0x190 (RM0090 32.9.5 register map) */
    assert_int_equal((uintptr_t)m - (uintptr_t)&stm32_fake_can1, 0x190u);
    assert_int_equal(FIELD(m->IR, RM_IR_STID_POS, 11), 0x123u);
    assert_int_equal(m->IR & RM_IR_IDE, 0u);
    assert_int_equal(m->IR & RM_IR_RTR, 0u);
    assert_true((m->IR & RM_IR_TXRQ) != 0u);
    assert_int_equal(m->IR, (0x123u << RM_IR_STID_POS) | RM_IR_TXRQ);
    assert_int_equal(FIELD(m->DTR, 0, 4), 3u);
    assert_int_equal(m->DTR, 3u);
    assert_int_equal(m->DLR, 0x00332211u); /* DATA0 in bits 7:0 */
    assert_int_equal(m->DHR, 0u);
    assert_true(mailbox_zero(&stm32_fake_can1.TX[0]));
    assert_true(mailbox_zero(&stm32_fake_can1.TX[2]));
}

static void test_send_extended(void **state)
{
    (void)state;
    tx_ready(2u);
    const hal_can_frame_t f = { .id = 0x1ABCDEF0u,
                                .extended = true,
                                .rtr = false,
                                .dlc = 8u,
                                .data = { 1u, 2u, 3u, 4u, 5u, 6u, 7u, 8u } };
    assert_int_equal(stm32_can_send(&f), HAL_OK);
    const stm32_can_mailbox_t *m = &stm32_fake_can1.TX[2];
    /* ID[28:18] in STID/EXID[28:18] (31:21), ID[17:0] in EXID (20:3) */
    assert_int_equal(FIELD(m->IR, RM_IR_STID_POS, 11), 0x1ABCDEF0u >> 18);
    assert_int_equal(FIELD(m->IR, RM_IR_EXID_POS, 18), 0x1ABCDEF0u & 0x3FFFFu);
    assert_true((m->IR & RM_IR_IDE) != 0u);
    assert_int_equal(m->IR & RM_IR_RTR, 0u);
    assert_true((m->IR & RM_IR_TXRQ) != 0u);
    assert_int_equal(m->DTR, 8u);
    assert_int_equal(m->DLR, 0x04030201u);
    assert_int_equal(m->DHR, 0x08070605u);
    assert_true(mailbox_zero(&stm32_fake_can1.TX[0]));
    assert_true(mailbox_zero(&stm32_fake_can1.TX[1]));
}

static void test_send_rtr(void **state)
{
    (void)state;
    tx_ready(0u);
    const hal_can_frame_t f = { .id = 0x7FFu, .extended = false, .rtr = true, .dlc = 2u };
    assert_int_equal(stm32_can_send(&f), HAL_OK);
    const stm32_can_mailbox_t *m = &stm32_fake_can1.TX[0];
    assert_int_equal(m->IR, (0x7FFu << RM_IR_STID_POS) | RM_IR_RTR | RM_IR_TXRQ);
    assert_int_equal(m->DTR, 2u);
}

static bool can_untouched_but_tsr(uint32_t tsr)
{
    stm32_can_t copy;
    memcpy(&copy, (const void *)&stm32_fake_can1, sizeof copy);
    if (copy.TSR != tsr) {
        return false;
    }
    copy.TSR = 0u;
    const unsigned char *b = (const unsigned char *)&copy;
    for (size_t k = 0; k < sizeof copy; ++k) {
        if (b[k] != 0u) {
            return false;
        }
    }
    return true;
}

static void test_send_busy(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_fake_can1.TSR = 1u << RM_TSR_CODE_POS; /* no TMEx */
    const hal_can_frame_t f = { .id = 0x10u, .dlc = 1u, .data = { 0xAAu } };
    assert_int_equal(stm32_can_send(&f), HAL_ERR_BUSY);
    assert_true(can_untouched_but_tsr(1u << RM_TSR_CODE_POS));
}

static void test_send_invalid(void **state)
{
    (void)state;
    const hal_can_frame_t bad[] = {
        { .id = 0x123u, .dlc = 9u },
        { .id = 0x800u, .dlc = 1u },
        { .id = 0x20000000u, .extended = true, .dlc = 1u },
    };
    const uint32_t tsr = RM_TSR_TME(0) | RM_TSR_TME(1) | RM_TSR_TME(2);
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        tx_ready(0u);
        assert_int_equal(stm32_can_send(&bad[k]), HAL_ERR_PARAM);
        assert_true(can_untouched_but_tsr(tsr));
    }
}

/* ---- receive --------------------------------------------------------- */

static void test_receive_empty(void **state)
{
    (void)state;
    stm32_fake_reset();
    hal_can_frame_t f;
    assert_int_equal(stm32_can_receive(&f), HAL_ERR_EMPTY);
    assert_int_equal(stm32_fake_can1.RF0R, 0u);
}

static void test_receive_standard(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_can_mailbox_t *m = &stm32_fake_can1.RX[0];
    assert_int_equal((uintptr_t)m - (uintptr_t)&stm32_fake_can1, 0x1B0u);
    stm32_fake_can1.RF0R = 1u; /* FMP0 = 1 */
    m->IR = 0x2A5u << RM_IR_STID_POS;
    m->DTR = 5u | (0x12u << 8) | (0xBEEFu << 16); /* DLC, FMI, TIME */
    m->DLR = 0x44332211u;
    m->DHR = 0x88776655u;
    hal_can_frame_t f;
    memset(&f, 0xFF, sizeof f);
    assert_int_equal(stm32_can_receive(&f), HAL_OK);
    assert_int_equal(f.id, 0x2A5u);
    assert_false(f.extended);
    assert_false(f.rtr);
    assert_int_equal(f.dlc, 5u);
    const uint8_t want[8] = { 0x11u, 0x22u, 0x33u, 0x44u, 0x55u, 0x66u, 0x77u, 0x88u };
    assert_memory_equal(f.data, want, 8);
    assert_int_equal(stm32_fake_can1.RF0R, RM_RF0R_RFOM0); /* released */
}

static void test_receive_extended_rtr(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_can_mailbox_t *m = &stm32_fake_can1.RX[0];
    stm32_fake_can1.RF0R = 3u; /* FMP0 = 3 */
    m->IR = ((0x1ABCDEF0u >> 18) << RM_IR_STID_POS) | ((0x1ABCDEF0u & 0x3FFFFu) << RM_IR_EXID_POS) |
            RM_IR_IDE | RM_IR_RTR;
    m->DTR = 0u;
    hal_can_frame_t f;
    assert_int_equal(stm32_can_receive(&f), HAL_OK);
    assert_int_equal(f.id, 0x1ABCDEF0u);
    assert_true(f.extended);
    assert_true(f.rtr);
    assert_int_equal(f.dlc, 0u);
    assert_int_equal(stm32_fake_can1.RF0R, RM_RF0R_RFOM0);

    /* a DLC of 9..15 is 8 data bytes in classic CAN */
    stm32_fake_can1.RF0R = 1u;
    m->IR = 0x001u << RM_IR_STID_POS;
    m->DTR = 12u;
    assert_int_equal(stm32_can_receive(&f), HAL_OK);
    assert_int_equal(f.id, 1u);
    assert_false(f.extended);
    assert_int_equal(f.dlc, 8u);
}

static void test_receive_overrun(void **state)
{
    (void)state;
    stm32_fake_reset();
    hal_can_stats_t s0, s1;
    stm32_can_stats(&s0);
    stm32_fake_can1.RF0R = RM_RF0R_FOVR0; /* an overrun, no frame */
    hal_can_frame_t f;
    assert_int_equal(stm32_can_receive(&f), HAL_ERR_EMPTY);
    stm32_can_stats(&s1);
    assert_int_equal(s1.rx_overruns, s0.rx_overruns + 1u);
    assert_int_equal(s1.bus_errors, s0.bus_errors);
    /* FOVR0 is cleared by writing 1 (rc_w1) */
    assert_int_equal(stm32_fake_can1.RF0R, RM_RF0R_FOVR0);

    /* an overrun with a frame: counted and the frame taken */
    stm32_fake_can1.RF0R = RM_RF0R_FOVR0 | 3u;
    stm32_fake_can1.RX[0].IR = 0x55u << RM_IR_STID_POS;
    stm32_fake_can1.RX[0].DTR = 1u;
    assert_int_equal(stm32_can_receive(&f), HAL_OK);
    assert_int_equal(f.id, 0x55u);
    stm32_can_stats(&s1);
    assert_int_equal(s1.rx_overruns, s0.rx_overruns + 2u);
    assert_int_equal(stm32_fake_can1.RF0R, RM_RF0R_RFOM0);
}

static void test_bus_errors(void **state)
{
    (void)state;
    stm32_fake_reset();
    hal_can_stats_t s0, s;
    stm32_can_stats(&s0);
    uint32_t want = s0.bus_errors;
    for (uint32_t lec = 0u; lec <= 7u; ++lec) {
        /* TEC/REC (bits 31:16) and the state flags beside LEC */
        stm32_fake_can1.ESR = (lec << RM_ESR_LEC_POS) | (5u << 16) | 1u;
        stm32_can_stats(&s);
        if (lec >= 1u && lec <= 6u) {
            want++;
            assert_int_equal(FIELD(stm32_fake_can1.ESR, RM_ESR_LEC_POS, 3), 7u);
        } else {
            assert_int_equal(FIELD(stm32_fake_can1.ESR, RM_ESR_LEC_POS, 3), lec);
        }
        assert_int_equal(s.bus_errors, want);
        /* counted once: LEC is 7 now */
        stm32_can_stats(&s);
        assert_int_equal(s.bus_errors, want);
    }
    /* the receive path polls it too */
    stm32_fake_can1.ESR = 2u << RM_ESR_LEC_POS;
    hal_can_frame_t f;
    assert_int_equal(stm32_can_receive(&f), HAL_ERR_EMPTY);
    stm32_can_stats(&s);
    assert_int_equal(s.bus_errors, want + 1u);
    assert_int_equal(s.rx_overruns, s0.rx_overruns);
}

/* ---- initialisation -------------------------------------------------- */

static void test_init_no_ack(void **state)
{
    (void)state;
    stm32_fake_reset(); /* MSR = 0: INAK never set */
    assert_int_equal(stm32_can_init(&stm32_board, PCLK1, 1000000u), HAL_ERR_HW);
    assert_int_equal(stm32_fake_can1.BTR, 0u);
    assert_int_equal(stm32_fake_can1.MCR, RM_MCR_INRQ); /* asked, SLEEP cleared */
    assert_int_equal(stm32_fake_can1.FA1R, 0u);
}

static void test_init_bad_rate(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_fake_can1.MSR = RM_MSR_INAK;
    assert_int_equal(stm32_can_init(&stm32_board, PCLK1, 900000u), HAL_ERR_PARAM);
    assert_int_equal(stm32_fake_can1.MCR, 0u);
    assert_int_equal(stm32_fake_can1.BTR, 0u);
    assert_int_equal(stm32_fake_rcc.APB1ENR, 0u);
}

static void test_init_registers(void **state)
{
    (void)state;
    stm32_fake_reset();
    stm32_fake_can1.MSR = RM_MSR_INAK; /* in initialisation, and stays there */
    /* the bank-0 bits the driver must clear, and bank 1's it must keep */
    stm32_fake_can1.FM1R = 1u | 2u;
    stm32_fake_can1.FFA1R = 1u | 2u;
    stm32_fake_can1.FA1R = 2u;
    stm32_fake_can1.FR[0][0] = 0xFFFFFFFFu;
    stm32_fake_can1.FR[0][1] = 0xFFFFFFFFu;
    /* INAK never clears, so leaving initialisation times out */
    assert_int_equal(stm32_can_init(&stm32_board, PCLK1, 1000000u), HAL_ERR_HW);

    stm32_can_timing_t t;
    assert_true(stm32_can_timing_for(PCLK1, 1000000u, &t));
    check_timing(PCLK1, 1000000u);
    const uint32_t btr = stm32_fake_can1.BTR;
    assert_int_equal(FIELD(btr, 0, RM_BTR_BRP_W), t.brp - 1u);
    assert_int_equal(FIELD(btr, RM_BTR_TS1_POS, 4), t.tseg1 - 1u);
    assert_int_equal(FIELD(btr, RM_BTR_TS2_POS, 3), t.tseg2 - 1u);
    assert_int_equal(FIELD(btr, RM_BTR_SJW_POS, 2), 0u);
    assert_int_equal(btr & (RM_BTR_LBKM | RM_BTR_SILM), 0u);
    assert_int_equal(btr, (t.brp - 1u) | ((t.tseg1 - 1u) << RM_BTR_TS1_POS) |
                              ((t.tseg2 - 1u) << RM_BTR_TS2_POS));
    /* the bit rate the register gives, by RM0090 32.7.7 */
    const uint32_t quanta =
        1u + (FIELD(btr, RM_BTR_TS1_POS, 4) + 1u) + (FIELD(btr, RM_BTR_TS2_POS, 3) + 1u);
    assert_int_equal(PCLK1 / ((FIELD(btr, 0, RM_BTR_BRP_W) + 1u) * quanta), 1000000u);
    assert_int_equal(PCLK1 % ((FIELD(btr, 0, RM_BTR_BRP_W) + 1u) * quanta), 0u);

    /* filter bank 0: 32-bit, mask mode, FIFO 0, active, mask 0 */
    assert_int_equal(stm32_fake_can1.FS1R & 1u, 1u);
    assert_int_equal(stm32_fake_can1.FM1R, 2u);
    assert_int_equal(stm32_fake_can1.FFA1R, 2u);
    assert_int_equal(stm32_fake_can1.FA1R, 1u | 2u);
    assert_int_equal(stm32_fake_can1.FR[0][0], 0u);
    assert_int_equal(stm32_fake_can1.FR[0][1], 0u);
    assert_int_equal(stm32_fake_can1.FMR & RM_FMR_FINIT, 0u);

    /* normal mode asked for: INRQ and SLEEP clear, ABOM and TXFP */
    assert_int_equal(stm32_fake_can1.MCR, RM_MCR_ABOM | RM_MCR_TXFP);
    assert_int_equal(stm32_fake_can1.MCR & (RM_MCR_INRQ | RM_MCR_SLEEP), 0u);

    assert_true((stm32_fake_rcc.APB1ENR & RM_APB1ENR_CAN1EN) != 0u);
    assert_true((stm32_fake_rcc.AHB1ENR & (1u << PB)) != 0u);
    /* PB8 (RX), PB9 (TX): AF9 in AFRH (pin 8 bits 3:0, pin 9 bits 7:4),
     * MODER 10 (pin 8 bits 17:16, pin 9 bits 19:18) */
    const stm32_gpio_t *g = &stm32_fake_gpio[PB];
    assert_int_equal(FIELD(g->AFR[1], 0, 4), RM_AF_CAN1);
    assert_int_equal(FIELD(g->AFR[1], 4, 4), RM_AF_CAN1);
    assert_int_equal(g->AFR[1], RM_AF_CAN1 | (RM_AF_CAN1 << 4));
    assert_int_equal(g->AFR[0], 0u);
    assert_int_equal(FIELD(g->MODER, 16, 2), RM_MODER_AF);
    assert_int_equal(FIELD(g->MODER, 18, 2), RM_MODER_AF);
    assert_int_equal(g->MODER, (RM_MODER_AF << 16) | (RM_MODER_AF << 18));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_timing_42mhz),
        cmocka_unit_test(test_timing_none),
        cmocka_unit_test(test_timing_sweep),
        cmocka_unit_test(test_send_standard),
        cmocka_unit_test(test_send_extended),
        cmocka_unit_test(test_send_rtr),
        cmocka_unit_test(test_send_busy),
        cmocka_unit_test(test_send_invalid),
        cmocka_unit_test(test_receive_empty),
        cmocka_unit_test(test_receive_standard),
        cmocka_unit_test(test_receive_extended_rtr),
        cmocka_unit_test(test_receive_overrun),
        cmocka_unit_test(test_bus_errors),
        cmocka_unit_test(test_init_no_ack),
        cmocka_unit_test(test_init_bad_rate),
        cmocka_unit_test(test_init_registers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
