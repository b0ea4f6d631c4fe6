#include <math.h>
#include <stddef.h>
#include <string.h>

#include "plant.h"

void plant_config_default(plant_config_t *cfg)
{
    memset(cfg, 0, sizeof *cfg);
    plant_motor_params_t *m = &cfg->motor; /* paper 001, section 5 */
    m->R_ohm = 0.225;
    m->Ld_H = 3.8e-3;
    m->Lq_H = 3.8e-3;
    m->psi_Wb = 0.17;
    m->pole_pairs = 3u;
    m->J_kgm2 = 0.012;
    cfg->mismatch = (plant_mismatch_t){ .R = 1.0, .L = 1.0, .psi = 1.0, .J = 1.0 };
    cfg->inverter.f_pwm_Hz = PLANT_DEFAULT_F_PWM_HZ;
    sim_profile_set_constant(&cfg->inverter.v_dc_V, 48.0);
    for (int x = 0; x < 3; ++x) {
        cfg->sensors.current.gain[x] = 1.0;
    }
    cfg->sensors.vdc.gain = 1.0;
    cfg->sensors.encoder.lines = 2500u;
    cfg->sensors.seed = 1u;
    sim_profile_clear(&cfg->load_torque_Nm);
    cfg->substeps_per_period = PLANT_DEFAULT_SUBSTEPS;
    cfg->solver_method = PLANT_SOLVER_EXACT;
}

#define ADC_MAX_BITS      24u
#define ENCODER_MAX_LINES (1u << 28)
#define POLE_PAIRS_MAX    256u
#define SUBSTEPS_MAX      100000u

static int fail(const char **msg, int code, const char *text)
{
    if (msg != NULL) {
        *msg = text;
    }
    return code;
}

static bool finite_ge0(double v)
{
    return isfinite(v) && v >= 0.0;
}
static bool finite_gt0(double v)
{
    return isfinite(v) && v > 0.0;
}

static int validate_cogging(const plant_cogging_t *c, const char **msg)
{
    if (c->n_harmonics > PLANT_MAX_COG_HARMONICS) {
        return fail(msg, PLANT_ERR_MOTOR, "cogging.n_harmonics exceeds PLANT_MAX_COG_HARMONICS");
    }
    if (c->n_harmonics > 0u && c->slots == 0u) {
        return fail(msg, PLANT_ERR_MOTOR, "cogging.slots must be >= 1 when harmonics are given");
    }
    for (uint32_t k = 0; k < c->n_harmonics; ++k) {
        if (!isfinite(c->amplitude_Nm[k]) || !isfinite(c->phase_rad[k])) {
            return fail(msg, PLANT_ERR_MOTOR, "cogging amplitude or phase is not finite");
        }
    }
    return PLANT_OK;
}

static int validate_motor(const plant_motor_params_t *m, const plant_mismatch_t *mm,
                          const char **msg)
{
    if (!finite_ge0(m->R_ohm))
        return fail(msg, PLANT_ERR_MOTOR, "motor.R_ohm must be finite and >= 0");
    if (!finite_gt0(m->Ld_H))
        return fail(msg, PLANT_ERR_MOTOR, "motor.Ld_H must be finite and > 0");
    if (!finite_gt0(m->Lq_H))
        return fail(msg, PLANT_ERR_MOTOR, "motor.Lq_H must be finite and > 0");
    if (!finite_ge0(m->psi_Wb))
        return fail(msg, PLANT_ERR_MOTOR, "motor.psi_Wb must be finite and >= 0");
    if (m->pole_pairs == 0u || m->pole_pairs > POLE_PAIRS_MAX) {
        return fail(msg, PLANT_ERR_MOTOR, "motor.pole_pairs must be in 1..256");
    }
    if (!finite_gt0(m->J_kgm2))
        return fail(msg, PLANT_ERR_MOTOR, "motor.J_kgm2 must be finite and > 0");
    if (!finite_ge0(m->B_Nm_s_rad))
        return fail(msg, PLANT_ERR_MOTOR, "motor.B_Nm_s_rad must be finite and >= 0");
    if (!finite_ge0(m->tau_coulomb_Nm)) {
        return fail(msg, PLANT_ERR_MOTOR, "motor.tau_coulomb_Nm must be finite and >= 0");
    }
    if (m->tau_coulomb_Nm > 0.0 && !finite_gt0(m->coulomb_eps_rad_s)) {
        return fail(msg, PLANT_ERR_MOTOR,
                    "motor.coulomb_eps_rad_s must be finite and > 0 with Coulomb friction");
    }
    if (!isfinite(m->g3_amplitude_per_kgm2) || !finite_ge0(m->g3_omega_rad_s)) {
        return fail(msg, PLANT_ERR_MOTOR, "motor.g3 amplitude/omega must be finite (omega >= 0)");
    }
    if (fabs(m->g3_amplitude_per_kgm2) >= 1.0 / (m->J_kgm2 * mm->J)) {
        return fail(msg, PLANT_ERR_MOTOR,
                    "motor.g3_amplitude_per_kgm2 must be below 1/J so g3 stays > 0");
    }
    return validate_cogging(&m->cogging, msg);
}

static int validate_mismatch(const plant_mismatch_t *mm, const char **msg)
{
    if (!finite_gt0(mm->R) || !finite_gt0(mm->L) || !finite_gt0(mm->psi) || !finite_gt0(mm->J)) {
        return fail(msg, PLANT_ERR_MISMATCH, "mismatch multipliers must be finite and > 0");
    }
    return PLANT_OK;
}

static int validate_inverter(const plant_inverter_params_t *inv, const char **msg)
{
    if (!finite_gt0(inv->f_pwm_Hz))
        return fail(msg, PLANT_ERR_INVERTER, "inverter.f_pwm_Hz must be finite and > 0");
    if (inv->duty_update != PLANT_DUTY_UPDATE_NEXT_PERIOD &&
        inv->duty_update != PLANT_DUTY_UPDATE_HALF_PERIOD) {
        return fail(msg, PLANT_ERR_INVERTER, "inverter.duty_update is not a plant_duty_update_t");
    }
    if (!finite_ge0(inv->t_dead_s) || inv->t_dead_s * inv->f_pwm_Hz >= 0.5) {
        return fail(msg, PLANT_ERR_INVERTER,
                    "inverter.t_dead_s must be >= 0 and below half a PWM period");
    }
    if (!finite_ge0(inv->v_device_drop_V)) {
        return fail(msg, PLANT_ERR_INVERTER, "inverter.v_device_drop_V must be finite and >= 0");
    }
    if (!finite_ge0(inv->dead_time_current_band_A)) {
        return fail(msg, PLANT_ERR_INVERTER,
                    "inverter.dead_time_current_band_A must be finite and >= 0");
    }
    if (sim_profile_validate(&inv->v_dc_V, NULL) != SIM_PROFILE_OK) {
        return fail(msg, PLANT_ERR_PROFILE,
                    "inverter.v_dc_V: invalid profile (sim_profile_validate says why)");
    }
    return PLANT_OK;
}

static int validate_dc_link(const plant_dc_link_t *l, const char **msg)
{
    if (!finite_ge0(l->capacitance_F)) {
        return fail(msg, PLANT_ERR_DC_LINK, "dc_link.capacitance_F must be finite and >= 0");
    }
    if (l->capacitance_F == 0.0) { /* stiff bus: nothing else applies */
        if (l->source_resistance_ohm != 0.0 || l->brake_resistance_ohm != 0.0 ||
            l->brake_on_V != 0.0 || l->brake_off_V != 0.0 || l->v0_given) {
            return fail(msg, PLANT_ERR_DC_LINK,
                        "dc_link: source_resistance_ohm, the brake and v0_V need "
                        "capacitance_F > 0 (0 is a stiff bus)");
        }
        return PLANT_OK;
    }
    if (!finite_gt0(l->source_resistance_ohm)) {
        return fail(msg, PLANT_ERR_DC_LINK,
                    "dc_link.source_resistance_ohm must be finite and > 0 with a capacitance");
    }
    if (!finite_ge0(l->brake_resistance_ohm)) {
        return fail(msg, PLANT_ERR_DC_LINK, "dc_link.brake_resistance_ohm must be finite and >= 0");
    }
    if (l->brake_resistance_ohm > 0.0) {
        if (!finite_gt0(l->brake_on_V) || !finite_ge0(l->brake_off_V)) {
            return fail(msg, PLANT_ERR_DC_LINK,
                        "dc_link: brake_on_V must be finite and > 0, brake_off_V finite and >= 0");
        }
        if (!(l->brake_off_V < l->brake_on_V)) {
            return fail(msg, PLANT_ERR_DC_LINK,
                        "dc_link.brake_off_V must be below brake_on_V (the chopper's hysteresis)");
        }
    } else if (l->brake_on_V != 0.0 || l->brake_off_V != 0.0) {
        return fail(msg, PLANT_ERR_DC_LINK,
                    "dc_link: brake_on_V / brake_off_V need brake_resistance_ohm > 0");
    }
    if (l->v0_given && !finite_ge0(l->v0_V)) {
        return fail(msg, PLANT_ERR_DC_LINK, "dc_link.v0_V must be finite and >= 0");
    }
    if (!l->v0_given && l->v0_V != 0.0) {
        return fail(msg, PLANT_ERR_DC_LINK, "dc_link.v0_V is set but v0_given is false");
    }
    return PLANT_OK;
}

static int validate_sensors(const plant_sensor_params_t *s, const char **msg)
{
    const plant_current_sensor_t *c = &s->current;
    for (int x = 0; x < 3; ++x) {
        if (!isfinite(c->gain[x]) || !isfinite(c->offset_A[x])) {
            return fail(msg, PLANT_ERR_SENSOR, "sensors.current gain/offset must be finite");
        }
    }
    if (!finite_ge0(c->noise_rms_A))
        return fail(msg, PLANT_ERR_SENSOR, "sensors.current.noise_rms_A must be finite and >= 0");
    if (c->adc_bits > ADC_MAX_BITS || (c->adc_bits > 0u && !finite_gt0(c->full_scale_A))) {
        return fail(msg, PLANT_ERR_SENSOR,
                    "sensors.current: adc_bits must be 0..24 with full_scale_A > 0");
    }
    const plant_vdc_sensor_t *v = &s->vdc;
    if (!isfinite(v->gain) || !isfinite(v->offset_V) || !finite_ge0(v->noise_rms_V)) {
        return fail(msg, PLANT_ERR_SENSOR,
                    "sensors.vdc gain/offset/noise must be finite (noise >= 0)");
    }
    if (v->adc_bits > ADC_MAX_BITS || (v->adc_bits > 0u && !finite_gt0(v->full_scale_V))) {
        return fail(msg, PLANT_ERR_SENSOR,
                    "sensors.vdc: adc_bits must be 0..24 with full_scale_V > 0");
    }
    if (s->encoder.lines > ENCODER_MAX_LINES || !isfinite(s->encoder.offset_rad)) {
        return fail(msg, PLANT_ERR_SENSOR, "sensors.encoder: lines <= 2^28 and a finite offset");
    }
    return PLANT_OK;
}

int plant_config_validate(const plant_config_t *cfg, const char **msg)
{
    if (cfg == NULL) {
        return fail(msg, PLANT_ERR_NULL, "config is NULL");
    }
    int rc = validate_mismatch(&cfg->mismatch, msg);
    if (rc == PLANT_OK)
        rc = validate_motor(&cfg->motor, &cfg->mismatch, msg);
    if (rc == PLANT_OK)
        rc = validate_inverter(&cfg->inverter, msg);
    if (rc == PLANT_OK)
        rc = validate_dc_link(&cfg->dc_link, msg);
    if (rc == PLANT_OK)
        rc = validate_sensors(&cfg->sensors, msg);
    if (rc == PLANT_OK && sim_profile_validate(&cfg->load_torque_Nm, NULL) != SIM_PROFILE_OK) {
        rc = fail(msg, PLANT_ERR_PROFILE,
                  "load_torque_Nm: invalid profile (sim_profile_validate says why)");
    }
    if (rc == PLANT_OK &&
        (cfg->substeps_per_period == 0u || cfg->substeps_per_period > SUBSTEPS_MAX)) {
        rc = fail(msg, PLANT_ERR_SOLVER, "substeps_per_period must be in 1..100000");
    }
    if (rc == PLANT_OK && cfg->solver_method != PLANT_SOLVER_EXACT &&
        cfg->solver_method != PLANT_SOLVER_RK4) {
        rc = fail(msg, PLANT_ERR_SOLVER, "solver_method is not a plant_solver_method_t");
    }
    if (rc == PLANT_OK && cfg->inverter.duty_update == PLANT_DUTY_UPDATE_HALF_PERIOD &&
        cfg->substeps_per_period % 2u != 0u) {
        rc = fail(msg, PLANT_ERR_SOLVER,
                  "substeps_per_period must be even with the half-period duty update");
    }
    if (rc == PLANT_OK && (!isfinite(cfg->theta_m0_rad) || !isfinite(cfg->omega_m0_rad_s))) {
        rc = fail(msg, PLANT_ERR_SOLVER, "initial theta_m0_rad / omega_m0_rad_s must be finite");
    }
    if (rc == PLANT_OK && msg != NULL) {
        *msg = "ok";
    }
    return rc;
}
