/* Closed-loop simulation engine (see sim_engine.h). */
#include "sim_engine.h"

#include <math.h>
#include <stddef.h>

/* Relative tolerance of the plant / firmware PWM frequency agreement
 * (the firmware holds it in float). */
#define SIM_ENGINE_F_PWM_REL_TOL 1.0e-6

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
    fw->encoder.counts_per_rev = 4u * plant->sensors.encoder.lines;
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
    if (!(fabs((double)fw_cfg->timing.f_pwm_Hz - f_plant) <= SIM_ENGINE_F_PWM_REL_TOL * f_plant)) {
        return fail(e, SIM_ENGINE_ERR_MISMATCH,
                    "firmware timing.f_pwm_Hz differs from the plant's f_pwm_Hz");
    }
    const uint32_t cpr = 4u * plant_cfg->sensors.encoder.lines;
    const uint32_t fw_cpr = mc_config_estimator_info(fw_cfg).encoder_cpr;
    if (fw_cpr != 0u && fw_cpr != cpr) {
        return fail(e, SIM_ENGINE_ERR_MISMATCH,
                    "firmware encoder.counts_per_rev differs from 4 x plant encoder lines");
    }
    /* plant_init checked that the half-period update has even substeps */
    const bool half = plant_cfg->inverter.duty_update == PLANT_DUTY_UPDATE_HALF_PERIOD;
    e->half_period_update = half;
    hal_sim_mailbox_reset(&e->mailbox);
    e->mailbox.encoder_cpr = cpr;
    e->mailbox.pwm_f_Hz = (float)f_plant;
    e->mailbox.pwm_delay_periods =
        half ? SIM_ENGINE_DELAY_HALF_PERIOD : SIM_ENGINE_DELAY_NEXT_PERIOD;
    hal_sim_bind(&e->mailbox);
    const mc_status_t st = mc_app_init(&e->app, fw_cfg);
    hal_sim_bind(NULL);
    if (st != MC_OK) {
        return fail(e, SIM_ENGINE_ERR_FIRMWARE, "firmware config rejected by mc_app_init");
    }
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

int sim_engine_add_injection(sim_engine_t *e, const sim_injection_t *inj)
{
    if (e == NULL || inj == NULL) {
        return SIM_ENGINE_ERR_NULL;
    }
    if (e->n_injections >= SIM_ENGINE_MAX_INJECTIONS) {
        return fail(e, SIM_ENGINE_ERR_INJECTION, "injection table is full");
    }
    const bool is_current =
        inj->kind == SIM_INJECT_CURRENT_NAN || inj->kind == SIM_INJECT_CURRENT_OFFSET;
    const bool known =
        is_current || inj->kind == SIM_INJECT_VDC_MEASURED || inj->kind == SIM_INJECT_FAULT_INPUT;
    if (!known) {
        return fail(e, SIM_ENGINE_ERR_INJECTION, "unknown injection kind");
    }
    if (!isfinite(inj->t_start_s) || isnan(inj->t_end_s) || !(inj->t_end_s >= inj->t_start_s)) {
        return fail(e, SIM_ENGINE_ERR_INJECTION, "injection needs a finite start and end >= start");
    }
    if (is_current && inj->phase > 2u) {
        return fail(e, SIM_ENGINE_ERR_INJECTION, "injection phase must be 0..2");
    }
    if (inj->kind != SIM_INJECT_CURRENT_NAN && inj->kind != SIM_INJECT_FAULT_INPUT &&
        !isfinite(inj->value)) {
        return fail(e, SIM_ENGINE_ERR_INJECTION, "injection value must be finite");
    }
    e->injections[e->n_injections++] = *inj;
    e->message = "ok";
    return SIM_ENGINE_OK;
}

/* Apply the injections active at m->t_s; returns their bit mask and sets
 * *fault_input. */
static uint32_t apply_injections(const sim_engine_t *e, plant_measurement_t *m, bool *fault_input)
{
    uint32_t active = 0u;
    *fault_input = false;
    for (uint32_t i = 0u; i < e->n_injections; ++i) {
        const sim_injection_t *inj = &e->injections[i];
        if (!(m->t_s >= inj->t_start_s && m->t_s < inj->t_end_s)) {
            continue;
        }
        active |= 1u << i;
        switch (inj->kind) {
        case SIM_INJECT_CURRENT_NAN: m->i_abc_A[inj->phase] = NAN; break;
        case SIM_INJECT_CURRENT_OFFSET: m->i_abc_A[inj->phase] += inj->value; break;
        case SIM_INJECT_VDC_MEASURED: m->v_dc_V = inj->value; break;
        case SIM_INJECT_FAULT_INPUT:
        default: *fault_input = true; break;
        }
    }
    return active;
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
    if (e == NULL || cmd == NULL) {
        return SIM_ENGINE_ERR_NULL;
    }
    if (!e->initialised) {
        return fail(e, SIM_ENGINE_ERR_STATE, "engine is not initialised");
    }
    /* The command first: a rejected one must leave no trace (no PRNG
     * draw, no consumed encoder index, sim_engine_last() unchanged). */
    if (mc_app_set_command(&e->app, cmd) != MC_OK) {
        return fail(e, SIM_ENGINE_ERR_COMMAND, "command has an unknown mode");
    }
    sim_trace_sample_t *s = &e->last;
    s->k = e->k;
    s->plant = *plant_true_state(&e->plant);
    s->t_s = s->plant.t_s;

    /* 1-2. Sample at the PWM centre, inject. */
    plant_sample(&e->plant, &s->meas);
    bool fault_input;
    s->injections_active = apply_injections(e, &s->meas, &fault_input);

    /* 3. HAL mailbox, fast ISR. */
    fill_mailbox(&e->mailbox, &s->meas, fault_input);
    hal_sim_bind(&e->mailbox);
    mc_app_fast_isr(&e->app);
    (void)mc_app_get_telemetry(&e->app, &s->fw); /* no concurrency here */
    hal_sim_bind(NULL);
    s->cmd = *cmd;

    /* 4. Advance: the previous ISR's duties until the update event, this
     * ISR's after it; enable is delayed like the duties, disable is
     * immediate. */
    const bool outputs_now = hal_sim_outputs_active(&e->mailbox);
    s->outputs_applied = e->outputs_next && outputs_now;
    for (unsigned k = 0u; k < 3u; ++k) {
        s->duty_applied[k] = e->duty_next[k];
        e->duty_next[k] = (double)e->mailbox.duty_abc[k];
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
