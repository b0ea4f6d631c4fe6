/* Scenario sections that configure the plant: motor, inverter, sensors,
 * disturbances, initial state and solver. Absent optional keys keep the
 * values of plant_config_default(). */
#include <stdio.h>

#include "mc/encoder_tracker.h"
#include "mc/motor.h"
#include "mc/timing.h"
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

static bool read_motor(jr_object_t *root, plant_motor_params_t *m)
{
    jr_object_t o;
    uint64_t pole_pairs;
    bool ok = jr_object(root, "motor", &o) && jr_number(&o, "R_ohm", JR_POSITIVE(1e3), &m->R_ohm) &&
              jr_number(&o, "Ld_H", JR_POSITIVE(10.0), &m->Ld_H) &&
              jr_number_opt(&o, "Lq_H", JR_POSITIVE(10.0), m->Ld_H, &m->Lq_H) &&
              jr_number(&o, "psi_Wb", JR_POSITIVE(10.0), &m->psi_Wb) &&
              jr_uint(&o, "pole_pairs", 1, MC_MOTOR_POLE_PAIRS_MAX, &pole_pairs) &&
              jr_number(&o, "J_kgm2", JR_POSITIVE(1e3), &m->J_kgm2) &&
              jr_number_opt(&o, "B_Nm_s_rad", JR_CLOSED(0.0, 1e3), 0.0, &m->B_Nm_s_rad) &&
              jr_finish(&o);
    if (ok) {
        m->pole_pairs = (uint32_t)pole_pairs;
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

static bool read_inverter(jr_object_t *root, plant_inverter_params_t *inv)
{
    jr_object_t o;
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
           jr_finish(&o);
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
           jr_u32_opt(&enc, "lines", 0, MC_ENCODER_CPR_MAX / 4u, s->encoder.lines,
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
    if (!(read_motor(root, &plant->motor) && read_inverter(root, &plant->inverter) &&
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
