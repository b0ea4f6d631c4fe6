/* Scenario sections that configure the plant: motor, inverter, sensors,
 * disturbances, initial state and solver. Absent optional keys keep the
 * values of plant_config_default(). */
#include <stdio.h>

#include "mc/encoder_tracker.h"
#include "mc/motor.h"
#include "mc/timing.h"
#include "motor_convention.h"
#include "profile_reader.h"
#include "scenario_sections.h"

/* Optional array of three numbers (per phase); absent keeps out[]. */
static bool read_per_phase(jr_object_t *obj, const char *key, jr_range_t range, double out[3])
{
    jr_array_t arr;
    if (!jr_array_opt(obj, key, 3, 3, &arr)) {
        return false;
    }
    for (size_t i = 0; i < arr.size; i++) {
        if (!jr_array_number(&arr, i, range, &out[i])) {
            return false;
        }
    }
    return true;
}

/* motor: the parameters in the frame "convention" names
 * (motor_convention.h), converted once here to the plant's. */
static bool read_motor(jr_object_t *root, plant_motor_params_t *m)
{
    static const char *const conventions[] = { "amplitude_invariant", "power_invariant" };
    jr_object_t o;
    uint64_t pole_pairs;
    size_t convention;
    bool ok =
        jr_object(root, "motor", &o) &&
        jr_enum_opt(&o, "convention", conventions, 2, PLANT_AMPLITUDE_INVARIANT, &convention) &&
        jr_number(&o, "R_ohm", JR_POSITIVE(1e3), &m->R_ohm) &&
        jr_number(&o, "Ld_H", JR_POSITIVE(10.0), &m->Ld_H) &&
        jr_number_opt(&o, "Lq_H", JR_POSITIVE(10.0), m->Ld_H, &m->Lq_H) &&
        jr_number(&o, "psi_Wb", JR_POSITIVE(10.0), &m->psi_Wb) &&
        jr_uint(&o, "pole_pairs", 1, MC_MOTOR_POLE_PAIRS_MAX, &pole_pairs) &&
        jr_number(&o, "J_kgm2", JR_POSITIVE(1e3), &m->J_kgm2) &&
        jr_number_opt(&o, "B_Nm_s_rad", JR_CLOSED(0.0, 1e3), 0.0, &m->B_Nm_s_rad) && jr_finish(&o);
    if (ok) {
        m->pole_pairs = (uint32_t)pole_pairs;
        plant_motor_to_amplitude_invariant(m, (plant_motor_convention_t)convention);
    }
    return ok;
}

/* When the inverter latches new duties (plant_duty_update_t). */
static bool read_duty_update(jr_object_t *o, plant_duty_update_t *update)
{
    static const char *const names[] = { "next_period", "half_period" };
    size_t index;
    if (!jr_enum_opt(o, "duty_update", names, 2, (size_t)*update, &index)) {
        return false;
    }
    *update = (plant_duty_update_t)index;
    return true;
}

/* A number key of obj that applies only under a condition that does not
 * hold: present, it is an error at its path (expected says when it
 * applies); absent, it is still listed among the object's keys. */
static bool refuse_key(jr_object_t *obj, const char *key, const char *expected)
{
    const cJSON *item = jr_peek(obj, key);
    if (item == NULL) {
        double unused;
        return jr_number_opt(obj, key, JR_ANY_FINITE, 0.0, &unused);
    }
    char found[SCN_TEXT_MAX];
    jr_describe(item, found, sizeof(found));
    jr_fail(obj, key, SCN_ERR_INVALID, expected, found);
    return false;
}

/* The brake chopper of a capacitive link: brake_resistance_ohm > 0 needs
 * brake_on_V and brake_off_V < brake_on_V; without it they are refused. */
static bool read_brake(jr_object_t *o, plant_dc_link_t *l)
{
    if (!jr_number_opt(o, "brake_resistance_ohm", JR_CLOSED(0.0, 1e4), l->brake_resistance_ohm,
                       &l->brake_resistance_ohm)) {
        return false;
    }
    if (l->brake_resistance_ohm == 0.0) {
        static const char only_with_brake[] = "only with brake_resistance_ohm > 0 (a brake)";
        return refuse_key(o, "brake_on_V", only_with_brake) &&
               refuse_key(o, "brake_off_V", only_with_brake);
    }
    if (!jr_number(o, "brake_on_V", JR_POSITIVE(1e5), &l->brake_on_V) ||
        !jr_number(o, "brake_off_V", JR_CLOSED(0.0, 1e5), &l->brake_off_V)) {
        return false;
    }
    if (!(l->brake_off_V < l->brake_on_V)) {
        char expected[96];
        char found[32];
        snprintf(expected, sizeof(expected),
                 "below brake_on_V = %g V (the chopper's hysteresis: off below, on above)",
                 l->brake_on_V);
        snprintf(found, sizeof(found), "%g", l->brake_off_V);
        jr_fail(o, "brake_off_V", SCN_ERR_INVALID, expected, found);
        return false;
    }
    return true;
}

/* inverter.dc_link (plant_dc_link_t): absent or capacitance_F 0, the stiff
 * bus that follows inverter.v_dc_V, and no other key applies; with a
 * capacitance, v_dc_V is the source behind source_resistance_ohm. */
static bool read_dc_link(jr_object_t *inv, plant_dc_link_t *l)
{
    jr_object_t o;
    if (!jr_object_opt(inv, "dc_link", &o) ||
        !jr_number_opt(&o, "capacitance_F", JR_CLOSED(0.0, 100.0), l->capacitance_F,
                       &l->capacitance_F)) {
        return false;
    }
    if (l->capacitance_F == 0.0) {
        static const char *const keys[] = { "source_resistance_ohm", "brake_resistance_ohm",
                                            "brake_on_V", "brake_off_V", "v0_V" };
        for (size_t i = 0; i < sizeof(keys) / sizeof(keys[0]); i++) {
            if (!refuse_key(&o, keys[i], "only with capacitance_F > 0 (0 is a stiff bus)")) {
                return false;
            }
        }
        return jr_finish(&o);
    }
    if (!jr_number(&o, "source_resistance_ohm", JR_POSITIVE(1e3), &l->source_resistance_ohm) ||
        !read_brake(&o, l)) {
        return false;
    }
    l->v0_given = jr_peek(&o, "v0_V") != NULL; /* absent: the source voltage at t = 0 */
    return jr_number_opt(&o, "v0_V", JR_CLOSED(0.0, 1e5), l->v0_V, &l->v0_V) && jr_finish(&o);
}

static bool read_inverter(jr_object_t *root, plant_config_t *plant)
{
    jr_object_t o;
    plant_inverter_params_t *inv = &plant->inverter;
    return jr_object_opt(root, "inverter", &o) &&
           jr_number_opt(&o, "f_pwm_Hz", JR_CLOSED(MC_TIMING_F_PWM_MIN_HZ, MC_TIMING_F_PWM_MAX_HZ),
                         inv->f_pwm_Hz, &inv->f_pwm_Hz) &&
           read_duty_update(&o, &inv->duty_update) &&
           profile_read(&o, "v_dc_V", false, 1.0, &inv->v_dc_V) &&
           jr_number_opt(&o, "dead_time_s", JR_CLOSED(0.0, 1e-4), inv->t_dead_s, &inv->t_dead_s) &&
           jr_number_opt(&o, "device_drop_V", JR_CLOSED(0.0, 100.0), inv->v_device_drop_V,
                         &inv->v_device_drop_V) &&
           jr_number_opt(&o, "dead_time_current_band_A", JR_CLOSED(0.0, 1e3),
                         inv->dead_time_current_band_A, &inv->dead_time_current_band_A) &&
           jr_bool_opt(&o, "overcurrent_comparator", inv->overcurrent_comparator,
                       &inv->overcurrent_comparator) &&
           read_dc_link(&o, &plant->dc_link) && jr_finish(&o);
}

static bool read_current_sensor(jr_object_t *sensors, plant_current_sensor_t *c)
{
    jr_object_t o;
    return jr_object_opt(sensors, "current", &o) &&
           read_per_phase(&o, "gain", JR_POSITIVE(10.0), c->gain) &&
           read_per_phase(&o, "offset_A", JR_CLOSED(-1e3, 1e3), c->offset_A) &&
           jr_number_opt(&o, "noise_rms_A", JR_CLOSED(0.0, 1e3), c->noise_rms_A, &c->noise_rms_A) &&
           jr_u32_opt(&o, "adc_bits", 0, 24, c->adc_bits, &c->adc_bits) &&
           jr_number_opt(&o, "full_scale_A", JR_POSITIVE(1e5), c->full_scale_A, &c->full_scale_A) &&
           jr_finish(&o);
}

static bool read_vdc_sensor(jr_object_t *sensors, plant_vdc_sensor_t *v)
{
    jr_object_t o;
    return jr_object_opt(sensors, "vdc", &o) &&
           jr_number_opt(&o, "gain", JR_POSITIVE(10.0), v->gain, &v->gain) &&
           jr_number_opt(&o, "offset_V", JR_CLOSED(-1e4, 1e4), v->offset_V, &v->offset_V) &&
           jr_number_opt(&o, "noise_rms_V", JR_CLOSED(0.0, 1e4), v->noise_rms_V, &v->noise_rms_V) &&
           jr_u32_opt(&o, "adc_bits", 0, 24, v->adc_bits, &v->adc_bits) &&
           jr_number_opt(&o, "full_scale_V", JR_POSITIVE(1e5), v->full_scale_V, &v->full_scale_V) &&
           jr_finish(&o);
}

static bool read_sensors(jr_object_t *root, plant_sensor_params_t *s)
{
    jr_object_t o;
    jr_object_t enc;
    return jr_object_opt(root, "sensors", &o) && read_current_sensor(&o, &s->current) &&
           read_vdc_sensor(&o, &s->vdc) && jr_object_opt(&o, "encoder", &enc) &&
           jr_u32_opt(&enc, "lines", 0, SCENARIO_ENCODER_LINES_MAX, s->encoder.lines,
                      &s->encoder.lines) &&
           jr_number_opt(&enc, "offset_rad", JR_CLOSED(-1e3, 1e3), s->encoder.offset_rad,
                         &s->encoder.offset_rad) &&
           jr_finish(&enc) && jr_uint_opt(&o, "seed", 0, UINT32_MAX, s->seed, &s->seed) &&
           jr_finish(&o);
}

static bool read_cogging(jr_object_t *dist, plant_cogging_t *cog)
{
    jr_object_t o;
    jr_array_t harmonics;
    if (!jr_object_opt(dist, "cogging", &o) || o.json == NULL) {
        return jr_ok(dist);
    }
    if (!jr_u32_opt(&o, "slots", 1, 1000, cog->slots, &cog->slots) ||
        !jr_array(&o, "harmonics", 1, PLANT_MAX_COG_HARMONICS, &harmonics)) {
        return false;
    }
    for (size_t k = 0; k < harmonics.size; k++) {
        jr_object_t h;
        if (!jr_array_object(&harmonics, k, &h) ||
            !jr_number(&h, "amplitude_Nm", JR_CLOSED(-1e3, 1e3), &cog->amplitude_Nm[k]) ||
            !jr_number_opt(&h, "phase_rad", JR_CLOSED(-1e3, 1e3), 0.0, &cog->phase_rad[k]) ||
            !jr_finish(&h)) {
            return false;
        }
    }
    cog->n_harmonics = (uint32_t)harmonics.size;
    return jr_finish(&o);
}

static bool read_mismatch(jr_object_t *dist, plant_mismatch_t *mm)
{
    jr_object_t o;
    return jr_object_opt(dist, "mismatch", &o) &&
           jr_number_opt(&o, "R", JR_POSITIVE(100.0), mm->R, &mm->R) &&
           jr_number_opt(&o, "L", JR_POSITIVE(100.0), mm->L, &mm->L) &&
           jr_number_opt(&o, "psi", JR_POSITIVE(100.0), mm->psi, &mm->psi) &&
           jr_number_opt(&o, "J", JR_POSITIVE(100.0), mm->J, &mm->J) && jr_finish(&o);
}

/* Paper 000 Section 6: g3 = 1/J + A sin(Omega t) with |A| < 1/J. */
static bool read_inertia_variation(jr_object_t *dist, plant_config_t *plant)
{
    jr_object_t o;
    plant_motor_params_t *m = &plant->motor;
    if (!jr_object_opt(dist, "inertia_variation", &o) ||
        !jr_number_opt(&o, "g3_amplitude_per_kgm2", JR_ANY_FINITE, m->g3_amplitude_per_kgm2,
                       &m->g3_amplitude_per_kgm2) ||
        !jr_number_opt(&o, "omega_rad_s", JR_CLOSED(0.0, 1e6), m->g3_omega_rad_s,
                       &m->g3_omega_rad_s) ||
        !jr_finish(&o)) {
        return false;
    }
    double inv_J = 1.0 / (m->J_kgm2 * plant->mismatch.J);
    if (!(m->g3_amplitude_per_kgm2 > -inv_J && m->g3_amplitude_per_kgm2 < inv_J)) {
        char expected[96];
        char found[32];
        snprintf(expected, sizeof(expected), "|A| < 1/J = %g 1/(kg m^2)", inv_J);
        snprintf(found, sizeof(found), "%g", m->g3_amplitude_per_kgm2);
        jr_fail(&o, "g3_amplitude_per_kgm2", SCN_ERR_INVALID, expected, found);
        return false;
    }
    return true;
}

static bool read_disturbances(jr_object_t *root, plant_config_t *plant)
{
    jr_object_t o;
    jr_object_t coul;
    plant_motor_params_t *m = &plant->motor;
    return jr_object_opt(root, "disturbances", &o) &&
           profile_read(&o, "load_torque_Nm", false, 1.0, &plant->load_torque_Nm) &&
           read_mismatch(&o, &plant->mismatch) && read_cogging(&o, &m->cogging) &&
           jr_object_opt(&o, "coulomb_friction", &coul) &&
           jr_number_opt(&coul, "torque_Nm", JR_CLOSED(0.0, 1e3), m->tau_coulomb_Nm,
                         &m->tau_coulomb_Nm) &&
           jr_number_opt(&coul, "eps_rad_s", JR_POSITIVE(1e3), m->coulomb_eps_rad_s,
                         &m->coulomb_eps_rad_s) &&
           jr_finish(&coul) && read_inertia_variation(&o, plant) && jr_finish(&o);
}

static bool read_initial_and_solver(jr_object_t *root, plant_config_t *plant)
{
    jr_object_t init;
    jr_object_t solver;
    return jr_object_opt(root, "initial", &init) &&
           jr_number_opt(&init, "theta_m_rad", JR_CLOSED(-1e6, 1e6), plant->theta_m0_rad,
                         &plant->theta_m0_rad) &&
           jr_number_opt(&init, "omega_m_rad_s", JR_CLOSED(-1e5, 1e5), plant->omega_m0_rad_s,
                         &plant->omega_m0_rad_s) &&
           jr_bool_opt(&init, "locked_rotor", plant->locked_rotor, &plant->locked_rotor) &&
           jr_finish(&init) && jr_object_opt(root, "solver", &solver) &&
           jr_u32_opt(&solver, "substeps_per_period", 1, 10000, plant->substeps_per_period,
                      &plant->substeps_per_period) &&
           jr_finish(&solver);
}

bool scenario_read_plant(jr_object_t *root, plant_config_t *plant)
{
    if (!(read_motor(root, &plant->motor) && read_inverter(root, plant) &&
          read_sensors(root, &plant->sensors) && read_disturbances(root, plant) &&
          read_initial_and_solver(root, plant))) {
        return false;
    }
    if (plant->inverter.duty_update == PLANT_DUTY_UPDATE_HALF_PERIOD &&
        plant->substeps_per_period % 2u != 0u) {
        char found[32];
        snprintf(found, sizeof(found), "%u", (unsigned)plant->substeps_per_period);
        jr_fail(root, "solver.substeps_per_period", SCN_ERR_INVALID,
                "an even count with inverter.duty_update \"half_period\" (the duties change "
                "at the middle of the period)",
                found);
        return false;
    }
    const char *msg = "";
    if (plant_config_validate(plant, &msg) != PLANT_OK) {
        jr_fail(root, "(plant)", SCN_ERR_INVALID, "a plant configuration sim_plant accepts", msg);
        return false;
    }
    return true;
}
