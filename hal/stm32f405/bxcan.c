/* CAN1 (bxcan.h). */
#include "bxcan.h"

#include "gpio_cfg.h"
#include "regs.h"

/* Mode-change waits: leaving initialisation needs 11 recessive bits on
 * the bus (11 us at 1 Mbit/s); the loop allows milliseconds. */
#define CAN_WAIT_LOOPS 100000u

static uint32_t rx_overruns;
static uint32_t bus_errors;

/* ESR.LEC (bits 6:4), the last error code: 0 none, 1..6 an error, 7 set by
 * software (RM0090 32.9.2), so a new error is a value in 1..6. Polled with
 * every receive and statistics call: at most one error counted per poll
 * (the controller keeps no count). */
static void poll_errors(void)
{
    const uint32_t lec = (STM32_CAN1->ESR >> CAN_ESR_LEC_POS) & 7u;
    if (lec != 0u && lec != 7u) {
        bus_errors++;
        STM32_CAN1->ESR = 7u << CAN_ESR_LEC_POS;
    }
}

bool stm32_can_timing_for(uint32_t pclk1_hz, uint32_t bitrate_bps,
                          stm32_can_timing_t *t)
{
    if (bitrate_bps == 0u) {
        return false;
    }
    bool found = false;
    uint32_t best_err = UINT32_MAX; /* |sample point - 87.5 %| in 0.1 % */
    for (uint32_t quanta = 25u; quanta >= 8u; --quanta) {
        const uint64_t per_brp = (uint64_t)bitrate_bps * quanta;
        if (pclk1_hz % per_brp != 0u) {
            continue;
        }
        const uint64_t brp = pclk1_hz / per_brp;
        if (brp < 1u || brp > 1024u) {
            continue;
        }
        /* sync (1) + tseg1 + tseg2 = quanta; sample after tseg1 */
        uint32_t tseg2 = (quanta + 4u) / 8u; /* 12.5 %, rounded */
        if (quanta > 17u + tseg2) {
            /* tseg1 at most 16: the latest sample point this quanta
             * allows (without it, 21..25 quanta were never tried: no
             * timing at all for a rate only 25 quanta divide) */
            tseg2 = quanta - 17u;
        }
        tseg2 = (tseg2 < 1u) ? 1u : ((tseg2 > 8u) ? 8u : tseg2);
        const uint32_t tseg1 = quanta - 1u - tseg2;
        if (tseg1 < 1u || tseg1 > 16u) {
            continue;
        }
        const uint32_t sp = 1000u * (1u + tseg1) / quanta;
        const uint32_t err = (sp > 875u) ? sp - 875u : 875u - sp;
        if (err < best_err) {
            best_err = err;
            *t = (stm32_can_timing_t){
                .brp = (uint32_t)brp, .tseg1 = tseg1, .tseg2 = tseg2, .sjw = 1u
            };
            found = true;
        }
    }
    return found;
}

static bool wait_msr(uint32_t mask, uint32_t want)
{
    return stm32_wait_bits(&STM32_CAN1->MSR, mask, want, CAN_WAIT_LOOPS);
}

hal_status_t stm32_can_init(const stm32_board_t *b, uint32_t pclk1_hz,
                            uint32_t bitrate_bps)
{
    stm32_can_timing_t tm;
    if (!stm32_can_timing_for(pclk1_hz, bitrate_bps, &tm)) {
        return HAL_ERR_PARAM;
    }
    STM32_RCC->APB1ENR |= RCC_APB1ENR_CAN1EN;
    stm32_gpio_setup(&b->can_rx, GPIO_MODE_AF, STM32_PULL_UP);
    stm32_gpio_setup(&b->can_tx, GPIO_MODE_AF, STM32_PULL_NONE);
    stm32_can_t *c = STM32_CAN1;
    /* leave sleep, enter initialisation */
    c->MCR = CAN_MCR_INRQ;
    if (!wait_msr(CAN_MSR_INAK | CAN_MSR_SLAK, CAN_MSR_INAK)) {
        return HAL_ERR_HW;
    }
    c->MCR = CAN_MCR_INRQ | CAN_MCR_ABOM | CAN_MCR_TXFP;
    c->BTR = (tm.brp - 1u) | ((tm.tseg1 - 1u) << CAN_BTR_TS1_POS) |
             ((tm.tseg2 - 1u) << CAN_BTR_TS2_POS) |
             ((tm.sjw - 1u) << CAN_BTR_SJW_POS);
    /* filter bank 0: 32-bit mask mode, mask 0 (everything), FIFO 0 */
    c->FMR |= CAN_FMR_FINIT;
    c->FA1R &= ~1u;
    c->FM1R &= ~1u;
    c->FS1R |= 1u;
    c->FFA1R &= ~1u;
    c->FR[0][0] = 0u;
    c->FR[0][1] = 0u;
    c->FA1R |= 1u;
    c->FMR &= ~CAN_FMR_FINIT;
    c->MCR = CAN_MCR_ABOM | CAN_MCR_TXFP; /* normal mode */
    if (!wait_msr(CAN_MSR_INAK, 0u)) {
        return HAL_ERR_HW;
    }
    rx_overruns = 0u;
    bus_errors = 0u;
    return HAL_OK;
}

hal_status_t stm32_can_send(const hal_can_frame_t *f)
{
    if (!hal_can_frame_valid(f)) {
        return HAL_ERR_PARAM;
    }
    stm32_can_t *c = STM32_CAN1;
    const uint32_t tsr = c->TSR;
    if ((tsr & (7u * CAN_TSR_TME0)) == 0u) {
        return HAL_ERR_BUSY; /* all three mailboxes pending */
    }
    const uint32_t box = (tsr >> CAN_TSR_CODE_POS) & 3u; /* an empty one */
    stm32_can_mailbox_t *m = &c->TX[box];
    const uint32_t id = f->extended ? (f->id << CAN_TIR_EXID_POS) | CAN_TIR_IDE
                                    : (f->id << CAN_TIR_STID_POS);
    m->DTR = f->dlc;
    uint32_t lo = 0u;
    uint32_t hi = 0u;
    for (uint32_t k = 0u; k < 4u; ++k) {
        lo |= (uint32_t)f->data[k] << (8u * k);
        hi |= (uint32_t)f->data[k + 4u] << (8u * k);
    }
    m->DLR = lo;
    m->DHR = hi;
    m->IR = id | (f->rtr ? CAN_TIR_RTR : 0u) | CAN_TIR_TXRQ;
    return HAL_OK;
}

hal_status_t stm32_can_receive(hal_can_frame_t *f)
{
    stm32_can_t *c = STM32_CAN1;
    poll_errors();
    const uint32_t rf0r = c->RF0R;
    if ((rf0r & CAN_RF0R_FOVR) != 0u) {
        rx_overruns++;
        c->RF0R = CAN_RF0R_FOVR; /* write 1 to clear */
    }
    if ((rf0r & CAN_RF0R_FMP_MASK) == 0u) {
        return HAL_ERR_EMPTY;
    }
    const stm32_can_mailbox_t *m = &c->RX[0];
    const uint32_t ir = m->IR;
    f->extended = (ir & CAN_TIR_IDE) != 0u;
    f->id = f->extended ? (ir >> CAN_TIR_EXID_POS) & HAL_CAN_EXT_ID_MAX
                        : (ir >> CAN_TIR_STID_POS) & HAL_CAN_STD_ID_MAX;
    f->rtr = (ir & CAN_TIR_RTR) != 0u;
    /* a DLC of 9..15 means 8 data bytes in classic CAN (ISO 11898-1) */
    const uint32_t dlc = m->DTR & 0xFu;
    f->dlc = (uint8_t)((dlc > HAL_CAN_MAX_DLC) ? HAL_CAN_MAX_DLC : dlc);
    const uint32_t lo = m->DLR;
    const uint32_t hi = m->DHR;
    for (uint32_t k = 0u; k < 4u; ++k) {
        f->data[k] = (uint8_t)(lo >> (8u * k));
        f->data[k + 4u] = (uint8_t)(hi >> (8u * k));
    }
    c->RF0R = CAN_RF0R_RFOM; /* release the FIFO slot */
    return HAL_OK;
}

void stm32_can_stats(hal_can_stats_t *s)
{
    poll_errors();
    s->rx_overruns = rx_overruns;
    s->bus_errors = bus_errors;
}
