/* Closed-loop simulation engine (see sim_engine.h). */
#include "sim_engine.h"

#include <math.h>
#include <stddef.h>

#include "hal/encoder.h"

/* Relative tolerance of the plant / firmware PWM frequency agreement
 * (the firmware holds it in float). */
#define SIM_ENGINE_F_PWM_REL_TOL 1.0e-6

#define SIM_ENGINE_TWO_PI 6.283185307179586476925286766559

/* The drive's CAN bit rate (the protocol's: tools/dbc/pmsm_drive.dbc). */
#define SIM_ENGINE_CAN_BITRATE_BPS 1000000u

/* The engine's mailbox: the backend's fixed one, else its own
 * (hal_sim_fixed_mailbox). */
static hal_sim_mailbox_t *engine_mailbox(sim_engine_t *e)
{
    hal_sim_mailbox_t *fixed = hal_sim_fixed_mailbox();
    return (fixed != NULL) ? fixed : &e->mailbox;
}

static int fail(sim_engine_t *e, int code, const char *message)
{
    e->message = message;
    return code;
}

void sim_engine_firmware_from_plant(const plant_config_t *plant, mc_config_t *fw)
{
    const plant_motor_params_t *m = &plant->motor;
    fw->motor = (mc_motor_params_t){
        .R_ohm = (float)m->R_ohm,
        .Ld_H = (float)m->Ld_H,
        .Lq_H = (float)m->Lq_H,
        .psi_Wb = (float)m->psi_Wb,
        .pole_pairs = m->pole_pairs,
        .J_kgm2 = (float)m->J_kgm2,
        .B_Nm_s_rad = (float)m->B_Nm_s_rad,
    };
    fw->timing.f_pwm_Hz = (float)plant->inverter.f_pwm_Hz;
    fw->deadtime.dead_time_s = (float)plant->inverter.t_dead_s;
    fw->deadtime.device_drop_V = (float)plant->inverter.v_device_drop_V;
    fw->encoder.counts_per_rev = 4u * plant->sensors.encoder.lines;
    /* The bench times the fast ISR in host wall time (hal/host): a loaded
     * machine charges preemption, page faults and hypervisor steal to the
     * ISR it interrupts, so a few periods over budget in a row are the
     * host's, not the firmware's (measured with thread CPU time, which
     * sees page faults and steal: three in a row once in a few full test
     * runs on a 2-core VM). A preemption lengthens the one ISR it falls
     * into, and the scheduler preempts at most once a tick (ms) while the
     * bench runs an ISR every few us, so 100 in a row, the largest limit,
     * is still a hung ISR. */
    fw->timing.isr_overrun_limit = MC_TIMING_OVERRUN_LIMIT_MAX;
    /* The bench's traces and metrics read the record after every ISR. */
    fw->timing.telemetry_every_isr = true;
}

/* NULL when the firmware configuration agrees with the plant's PWM rate
 * and encoder resolution (cpr = 4 x lines), else what differs. */
static const char *firmware_mismatch(const mc_config_t *fw_cfg, double f_plant_Hz, uint32_t cpr)
{
    if (!(fabs((double)fw_cfg->timing.f_pwm_Hz - f_plant_Hz) <=
          SIM_ENGINE_F_PWM_REL_TOL * f_plant_Hz)) {
        return "firmware timing.f_pwm_Hz differs from the plant's f_pwm_Hz";
    }
    const uint32_t fw_cpr = mc_config_estimator_info(fw_cfg).encoder_cpr;
    if (fw_cpr != 0u && fw_cpr != cpr) {
        return "firmware encoder.counts_per_rev differs from 4 x plant encoder lines";
    }
    return NULL;
}

int sim_engine_init(sim_engine_t *e, const plant_config_t *plant_cfg, const mc_config_t *fw_cfg)
{
    if (e == NULL) {
        return SIM_ENGINE_ERR_NULL;
    }
    *e = (sim_engine_t){ .message = "ok" };
    if (plant_cfg == NULL || fw_cfg == NULL) {
        return fail(e, SIM_ENGINE_ERR_NULL, "plant or firmware config is NULL");
    }
    if (plant_init(&e->plant, plant_cfg) != PLANT_OK) {
        return fail(e, SIM_ENGINE_ERR_PLANT, plant_error_message(&e->plant));
    }
    const double f_plant = plant_cfg->inverter.f_pwm_Hz;
    const uint32_t cpr = 4u * plant_cfg->sensors.encoder.lines;
    const char *mismatch = firmware_mismatch(fw_cfg, f_plant, cpr);
    if (mismatch != NULL) {
        return fail(e, SIM_ENGINE_ERR_MISMATCH, mismatch);
    }
    /* plant_init checked that the half-period update has even substeps */
    const bool half = plant_cfg->inverter.duty_update == PLANT_DUTY_UPDATE_HALF_PERIOD;
    e->half_period_update = half;
    e->pole_pairs = plant_cfg->motor.pole_pairs;
    e->dc_link_capacitive = plant_cfg->dc_link.capacitance_F > 0.0;
    e->plant_normal = (sim_plant_faults_t){ .rotor_locked = plant_cfg->locked_rotor,
                                            .source_connected = true,
                                            .t_dead_s = plant_cfg->inverter.t_dead_s };
    e->plant_faults = e->plant_normal;
    hal_sim_mailbox_t *mb = engine_mailbox(e);
    hal_sim_mailbox_reset(mb);
    mb->encoder_cpr = cpr;
    mb->pwm_f_Hz = (float)f_plant;
    mb->pwm_delay_periods = half ? SIM_ENGINE_DELAY_HALF_PERIOD : SIM_ENGINE_DELAY_NEXT_PERIOD;
    mb->oc_comparator = plant_cfg->inverter.overcurrent_comparator;
    hal_sim_bind(mb);
    const mc_status_t st = mc_app_init(&e->app, fw_cfg);
    hal_sim_bind(NULL);
    if (st != MC_OK) {
        return fail(e, SIM_ENGINE_ERR_FIRMWARE, "firmware config rejected by mc_app_init");
    }
    e->fw_cfg = *fw_cfg;
    for (unsigned k = 0u; k < 3u; ++k) {
        e->duty_next[k] = 0.5;
    }
    e->outputs_next = false;
    e->initialised = true;
    return SIM_ENGINE_OK;
}

const char *sim_engine_message(const sim_engine_t *e)
{
    return (e == NULL) ? "engine is NULL" : e->message;
}

static bool uses_phase(sim_inject_kind_t kind)
{
    return kind == SIM_INJECT_CURRENT_NAN || kind == SIM_INJECT_CURRENT_OFFSET ||
           kind == SIM_INJECT_CURRENT_OFFSET_RAMP || kind == SIM_INJECT_CURRENT_STUCK ||
           kind == SIM_INJECT_CURRENT_GAIN || kind == SIM_INJECT_PHASE_OPEN;
}

static bool is_encoder_kind(sim_inject_kind_t kind)
{
    return kind == SIM_INJECT_ENCODER_SLIP || kind == SIM_INJECT_ENCODER_FROZEN ||
           kind == SIM_INJECT_ENCODER_COUNT_LOSS;
}

/* NULL if the kind's own fields are valid, else what is wrong. */
static const char *kind_field_problem(const sim_injection_t *inj)
{
    switch (inj->kind) {
    case SIM_INJECT_CURRENT_NAN:
    case SIM_INJECT_FAULT_INPUT:
    case SIM_INJECT_ENCODER_FROZEN:
    case SIM_INJECT_PHASE_OPEN:
    case SIM_INJECT_ROTOR_LOCK:
    case SIM_INJECT_BUS_SOURCE_LOSS: return NULL;
    case SIM_INJECT_CURRENT_OFFSET:
    case SIM_INJECT_VDC_MEASURED:
    case SIM_INJECT_CURRENT_STUCK:
        return isfinite(inj->value) ? NULL : "injection value must be finite";
    case SIM_INJECT_ENCODER_SLIP:
        return isfinite(inj->angle_e_rad) ? NULL : "encoder_slip angle_e_rad must be finite";
    case SIM_INJECT_ENCODER_COUNT_LOSS:
        return (inj->lost_fraction > 0.0 && inj->lost_fraction < 1.0)
                   ? NULL
                   : "encoder_count_loss lost_fraction must be in (0, 1)";
    case SIM_INJECT_CURRENT_GAIN:
        return isfinite(inj->value) && inj->value > 0.0
                   ? NULL
                   : "current_gain gain must be finite and > 0";
    case SIM_INJECT_DEAD_TIME:
        return isfinite(inj->value) && inj->value >= 0.0
                   ? NULL
                   : "dead_time dead_time_s must be finite and >= 0";
    case SIM_INJECT_CURRENT_OFFSET_RAMP:
        return isfinite(inj->rate_A_s) ? NULL : "current_offset_ramp rate_A_s must be finite";
    }
    return "unknown injection kind";
}

/* The encoder_slip shift in counts, 0..cpr-1: angle_e / n_p mechanical,
 * angle_e / n_p * cpr / (2 pi) counts, rounded to the nearest count (half
 * away from zero), mod cpr. The whole mechanical turns are dropped first
 * (fmod is exact and keeps the sign), so any finite angle fits llround. */
static uint32_t slip_counts(double angle_e_rad, uint32_t pole_pairs, uint32_t cpr)
{
    const double turns = fmod(angle_e_rad / (double)pole_pairs / SIM_ENGINE_TWO_PI, 1.0);
    const int64_t n = llround(turns * (double)cpr) % (int64_t)cpr;
    return (uint32_t)(n < 0 ? n + (int64_t)cpr : n);
}

int sim_engine_add_injection(sim_engine_t *e, const sim_injection_t *inj)
{
    if (e == NULL || inj == NULL) {
        return SIM_ENGINE_ERR_NULL;
    }
    if (!e->initialised) {
        return fail(e, SIM_ENGINE_ERR_STATE, "engine is not initialised");
    }
    if (e->n_injections >= SIM_ENGINE_MAX_INJECTIONS) {
        return fail(e, SIM_ENGINE_ERR_INJECTION, "injection table is full");
    }
    const char *problem = kind_field_problem(inj);
    if (problem != NULL) {
        return fail(e, SIM_ENGINE_ERR_INJECTION, problem);
    }
    if (!isfinite(inj->t_start_s) || isnan(inj->t_end_s) || !(inj->t_end_s >= inj->t_start_s)) {
        return fail(e, SIM_ENGINE_ERR_INJECTION, "injection needs a finite start and end >= start");
    }
    if (uses_phase(inj->kind) && inj->phase > 2u) {
        return fail(e, SIM_ENGINE_ERR_INJECTION, "injection phase must be 0..2");
    }
    const uint32_t cpr = engine_mailbox(e)->encoder_cpr;
    if (is_encoder_kind(inj->kind) && cpr == 0u) {
        return fail(e, SIM_ENGINE_ERR_INJECTION,
                    "encoder injections need a plant encoder (sensors.encoder.lines > 0)");
    }
    if (inj->kind == SIM_INJECT_DEAD_TIME && !(inj->value < 0.5 * plant_period_s(&e->plant))) {
        return fail(e, SIM_ENGINE_ERR_INJECTION,
                    "dead_time dead_time_s must be below half a PWM period");
    }
    if (inj->kind == SIM_INJECT_BUS_SOURCE_LOSS && !e->dc_link_capacitive) {
        return fail(e, SIM_ENGINE_ERR_INJECTION,
                    "bus_source_loss needs a DC link capacitance (dc_link.capacitance_F > 0)");
    }
    sim_injection_state_t *st = &e->injection_state[e->n_injections];
    *st = (sim_injection_state_t){ 0 };
    if (inj->kind == SIM_INJECT_ENCODER_SLIP) {
        st->count = slip_counts(inj->angle_e_rad, e->pole_pairs, cpr);
    }
    e->injections[e->n_injections++] = *inj;
    e->message = "ok";
    return SIM_ENGINE_OK;
}

static bool is_active(const sim_injection_t *inj, double t_s)
{
    return t_s >= inj->t_start_s && t_s < inj->t_end_s;
}

/* The plant-side faults for the period from t_s: the normal state with the
 * active plant-side injections applied; sets on the plant what changed.
 * False if the plant refused (plant_error_message). */
static bool set_plant_faults(sim_engine_t *e, double t_s)
{
    sim_plant_faults_t want = e->plant_normal;
    for (uint32_t i = 0u; i < e->n_injections; ++i) {
        const sim_injection_t *inj = &e->injections[i];
        if (!is_active(inj, t_s)) {
            continue;
        }
        switch (inj->kind) {
        case SIM_INJECT_PHASE_OPEN: want.phase_open[inj->phase] = true; break;
        case SIM_INJECT_ROTOR_LOCK: want.rotor_locked = true; break;
        case SIM_INJECT_BUS_SOURCE_LOSS: want.source_connected = false; break;
        case SIM_INJECT_DEAD_TIME: want.t_dead_s = inj->value; break;
        default: break; /* measurement side: apply_injections */
        }
    }
    sim_plant_faults_t *now = &e->plant_faults;
    for (unsigned x = 0u; x < 3u; ++x) {
        if (want.phase_open[x] != now->phase_open[x]) {
            if (plant_set_phase_open(&e->plant, x, want.phase_open[x]) != PLANT_OK) {
                return false;
            }
            now->phase_open[x] = want.phase_open[x];
        }
    }
    if (want.rotor_locked != now->rotor_locked) {
        if (plant_set_rotor_locked(&e->plant, want.rotor_locked) != PLANT_OK) {
            return false;
        }
        now->rotor_locked = want.rotor_locked;
    }
    if (want.source_connected != now->source_connected) {
        if (plant_set_source_connected(&e->plant, want.source_connected) != PLANT_OK) {
            return false;
        }
        now->source_connected = want.source_connected;
    }
    if (want.t_dead_s != now->t_dead_s) {
        if (plant_set_dead_time(&e->plant, want.t_dead_s) != PLANT_OK) {
            return false;
        }
        now->t_dead_s = want.t_dead_s;
    }
    return true;
}

/* ENCODER_COUNT_LOSS: the count it reports for the count it receives. */
static uint32_t lose_counts(const sim_injection_t *inj, sim_injection_state_t *st,
                            uint32_t count_in, uint32_t cpr)
{
    if (!st->started) {
        st->count = count_in;
        st->remainder_counts = 0.0;
    } else {
        /* the increment as the shorter way round: -cpr/2 < delta <= cpr/2 */
        const uint32_t forward = (count_in + cpr - st->count_in) % cpr;
        const int64_t delta = forward > cpr / 2u ? (int64_t)forward - (int64_t)cpr : forward;
        const double kept = st->remainder_counts + (double)delta * (1.0 - inj->lost_fraction);
        const double whole = floor(kept);
        st->remainder_counts = kept - whole; /* exact: |kept| < 2^52 */
        const int64_t count = ((int64_t)st->count + (int64_t)whole) % (int64_t)cpr;
        st->count = (uint32_t)(count < 0 ? count + (int64_t)cpr : count);
    }
    st->count_in = count_in;
    return st->count;
}

/* Apply the injections active at m->t_s; returns their bit mask and sets
 * *fault_input. Counts are below cpr <= 2^30 (plant: lines <= 2^28), so the
 * sum of two does not overflow. */
static uint32_t apply_injections(sim_engine_t *e, plant_measurement_t *m, bool *fault_input)
{
    const uint32_t cpr = engine_mailbox(e)->encoder_cpr;
    uint32_t active = 0u;
    *fault_input = false;
    for (uint32_t i = 0u; i < e->n_injections; ++i) {
        const sim_injection_t *inj = &e->injections[i];
        sim_injection_state_t *st = &e->injection_state[i];
        if (!is_active(inj, m->t_s)) {
            continue;
        }
        active |= 1u << i;
        switch (inj->kind) {
        case SIM_INJECT_CURRENT_NAN: m->i_abc_A[inj->phase] = NAN; break;
        case SIM_INJECT_CURRENT_OFFSET: m->i_abc_A[inj->phase] += inj->value; break;
        case SIM_INJECT_VDC_MEASURED: m->v_dc_V = inj->value; break;
        case SIM_INJECT_FAULT_INPUT: *fault_input = true; break;
        case SIM_INJECT_ENCODER_SLIP:
            m->encoder_count = (m->encoder_count + st->count) % cpr;
            break;
        case SIM_INJECT_ENCODER_FROZEN:
            if (!st->started) {
                st->count = m->encoder_count;
                st->t_edge_s = m->t_s - m->encoder_edge_age_s;
            }
            m->encoder_count = st->count;
            /* no edge since: its age grows */
            m->encoder_edge_age_s = m->t_s - st->t_edge_s;
            break;
        case SIM_INJECT_ENCODER_COUNT_LOSS:
            m->encoder_count = lose_counts(inj, st, m->encoder_count, cpr);
            break;
        case SIM_INJECT_CURRENT_OFFSET_RAMP:
            m->i_abc_A[inj->phase] += inj->rate_A_s * (m->t_s - inj->t_start_s);
            break;
        case SIM_INJECT_CURRENT_STUCK: m->i_abc_A[inj->phase] = inj->value; break;
        case SIM_INJECT_CURRENT_GAIN: m->i_abc_A[inj->phase] *= inj->value; break;
        case SIM_INJECT_PHASE_OPEN:
        case SIM_INJECT_ROTOR_LOCK:
        case SIM_INJECT_BUS_SOURCE_LOSS:
        case SIM_INJECT_DEAD_TIME: break; /* plant side: set_plant_faults */
        }
        st->started = true;
    }
    return active;
}

/* An armed comparator (trip_A > 0) trips on a phase current beyond the
 * level (an infinite one included; NaN does not compare). */
static bool overcurrent(float trip_A, const double i_abc_A[3])
{
    if (!(trip_A > 0.0f)) {
        return false;
    }
    for (unsigned k = 0u; k < 3u; ++k) {
        if (fabs(i_abc_A[k]) > (double)trip_A) {
            return true;
        }
    }
    return false;
}

/* Measurement -> mailbox (the ADC and encoder registers of the host). */
static void fill_mailbox(hal_sim_mailbox_t *mb, const plant_measurement_t *m, bool fault_input)
{
    for (unsigned k = 0u; k < 3u; ++k) {
        mb->adc.i_abc_A[k] = (float)m->i_abc_A[k];
    }
    mb->adc.v_dc_V = (float)m->v_dc_V;
    mb->adc.temp_valid = false;
    mb->encoder_count = m->encoder_count;
    /* the HAL contract's range: an older edge, or none, reads as the maximum */
    mb->encoder_edge_age_s = (float)fmin(m->encoder_edge_age_s, (double)HAL_ENCODER_EDGE_AGE_MAX_S);
    if (m->encoder_index) {
        /* The plant's index mark is at count 0 (see plant.h). */
        mb->encoder_index_seen = true;
        mb->encoder_count_at_index = 0u;
    }
    mb->fault_input_active = fault_input;
    mb->sim_time_ns = (uint64_t)llround(m->t_s * 1.0e9);
}

int sim_engine_step(sim_engine_t *e, const mc_command_t *cmd)
{
    if (e == NULL || (cmd == NULL && !e->can_attached)) {
        return SIM_ENGINE_ERR_NULL;
    }
    if (!e->initialised) {
        return fail(e, SIM_ENGINE_ERR_STATE, "engine is not initialised");
    }
    /* The command first: a rejected one must leave no trace (no PRNG
     * draw, no consumed encoder index, sim_engine_last() unchanged). With
     * a CAN node the node hands its command to the drive in its poll. */
    if (!e->can_attached && mc_app_set_command(&e->app, cmd) != MC_OK) {
        return fail(e, SIM_ENGINE_ERR_COMMAND, "command has an unknown mode");
    }
    if (!set_plant_faults(e, plant_true_state(&e->plant)->t_s)) {
        return fail(e, SIM_ENGINE_ERR_PLANT, plant_error_message(&e->plant));
    }
    sim_trace_sample_t *s = &e->last;
    s->k = e->k;
    s->plant = *plant_true_state(&e->plant);
    s->t_s = s->plant.t_s;

    /* 1-2. Sample at the PWM centre, inject. */
    plant_sample(&e->plant, &s->meas);
    bool fault_input;
    s->injections_active = apply_injections(e, &s->meas, &fault_input);

    /* 3. HAL mailbox, fast ISR. The board's over-current comparators, when
     * the firmware armed them, see the sampled phase currents (a sensor
     * fault included) and stop the outputs by themselves. */
    hal_sim_mailbox_t *mb = engine_mailbox(e);
    fill_mailbox(mb, &s->meas, fault_input);
    mb->oc_active = overcurrent(mb->oc_trip_A, s->meas.i_abc_A);
    s->oc_tripped = mb->oc_active;
    hal_sim_bind(mb);
    /* the command the ISR uses: the one handed over before it */
    s->cmd = e->can_attached ? e->can_node.cmd : *cmd;
    mc_app_fast_isr(&e->app);
    (void)mc_app_get_telemetry(&e->app, &s->fw); /* no concurrency here */
    if (e->can_attached) {
        /* the background loop after the ISR (a parameter write may
         * re-initialise the drive here: engine_apply_config) */
        mc_can_node_poll(&e->can_node, &e->app);
    }
    hal_sim_bind(NULL);

    /* 4. Advance: the previous ISR's duties until the update event, this
     * ISR's after it; enable is delayed like the duties, disable is
     * immediate. */
    const bool outputs_now = hal_sim_outputs_active(mb);
    s->outputs_applied = e->outputs_next && outputs_now;
    for (unsigned k = 0u; k < 3u; ++k) {
        s->duty_applied[k] = e->duty_next[k];
        e->duty_next[k] = (double)mb->duty_abc[k];
    }
    if (e->half_period_update) {
        plant_advance_split(&e->plant, s->duty_applied, s->outputs_applied, e->duty_next,
                            outputs_now);
    } else {
        plant_advance(&e->plant, s->duty_applied, s->outputs_applied);
    }
    e->outputs_next = outputs_now;
    e->k++;
    e->message = "ok";
    return SIM_ENGINE_OK;
}

const sim_trace_sample_t *sim_engine_last(const sim_engine_t *e)
{
    return &e->last;
}

double sim_engine_time_s(const sim_engine_t *e)
{
    return (double)e->k * plant_period_s(&e->plant);
}

double sim_engine_period_s(const sim_engine_t *e)
{
    return plant_period_s(&e->plant);
}

/* The CAN node's apply callback (mc_can_apply_config_fn): runs inside
 * mc_can_node_poll, after the ISR of this step and before the plant
 * advances, with the engine's mailbox bound and no ISR possible (one
 * thread), so the drive is never seen half initialised; the next ISR runs
 * on the re-initialised drive. The node has validated cfg and checked that
 * the drive is stopped; the engine checks again what it needs (stopped,
 * the plant's PWM rate and encoder resolution). The engine owns the
 * mc_app_t, so it may copy it back whole after a refused mc_app_init. */
static mc_status_t engine_apply_config(void *ctx, const mc_config_t *cfg)
{
    sim_engine_t *e = ctx;
    mc_telemetry_t tlm;
    if (mc_app_get_telemetry(&e->app, &tlm) != MC_OK ||
        (tlm.state != MC_STATE_IDLE && tlm.state != MC_STATE_FAULT)) {
        return MC_ERR_STATE;
    }
    hal_sim_mailbox_t *mb = engine_mailbox(e);
    if (firmware_mismatch(cfg, (double)mb->pwm_f_Hz, mb->encoder_cpr) != NULL ||
        cfg->timing.telemetry_every_isr != e->fw_cfg.timing.telemetry_every_isr) {
        return MC_ERR_PARAM; /* the rate of the record the bench reads stays */
    }
    /* the drive exactly as it is (state, latched faults, history) and the
     * firmware's HAL outputs, to put back if mc_app_init refuses cfg */
    const mc_app_t before = e->app;
    const float duty[3] = { mb->duty_abc[0], mb->duty_abc[1], mb->duty_abc[2] };
    const bool pwm_on = mb->pwm_outputs_enabled;
    const bool stage_on = mb->power_stage_enabled;
    const mc_status_t st = mc_app_init(&e->app, cfg);
    if (st != MC_OK) {
        e->app = before;
        for (unsigned k = 0u; k < 3u; ++k) {
            mb->duty_abc[k] = duty[k];
        }
        mb->pwm_outputs_enabled = pwm_on;
        mb->power_stage_enabled = stage_on;
        return st;
    }
    e->fw_cfg = *cfg;
    return MC_OK;
}

int sim_engine_can_attach(sim_engine_t *e, const mc_can_node_config_t *cfg)
{
    if (e == NULL || cfg == NULL) {
        return SIM_ENGINE_ERR_NULL;
    }
    if (!e->initialised) {
        return fail(e, SIM_ENGINE_ERR_STATE, "engine is not initialised");
    }
    if (e->can_attached) {
        return fail(e, SIM_ENGINE_ERR_STATE, "a CAN node is attached already");
    }
    hal_sim_mailbox_t *mb = engine_mailbox(e);
    hal_sim_bind(mb);
    const bool was_up = mb->can_up;
    const uint32_t bitrate = mb->can_bitrate_bps;
    int code = SIM_ENGINE_OK;
    if (hal_can_init(SIM_ENGINE_CAN_BITRATE_BPS) != HAL_OK) {
        code = fail(e, SIM_ENGINE_ERR_CAN, "hal_can_init refused 1 Mbit/s");
    } else if (mc_can_node_init(&e->can_node, cfg, &e->fw_cfg, engine_apply_config, e) != MC_OK) {
        mb->can_up = was_up; /* nothing changes */
        mb->can_bitrate_bps = bitrate;
        code = fail(e, SIM_ENGINE_ERR_CAN,
                    "CAN node configuration rejected by mc_can_node_init (node_id 0..63, "
                    "timeout_s in (0, 60])");
    }
    hal_sim_bind(NULL);
    if (code != SIM_ENGINE_OK) {
        return code;
    }
    e->can_attached = true;
    e->message = "ok";
    return SIM_ENGINE_OK;
}

bool sim_engine_can_deliver(sim_engine_t *e, const hal_can_frame_t *f)
{
    if (e == NULL || f == NULL || !e->can_attached) {
        return false;
    }
    if (!hal_can_frame_valid(f)) {
        return false;
    }
    return hal_sim_can_deliver(engine_mailbox(e), f);
}

bool sim_engine_can_collect(sim_engine_t *e, hal_can_frame_t *f)
{
    if (e == NULL || f == NULL || !e->can_attached) {
        return false;
    }
    return hal_sim_can_collect(engine_mailbox(e), f);
}

void sim_engine_can_count_link_events(sim_engine_t *e, uint32_t rx_overruns, uint32_t bus_errors)
{
    if (e == NULL || !e->can_attached) {
        return;
    }
    hal_can_stats_t *st = &engine_mailbox(e)->can_stats;
    st->rx_overruns += rx_overruns; /* wrapping, as hal/can.h says */
    st->bus_errors += bus_errors;
}

const mc_can_node_t *sim_engine_can_node(const sim_engine_t *e)
{
    return (e != NULL && e->can_attached) ? &e->can_node : NULL;
}
