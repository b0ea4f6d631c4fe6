/*
 * STM32F405 registers the port uses, written from the reference manual
 * RM0090 (register maps of sections 7 RCC, 8 GPIO, 13 ADC, 17 TIM1/TIM8,
 * 18 TIM2-TIM5, 21 IWDG, 30 USART, 32 bxCAN, 3 FLASH) and the Cortex-M4
 * generic user guide (SCB, NVIC, SysTick, MPU, DWT). No vendor header.
 *
 * Every peripheral is a struct of volatile 32-bit registers at its
 * offsets (reserved words named rsvd*), reached through a STM32_<name>
 * macro. Built with STM32_REGS_FAKE (the host register tests,
 * tests/unit/hal/stm32f405), the macros name RAM structs instead
 * (stm32_fake_<name>), so the same driver code writes into memory a test
 * can inspect.
 */
#ifndef STM32_REGS_H
#define STM32_REGS_H

#include <stdbool.h>
#include <stdint.h>

#define STM32_REG volatile uint32_t

/* ---- RCC (RM0090 7.3) ---------------------------------------------- */
typedef struct {
    STM32_REG CR;        /* 0x00 */
    STM32_REG PLLCFGR;   /* 0x04 */
    STM32_REG CFGR;      /* 0x08 */
    STM32_REG CIR;       /* 0x0C */
    STM32_REG AHB1RSTR;  /* 0x10 */
    STM32_REG AHB2RSTR;  /* 0x14 */
    STM32_REG AHB3RSTR;  /* 0x18 */
    STM32_REG rsvd0;     /* 0x1C */
    STM32_REG APB1RSTR;  /* 0x20 */
    STM32_REG APB2RSTR;  /* 0x24 */
    STM32_REG rsvd1[2];  /* 0x28 */
    STM32_REG AHB1ENR;   /* 0x30 */
    STM32_REG AHB2ENR;   /* 0x34 */
    STM32_REG AHB3ENR;   /* 0x38 */
    STM32_REG rsvd2;     /* 0x3C */
    STM32_REG APB1ENR;   /* 0x40 */
    STM32_REG APB2ENR;   /* 0x44 */
    STM32_REG rsvd3[10]; /* 0x48 */
    STM32_REG BDCR;      /* 0x70 */
    STM32_REG CSR;       /* 0x74 */
} stm32_rcc_t;

#define RCC_CR_HSEON         (1u << 16)
#define RCC_CR_HSERDY        (1u << 17)
#define RCC_CR_PLLON         (1u << 24)
#define RCC_CR_PLLRDY        (1u << 25)
#define RCC_PLLCFGR_M_POS    0u  /* PLLM[5:0] */
#define RCC_PLLCFGR_N_POS    6u  /* PLLN[14:6] */
#define RCC_PLLCFGR_P_POS    16u /* PLLP[17:16]: P = 2 (PLLP + 1) */
#define RCC_PLLCFGR_SRC_HSE  (1u << 22)
#define RCC_PLLCFGR_Q_POS    24u /* PLLQ[27:24] */
#define RCC_CFGR_SW_MASK     (3u << 0)
#define RCC_CFGR_SW_HSI      (0u << 0)
#define RCC_CFGR_SW_PLL      (2u << 0)
#define RCC_CFGR_SWS_MASK    (3u << 2)
#define RCC_CFGR_SWS_PLL     (2u << 2)
#define RCC_CFGR_HPRE_POS    4u  /* HPRE[7:4], 0xxx: /1 */
#define RCC_CFGR_PPRE1_POS   10u /* PPRE1[12:10]: 0xx /1, 100 /2, 101 /4 */
#define RCC_CFGR_PPRE2_POS   13u /* PPRE2[15:13] */
#define RCC_APB_DIV2         4u
#define RCC_APB_DIV4         5u
#define RCC_AHB1ENR_GPIO(n)  (1u << (n)) /* GPIOAEN .. GPIOIEN: 0 .. 8 */
#define RCC_APB1ENR_TIM2EN   (1u << 0)
#define RCC_APB1ENR_TIM3EN   (1u << 1)
#define RCC_APB1ENR_SPI3EN   (1u << 15)
#define RCC_APB1ENR_USART2EN (1u << 17)
#define RCC_APB1ENR_CAN1EN   (1u << 25)
#define RCC_APB1ENR_PWREN    (1u << 28)
#define RCC_APB2ENR_TIM1EN   (1u << 0)
#define RCC_APB2ENR_ADC1EN   (1u << 8)
#define RCC_APB2ENR_ADC2EN   (1u << 9)
#define RCC_APB2ENR_ADC3EN   (1u << 10)

/* ---- FLASH interface (RM0090 3.9) ------------------------------------ */
typedef struct {
    STM32_REG ACR; /* 0x00 */
} stm32_flash_t;

#define FLASH_ACR_PRFTEN (1u << 8)
#define FLASH_ACR_ICEN   (1u << 9)
#define FLASH_ACR_DCEN   (1u << 10)

/* ---- PWR (RM0090 5.4) ------------------------------------------------ */
typedef struct {
    STM32_REG CR; /* 0x00 */
} stm32_pwr_t;

#define PWR_CR_VOS (1u << 14) /* regulator scale 1 (168 MHz) */

/* ---- GPIO (RM0090 8.4) ----------------------------------------------- */
typedef struct {
    STM32_REG MODER;   /* 0x00: 2 bits per pin */
    STM32_REG OTYPER;  /* 0x04 */
    STM32_REG OSPEEDR; /* 0x08 */
    STM32_REG PUPDR;   /* 0x0C */
    STM32_REG IDR;     /* 0x10 */
    STM32_REG ODR;     /* 0x14 */
    STM32_REG BSRR;    /* 0x18: set low half, reset high half */
    STM32_REG LCKR;    /* 0x1C */
    STM32_REG AFR[2];  /* 0x20 AFRL, 0x24 AFRH: 4 bits per pin */
} stm32_gpio_t;

#define GPIO_MODE_INPUT  0u
#define GPIO_MODE_OUTPUT 1u
#define GPIO_MODE_AF     2u
#define GPIO_MODE_ANALOG 3u

/* ---- Timers: TIM1/TIM8 (RM0090 17.4), TIM2-TIM5 (18.4) --------------- */
typedef struct {
    STM32_REG CR1;    /* 0x00 */
    STM32_REG CR2;    /* 0x04 */
    STM32_REG SMCR;   /* 0x08 */
    STM32_REG DIER;   /* 0x0C */
    STM32_REG SR;     /* 0x10 */
    STM32_REG EGR;    /* 0x14 */
    STM32_REG CCMR1;  /* 0x18 */
    STM32_REG CCMR2;  /* 0x1C */
    STM32_REG CCER;   /* 0x20 */
    STM32_REG CNT;    /* 0x24 */
    STM32_REG PSC;    /* 0x28 */
    STM32_REG ARR;    /* 0x2C */
    STM32_REG RCR;    /* 0x30 (TIM1/TIM8 only) */
    STM32_REG CCR[4]; /* 0x34 .. 0x40 */
    STM32_REG BDTR;   /* 0x44 (TIM1/TIM8 only) */
    STM32_REG DCR;    /* 0x48 */
    STM32_REG DMAR;   /* 0x4C */
} stm32_tim_t;

#define TIM_CR1_CEN         (1u << 0)
#define TIM_CR1_CMS_CENTER1 (1u << 5) /* CMS = 01: centre-aligned mode 1 */
#define TIM_CR1_ARPE        (1u << 7)
#define TIM_SMCR_SMS_ENC3   3u /* encoder mode 3: both edges of TI1, TI2 */
#define TIM_SR_BIF          (1u << 7)
#define TIM_EGR_UG          (1u << 0)
#define TIM_CCMR_OC_PE      (1u << 3) /* OCxPE in the channel's byte */
#define TIM_CCMR_OC_PWM1    (6u << 4) /* OCxM = 110 in the channel's byte */
#define TIM_CCMR_CC_TI      1u        /* CCxS = 01: input on TIx */
#define TIM_CCER_CCE(ch)    (1u << (4u * (ch)))      /* ch 0..3 */
#define TIM_CCER_CCNE(ch)   (1u << (4u * (ch) + 2u)) /* ch 0..2 */
#define TIM_BDTR_OSSI       (1u << 10)
#define TIM_BDTR_OSSR       (1u << 11)
#define TIM_BDTR_BKE        (1u << 12)
#define TIM_BDTR_BKP        (1u << 13)
#define TIM_BDTR_MOE        (1u << 15)

/* ---- ADC (RM0090 13.13) ---------------------------------------------- */
typedef struct {
    STM32_REG SR;      /* 0x00 */
    STM32_REG CR1;     /* 0x04 */
    STM32_REG CR2;     /* 0x08 */
    STM32_REG SMPR1;   /* 0x0C: channels 10-18 */
    STM32_REG SMPR2;   /* 0x10: channels 0-9 */
    STM32_REG JOFR[4]; /* 0x14 .. 0x20 */
    STM32_REG HTR;     /* 0x24 */
    STM32_REG LTR;     /* 0x28 */
    STM32_REG SQR[3];  /* 0x2C .. 0x34 */
    STM32_REG JSQR;    /* 0x38 */
    STM32_REG JDR[4];  /* 0x3C .. 0x48 */
    STM32_REG DR;      /* 0x4C */
} stm32_adc_t;

typedef struct {
    STM32_REG CSR; /* 0x00 */
    STM32_REG CCR; /* 0x04 */
    STM32_REG CDR; /* 0x08 */
} stm32_adc_common_t;

#define ADC_SR_JEOC          (1u << 2)
#define ADC_CR1_JEOCIE       (1u << 7)
#define ADC_CR1_SCAN         (1u << 8)
#define ADC_CR2_ADON         (1u << 0)
#define ADC_CR2_JEXTSEL_POS  16u /* JEXTSEL[19:16] */
#define ADC_CR2_JEXTEN_POS   20u /* JEXTEN[21:20] */
#define ADC_JEXTSEL_TIM1_CC4 0u
#define ADC_JEXTEN_RISING    1u
#define ADC_JSQR_JL_POS      20u /* JL[21:20]: conversions - 1 */
#define ADC_CCR_ADCPRE_POS   16u /* ADCPRE[17:16]: PCLK2 / (2 (n + 1)) */
#define ADC_CCR_MULTI_TRIPLE_INJ                                               \
    0x15u /* triple mode, injected simultaneous                                \
           */

/* ---- IWDG (RM0090 21.4) ---------------------------------------------- */
typedef struct {
    STM32_REG KR;  /* 0x00 */
    STM32_REG PR;  /* 0x04 */
    STM32_REG RLR; /* 0x08 */
    STM32_REG SR;  /* 0x0C */
} stm32_iwdg_t;

#define IWDG_KEY_START  0xCCCCu
#define IWDG_KEY_RELOAD 0xAAAAu
#define IWDG_KEY_ACCESS 0x5555u
#define IWDG_SR_PVU     (1u << 0)
#define IWDG_SR_RVU     (1u << 1)

/* ---- USART (RM0090 30.6) --------------------------------------------- */
typedef struct {
    STM32_REG SR;   /* 0x00 */
    STM32_REG DR;   /* 0x04 */
    STM32_REG BRR;  /* 0x08 */
    STM32_REG CR1;  /* 0x0C */
    STM32_REG CR2;  /* 0x10 */
    STM32_REG CR3;  /* 0x14 */
    STM32_REG GTPR; /* 0x18 */
} stm32_usart_t;

#define USART_SR_TXE (1u << 7)
#define USART_CR1_TE (1u << 3)
#define USART_CR1_UE (1u << 13)

/* ---- SPI (RM0090 28.5) ----------------------------------------------- */
typedef struct {
    STM32_REG CR1; /* 0x00 */
    STM32_REG CR2; /* 0x04 */
    STM32_REG SR;  /* 0x08 */
    STM32_REG DR;  /* 0x0C */
} stm32_spi_t;

#define SPI_CR1_CPHA   (1u << 0)
#define SPI_CR1_MSTR   (1u << 2)
#define SPI_CR1_BR_POS 3u /* BR[5:3]: f_PCLK / 2^(BR + 1) */
#define SPI_CR1_SPE    (1u << 6)
#define SPI_CR1_SSI    (1u << 8)
#define SPI_CR1_SSM    (1u << 9)
#define SPI_CR1_DFF    (1u << 11) /* 16-bit frames */
#define SPI_SR_RXNE    (1u << 0)
#define SPI_SR_BSY     (1u << 7)

/* ---- bxCAN (RM0090 32.9) --------------------------------------------- */
typedef struct {
    STM32_REG IR;  /* TIR / RIR */
    STM32_REG DTR; /* TDTR / RDTR */
    STM32_REG DLR; /* TDLR / RDLR */
    STM32_REG DHR; /* TDHR / RDHR */
} stm32_can_mailbox_t;

typedef struct {
    STM32_REG MCR;             /* 0x000 */
    STM32_REG MSR;             /* 0x004 */
    STM32_REG TSR;             /* 0x008 */
    STM32_REG RF0R;            /* 0x00C */
    STM32_REG RF1R;            /* 0x010 */
    STM32_REG IER;             /* 0x014 */
    STM32_REG ESR;             /* 0x018 */
    STM32_REG BTR;             /* 0x01C */
    STM32_REG rsvd0[88];       /* 0x020 */
    stm32_can_mailbox_t TX[3]; /* 0x180 */
    stm32_can_mailbox_t RX[2]; /* 0x1B0 */
    STM32_REG rsvd1[12];       /* 0x1D0 */
    STM32_REG FMR;             /* 0x200 */
    STM32_REG FM1R;            /* 0x204 */
    STM32_REG rsvd2;           /* 0x208 */
    STM32_REG FS1R;            /* 0x20C */
    STM32_REG rsvd3;           /* 0x210 */
    STM32_REG FFA1R;           /* 0x214 */
    STM32_REG rsvd4;           /* 0x218 */
    STM32_REG FA1R;            /* 0x21C */
    STM32_REG rsvd5[8];        /* 0x220 */
    STM32_REG FR[28][2];       /* 0x240: F0R1, F0R2, ... */
} stm32_can_t;

#define CAN_MCR_INRQ      (1u << 0)
#define CAN_MCR_TXFP      (1u << 2)
#define CAN_MCR_ABOM      (1u << 6)
#define CAN_MSR_INAK      (1u << 0)
#define CAN_MSR_SLAK      (1u << 1)
#define CAN_TSR_TME0      (1u << 26)
#define CAN_TSR_CODE_POS  24u
#define CAN_RF0R_FMP_MASK 3u
#define CAN_RF0R_FOVR     (1u << 4)
#define CAN_RF0R_RFOM     (1u << 5)
#define CAN_ESR_LEC_POS   4u  /* LEC[6:4]: last error code */
#define CAN_BTR_TS1_POS   16u /* TS1[19:16]: tBS1 = (TS1 + 1) tq */
#define CAN_BTR_TS2_POS   20u /* TS2[22:20] */
#define CAN_BTR_SJW_POS   24u /* SJW[25:24] */
#define CAN_TIR_TXRQ      (1u << 0)
#define CAN_TIR_RTR       (1u << 1)
#define CAN_TIR_IDE       (1u << 2)
#define CAN_TIR_STID_POS  21u
#define CAN_TIR_EXID_POS  3u
#define CAN_FMR_FINIT     (1u << 0)

/* ---- Cortex-M4 system (ARMv7-M ARM B3) ------------------------------- */
typedef struct {
    STM32_REG CTRL; /* 0xE000E010 */
    STM32_REG LOAD;
    STM32_REG VAL;
    STM32_REG CALIB;
} stm32_systick_t;

#define SYSTICK_CTRL_ENABLE    (1u << 0)
#define SYSTICK_CTRL_TICKINT   (1u << 1)
#define SYSTICK_CTRL_CLKSOURCE (1u << 2)

typedef struct {
    STM32_REG CPUID; /* 0xE000ED00 */
    STM32_REG ICSR;
    STM32_REG VTOR;
    STM32_REG AIRCR;
    STM32_REG SCR;
    STM32_REG CCR;
    STM32_REG SHPR[3];
    STM32_REG SHCSR; /* 0xE000ED24 */
    STM32_REG CFSR;
    STM32_REG HFSR;
    STM32_REG DFSR;
    STM32_REG MMFAR;
    STM32_REG BFAR;
    STM32_REG AFSR;
} stm32_scb_t;

#define SCB_SHCSR_MEMFAULTENA (1u << 16)

typedef struct {
    STM32_REG TYPE; /* 0xE000ED90 */
    STM32_REG CTRL;
    STM32_REG RNR;
    STM32_REG RBAR;
    STM32_REG RASR;
} stm32_mpu_t;

#define MPU_CTRL_ENABLE     (1u << 0)
#define MPU_CTRL_PRIVDEFENA (1u << 2)
#define MPU_RASR_ENABLE     (1u << 0)
#define MPU_RASR_SIZE_POS   1u  /* region size 2^(SIZE + 1) bytes */
#define MPU_RASR_AP_POS     24u /* AP = 000: no access */
#define MPU_RASR_XN         (1u << 28)

typedef struct {
    STM32_REG ISER[8]; /* 0xE000E100 */
    STM32_REG rsvd0[24];
    STM32_REG ICER[8]; /* 0xE000E180 */
    STM32_REG rsvd1[24];
    STM32_REG ISPR[8]; /* 0xE000E200 */
    STM32_REG rsvd2[24];
    STM32_REG ICPR[8]; /* 0xE000E280 */
    STM32_REG rsvd3[24];
    STM32_REG IABR[8]; /* 0xE000E300 */
    STM32_REG rsvd4[56];
    volatile uint8_t IPR[240]; /* 0xE000E400 */
} stm32_nvic_t;

typedef struct {
    STM32_REG CTRL;   /* 0xE0001000 */
    STM32_REG CYCCNT; /* 0xE0001004 */
} stm32_dwt_t;

#define DWT_CTRL_CYCCNTENA (1u << 0)
#define DEMCR_ADDR         0xE000EDFCu
#define DEMCR_TRCENA       (1u << 24)

/* Device interrupt numbers (RM0090 table 61) the port uses. */
#define STM32_IRQ_ADC   18u
#define STM32_IRQ_TIM2  28u
#define STM32_IRQ_COUNT 82u

/* ---- instances ------------------------------------------------------- */
#ifdef STM32_REGS_FAKE
#define STM32_FAKE_LIST(X)                                                     \
    X(stm32_rcc_t, rcc, )                                                      \
    X(stm32_flash_t, flash, )                                                  \
    X(stm32_pwr_t, pwr, )                                                      \
    X(stm32_gpio_t, gpio, [9])                                                 \
    X(stm32_tim_t, tim1, )                                                     \
    X(stm32_tim_t, tim2, )                                                     \
    X(stm32_tim_t, tim3, )                                                     \
    X(stm32_adc_t, adc, [3])                                                   \
    X(stm32_adc_common_t, adc_common, )                                        \
    X(stm32_iwdg_t, iwdg, )                                                    \
    X(stm32_usart_t, usart2, )                                                 \
    X(stm32_spi_t, spi3, )                                                     \
    X(stm32_can_t, can1, )                                                     \
    X(stm32_systick_t, systick, )                                              \
    X(stm32_scb_t, scb, )                                                      \
    X(stm32_mpu_t, mpu, )                                                      \
    X(stm32_nvic_t, nvic, )                                                    \
    X(stm32_dwt_t, dwt, )                                                      \
    X(uint32_t, demcr, )
#define STM32_FAKE_DECLARE(type, name, dims) extern type stm32_fake_##name dims;
STM32_FAKE_LIST(STM32_FAKE_DECLARE)
#undef STM32_FAKE_DECLARE
#define STM32_RCC        (&stm32_fake_rcc)
#define STM32_FLASH      (&stm32_fake_flash)
#define STM32_PWR        (&stm32_fake_pwr)
#define STM32_GPIO(n)    (&stm32_fake_gpio[n])
#define STM32_TIM1       (&stm32_fake_tim1)
#define STM32_TIM2       (&stm32_fake_tim2)
#define STM32_TIM3       (&stm32_fake_tim3)
#define STM32_ADC(n)     (&stm32_fake_adc[(n)-1])
#define STM32_ADC_COMMON (&stm32_fake_adc_common)
#define STM32_IWDG       (&stm32_fake_iwdg)
#define STM32_USART2     (&stm32_fake_usart2)
#define STM32_SPI3       (&stm32_fake_spi3)
#define STM32_CAN1       (&stm32_fake_can1)
#define STM32_SYSTICK    (&stm32_fake_systick)
#define STM32_SCB        (&stm32_fake_scb)
#define STM32_MPU        (&stm32_fake_mpu)
#define STM32_NVIC       (&stm32_fake_nvic)
#define STM32_DWT        (&stm32_fake_dwt)
#define STM32_DEMCR      (&stm32_fake_demcr)
#else
#define STM32_PERIPH(type, addr) ((type *)(uintptr_t)(addr))
#define STM32_RCC                STM32_PERIPH(stm32_rcc_t, 0x40023800u)
#define STM32_FLASH              STM32_PERIPH(stm32_flash_t, 0x40023C00u)
#define STM32_PWR                STM32_PERIPH(stm32_pwr_t, 0x40007000u)
#define STM32_GPIO(n)            STM32_PERIPH(stm32_gpio_t, 0x40020000u + 0x400u * (n))
#define STM32_TIM1               STM32_PERIPH(stm32_tim_t, 0x40010000u)
#define STM32_TIM2               STM32_PERIPH(stm32_tim_t, 0x40000000u)
#define STM32_TIM3               STM32_PERIPH(stm32_tim_t, 0x40000400u)
#define STM32_ADC(n)             STM32_PERIPH(stm32_adc_t, 0x40012000u + 0x100u * ((n)-1))
#define STM32_ADC_COMMON         STM32_PERIPH(stm32_adc_common_t, 0x40012300u)
#define STM32_IWDG               STM32_PERIPH(stm32_iwdg_t, 0x40003000u)
#define STM32_USART2             STM32_PERIPH(stm32_usart_t, 0x40004400u)
#define STM32_SPI3               STM32_PERIPH(stm32_spi_t, 0x40003C00u)
#define STM32_CAN1               STM32_PERIPH(stm32_can_t, 0x40006400u)
#define STM32_SYSTICK            STM32_PERIPH(stm32_systick_t, 0xE000E010u)
#define STM32_SCB                STM32_PERIPH(stm32_scb_t, 0xE000ED00u)
#define STM32_MPU                STM32_PERIPH(stm32_mpu_t, 0xE000ED90u)
#define STM32_NVIC               STM32_PERIPH(stm32_nvic_t, 0xE000E100u)
#define STM32_DWT                STM32_PERIPH(stm32_dwt_t, 0xE0001000u)
#define STM32_DEMCR              STM32_PERIPH(volatile uint32_t, DEMCR_ADDR)
#endif

/* The register offsets of RM0090's maps (a wrong struct layout is a build
 * error, not a write to the wrong register). */
#include <stddef.h>
_Static_assert(offsetof(stm32_rcc_t, APB1ENR) == 0x40u, "RCC map");
_Static_assert(offsetof(stm32_rcc_t, CSR) == 0x74u, "RCC map");
_Static_assert(offsetof(stm32_gpio_t, AFR) == 0x20u, "GPIO map");
_Static_assert(offsetof(stm32_tim_t, CCR) == 0x34u, "TIM map");
_Static_assert(offsetof(stm32_tim_t, BDTR) == 0x44u, "TIM map");
_Static_assert(offsetof(stm32_adc_t, JSQR) == 0x38u, "ADC map");
_Static_assert(offsetof(stm32_adc_t, DR) == 0x4Cu, "ADC map");
_Static_assert(offsetof(stm32_can_t, TX) == 0x180u, "bxCAN map");
_Static_assert(offsetof(stm32_can_t, RX) == 0x1B0u, "bxCAN map");
_Static_assert(offsetof(stm32_can_t, FMR) == 0x200u, "bxCAN map");
_Static_assert(offsetof(stm32_can_t, FA1R) == 0x21Cu, "bxCAN map");
_Static_assert(offsetof(stm32_can_t, FR) == 0x240u, "bxCAN map");
_Static_assert(offsetof(stm32_scb_t, SHCSR) == 0x24u, "SCB map");
_Static_assert(offsetof(stm32_nvic_t, IPR) == 0x300u, "NVIC map");

/* Data and instruction barriers after a configuration change (none in
 * the host's register fake). */
static inline void stm32_barrier(void)
{
#ifndef STM32_REGS_FAKE
    __asm__ volatile("dsb\n isb" ::: "memory");
#endif
}

/* Wait until (*reg & mask) == want, reading it at most `loops` times: the
 * bounded wait of every status bit the drivers poll. False on the
 * timeout. */
static inline bool stm32_wait_bits(const volatile uint32_t *reg, uint32_t mask,
                                   uint32_t want, uint32_t loops)
{
    for (uint32_t k = 0u; k < loops; ++k) {
        if ((*reg & mask) == want) {
            return true;
        }
    }
    return false;
}

/* GPIO ports by letter. */
enum { STM32_PA = 0, STM32_PB, STM32_PC, STM32_PD, STM32_PE };

#endif /* STM32_REGS_H */
