/*
 * sim_engine.h - closed-loop simulation: plant + host HAL + drive firmware.
 *
 * One sim_engine_step() is one PWM period k (t_k = k Ts):
 *   0. the command goes to the firmware (mc_app_set_command);
 *   1. plant_sample(): currents, v_dc, encoder at the PWM centre t_k;
 *   2. active fault injections edit that measurement / the fault input;
 *   3. the host HAL mailbox gets the sample, the firmware fast ISR runs;
 *   4. the plant advances over [t_k, t_k + Ts). The duties latch at the
 *      inverter's update event (plant inverter.duty_update):
 *      PLANT_DUTY_UPDATE_NEXT_PERIOD (default): at t_{k+1}, so the period
 *        runs on the PREVIOUS ISR's duties; ISR k's act over
 *        [t_{k+1}, t_{k+2}): sample-to-apply delay 1.5 periods;
 *      PLANT_DUTY_UPDATE_HALF_PERIOD: at t_k + Ts/2 (plant_advance_split):
 *        ISR k's act over [t_k + Ts/2, t_{k+1} + Ts/2): delay 1.0 period.
 *      The engine reports that delay to the firmware through the HAL
 *      (hal/pwm.h). The PWM outputs follow the same update when they are
 *      ENABLED, but a disable is immediate (no shadow register), so an ISR
 *      that trips a fault at t_k stops the inverter for [t_k, t_k + Ts)
 *      already.
 *   5. the trace sample of period k is recorded (sim_engine_last()).
 *
 * The firmware sees the plant only through the HAL. The plant and firmware
 * PWM frequencies and encoder resolutions must agree (checked by init).
 *
 * Fault injection (for tests and scenarios) is driven by the sample time:
 * an injection is active for t_start_s <= t_k < t_end_s.
 *
 * Host only (C11, double precision, no allocation: the caller owns the
 * engine, about 5 kB, plant included; allocate it statically or on the
 * heap). Single-threaded per engine; several engines may be stepped in turn
 * from one thread (each step binds its own HAL mailbox).
 */
#ifndef SIM_ENGINE_H
#define SIM_ENGINE_H

#include <stdbool.h>
#include <stdint.h>

#include "hal_sim_mailbox.h"
#include "mc/app.h"
#include "plant.h"

#define SIM_ENGINE_MAX_INJECTIONS 16u

/* Sample-to-apply delays of the two duty-update models (periods). */
#define SIM_ENGINE_DELAY_NEXT_PERIOD 1.5f
#define SIM_ENGINE_DELAY_HALF_PERIOD 1.0f

typedef enum {
    SIM_ENGINE_OK = 0,
    SIM_ENGINE_ERR_NULL = -1,
    SIM_ENGINE_ERR_PLANT = -2,     /* plant_init failed (see the message) */
    SIM_ENGINE_ERR_MISMATCH = -3,  /* plant and firmware disagree (PWM
                                      frequency, encoder cpr) */
    SIM_ENGINE_ERR_FIRMWARE = -4,  /* mc_app_init failed */
    SIM_ENGINE_ERR_INJECTION = -5, /* invalid injection or table full */
    SIM_ENGINE_ERR_COMMAND = -6,   /* mc_app_set_command rejected it */
    SIM_ENGINE_ERR_STATE = -7      /* step on an engine whose init failed */
} sim_engine_err_t;

typedef enum {
    SIM_INJECT_CURRENT_NAN = 0, /* measured current of `phase` := NaN */
    SIM_INJECT_CURRENT_OFFSET,  /* measured current of `phase` += value (A):
                                   a sensor spike / fault */
    SIM_INJECT_VDC_MEASURED,    /* measured v_dc := value (V) */
    SIM_INJECT_FAULT_INPUT      /* external fault / STO input asserted */
} sim_inject_kind_t;

typedef struct {
    sim_inject_kind_t kind;
    double t_start_s; /* active for t_start_s <= t_k < t_end_s */
    double t_end_s;   /* may be INFINITY */
    uint32_t phase;   /* 0, 1, 2 (a, b, c) for the current kinds */
    double value;     /* A or V, see the kind */
} sim_injection_t;

/* Everything about PWM period k. */
typedef struct {
    uint64_t k;                 /* period index */
    double t_s;                 /* t_k = k Ts, the sampling instant */
    plant_true_state_t plant;   /* true plant state at t_k (its v_abc are
                                   the averages over the previous period) */
    plant_measurement_t meas;   /* what the HAL delivered (after the
                                   injections) */
    uint32_t injections_active; /* bit i: injection i was active at t_k */
    mc_command_t cmd;           /* command given for this step */
    mc_telemetry_t fw;          /* firmware telemetry of the ISR at t_k */
    double duty_applied[3];     /* duties the inverter used from t_k
                                   (to t_k + Ts, or to t_k + Ts/2 with the
                                   half-period update) */
    bool outputs_applied;       /* inverter switching in [t_k, t_k + Ts) */
} sim_trace_sample_t;

/* Private: the caller owns the storage; use the functions below. */
typedef struct {
    plant_t plant;
    mc_app_t app;
    hal_sim_mailbox_t mailbox;
    double duty_next[3]; /* latched by the last ISR */
    bool outputs_next;
    bool half_period_update; /* plant inverter.duty_update */
    sim_injection_t injections[SIM_ENGINE_MAX_INJECTIONS];
    uint32_t n_injections;
    uint64_t k;
    sim_trace_sample_t last;
    bool initialised;
    const char *message;
} sim_engine_t;

/* The firmware values the bench takes from the plant: the nominal motor
 * (the controller's model; the plant applies its mismatch), the PWM rate
 * and the encoder resolution (4 x lines). The rest of *fw is kept.
 * Call after mc_config_init_default() (or on any configuration). */
void sim_engine_firmware_from_plant(const plant_config_t *plant, mc_config_t *fw);

/* Initialise plant and firmware (the firmware enters IDLE with the PWM
 * off). Returns SIM_ENGINE_OK or a negative sim_engine_err_t; the message
 * (sim_engine_message) says what is wrong. */
int sim_engine_init(sim_engine_t *e, const plant_config_t *plant_cfg, const mc_config_t *fw_cfg);

/* Static sentence about the last init/add/step result ("ok"). */
const char *sim_engine_message(const sim_engine_t *e);

/* Add a fault injection (before or between steps). Rejects a non-finite
 * start, end < start, a phase > 2 for current kinds, a non-finite value
 * (except for SIM_INJECT_CURRENT_NAN, whose value is unused), an unknown
 * kind, or a full table: SIM_ENGINE_ERR_INJECTION. */
int sim_engine_add_injection(sim_engine_t *e, const sim_injection_t *inj);

/* Simulate one PWM period with this command (see the top of this file).
 * SIM_ENGINE_ERR_COMMAND: unknown mode; nothing changes (the period is NOT
 * simulated, the sensors are not sampled, sim_engine_last() is kept). */
int sim_engine_step(sim_engine_t *e, const mc_command_t *cmd);

/* The trace sample of the latest step (valid until the next step). */
const sim_trace_sample_t *sim_engine_last(const sim_engine_t *e);

/* Time of the next sampling instant t_{k+1} (s) = steps done * Ts. */
double sim_engine_time_s(const sim_engine_t *e);

/* PWM period Ts in s. */
double sim_engine_period_s(const sim_engine_t *e);

#endif /* SIM_ENGINE_H */
