/* Scenario section "controller" -> firmware configuration (mc/app.h).
 * The keys are the mc_config_t member names; absent keys keep the values of
 * mc_config_init_default(). */
#include <stddef.h>
#include <string.h>

#include "scenario_sections.h"

/* Names in the order of the firmware enums. */
static const char *const controller_names[] = { "foc_pi", "idapbc" };
static const char *const angle_source_names[] = { "encoder", "flux_observer" };

#define N_NAMES(a) (sizeof(a) / sizeof((a)[0]))

typedef enum { FIELD_F32, FIELD_U32, FIELD_BOOL, FIELD_CONTROLLER, FIELD_ANGLE_SOURCE } kind_t;

/* A key of the section and the mc_config_t member it sets. */
typedef struct {
    const char *key;
    size_t offset;
    kind_t kind;
    double lo;       /* numbers: (lo, hi] if lo_open, else [lo, hi] */
    double hi;
    bool lo_open;
} field_t;

#define AT(member) offsetof(mc_config_t, member)
#define F32(key, member, lo, hi, lo_open) { key, AT(member), FIELD_F32, lo, hi, lo_open }
#define U32(key, member, lo, hi) { key, AT(member), FIELD_U32, lo, hi, false }

static const field_t controller_fields[] = {
    { "type", AT(controller), FIELD_CONTROLLER, 0, 0, false },
    { "angle_source", AT(angle_source), FIELD_ANGLE_SOURCE, 0, 0, false },
    F32("current_bandwidth_rad_s", current_bandwidth_rad_s, 0.0, 1e6, true),
    F32("speed_bandwidth_rad_s", speed_bandwidth_rad_s, 0.0, 1e5, true),
    F32("position_kp_per_s", position_kp_per_s, 0.0, 1e4, true),
    F32("pll_bandwidth_rad_s", pll_bandwidth_rad_s, 0.0, 1e6, true),
    U32("speed_loop_decimation", speed_loop_decimation, 1, 1000),
    U32("calib_samples", calib_samples, 1, 65536),
    U32("isr_overrun_limit", isr_overrun_limit, 1, 100),
    F32("modulation_margin", modulation_margin, 0.0, 1.0, true),
    F32("i_max_A", i_max_A, 0.0, 1e4, true),
    F32("omega_max_rad_s", omega_max_rad_s, 0.0, 1e5, true),
    F32("i_offset_max_A", i_offset_max_A, 0.0, 1e3, true),
    F32("encoder_offset_e_rad", encoder_offset_e_rad, -1e3, 1e3, false),
    /* sensorless estimation and the paper-001 controller */
    F32("flux_obs_gamma", flux_obs_gamma, 0.0, 1e9, true),
    F32("speed_obs_a1", speed_obs_a1, 0.0, 1e9, true),
    F32("speed_obs_a2", speed_obs_a2, 0.0, 1e9, true),
    F32("sensorless_pll_bandwidth_rad_s", sensorless_pll_bandwidth_rad_s, 0.0, 1e6, true),
    F32("est_omega_max_rad_s", est_omega_max_rad_s, 0.0, 1e6, true),
    F32("est_tau_max_Nm", est_tau_max_Nm, 0.0, 1e6, true),
    F32("est_flux_ratio_min", est_flux_ratio_min, 0.0, 1.0, true),
    F32("est_flux_ratio_max", est_flux_ratio_max, 1.0, 100.0, true),
    { "delay_comp_enabled", AT(delay_comp_enabled), FIELD_BOOL, 0, 0, false },
    F32("delay_periods", delay_periods, 0.5, 1.5, false),
    F32("idapbc_r_ohm", idapbc_r_ohm, 0.0, 1e6, false),
    { "idapbc_integral_enabled", AT(idapbc_integral_enabled), FIELD_BOOL, 0, 0, false },
    F32("idapbc_integral_pole_rad_s", idapbc_integral_pole_rad_s, 0.0, 1e6, true),
    F32("idapbc_integral_tau_max_Nm", idapbc_integral_tau_max_Nm, 0.0, 1e6, true),
    /* sensorless start (ALIGN state) */
    F32("align_current_A", align_current_A, 0.0, 1e4, true),
    F32("align_ramp_s", align_ramp_s, 0.0, 10.0, false),
    F32("align_time_s", align_time_s, 0.0, 10.0, true),
    F32("align_angle_e_rad", align_angle_e_rad, -7.0, 7.0, false),
    F32("align_damping_ratio", align_damping_ratio, 0.0, 10.0, true),
    F32("align_i_q_max_A", align_i_q_max_A, 0.0, 1e4, true),
    F32("align_settle_speed_e_rad_s", align_settle_speed_e_rad_s, 0.0, 1e4, true),
    F32("align_settle_time_s", align_settle_time_s, 0.0, 10.0, true),
};

static const field_t fault_limit_fields[] = {
    F32("i_trip_A", fault_limits.i_trip_A, 0.0, 1e5, true),
    F32("v_dc_max_V", fault_limits.v_dc_max_V, 0.0, 1e5, true),
    F32("v_dc_min_V", fault_limits.v_dc_min_V, 0.0, 1e5, false),
};

#define N_FIELDS(a) (sizeof(a) / sizeof((a)[0]))

static size_t field_size(kind_t kind)
{
    switch (kind) {
    case FIELD_F32: return sizeof(float);
    case FIELD_U32: return sizeof(uint32_t);
    case FIELD_BOOL: return sizeof(bool);
    case FIELD_CONTROLLER: return sizeof(mc_controller_t);
    case FIELD_ANGLE_SOURCE: return sizeof(mc_angle_source_t);
    }
    return 0;
}

/* A firmware enum by name; *value is the default and the result. */
static bool read_enum(jr_object_t *o, const char *key, const char *const *names, size_t n,
                      int *value)
{
    size_t index;
    if (!jr_enum_opt(o, key, names, n, (size_t)*value, &index)) {
        return false;
    }
    *value = (int)index;
    return true;
}

static bool read_field(jr_object_t *o, const field_t *f, mc_config_t *cfg)
{
    unsigned char *member = (unsigned char *)cfg + f->offset;
    union {
        float f32;
        uint32_t u32;
        bool flag;
        mc_controller_t controller;
        mc_angle_source_t angle_source;
    } v;
    memcpy(&v, member, field_size(f->kind));
    bool ok = false;
    double d = 0.0;
    int e = 0;
    switch (f->kind) {
    case FIELD_F32:
        ok = jr_number_opt(o, f->key, (jr_range_t){ f->lo, f->hi, f->lo_open, false },
                           (double)v.f32, &d);
        v.f32 = (float)d;
        break;
    case FIELD_U32:
        ok = jr_u32_opt(o, f->key, (uint32_t)f->lo, (uint32_t)f->hi, v.u32, &v.u32);
        break;
    case FIELD_BOOL:
        ok = jr_bool_opt(o, f->key, v.flag, &v.flag);
        break;
    case FIELD_CONTROLLER:
        e = (int)v.controller;
        ok = read_enum(o, f->key, controller_names, N_NAMES(controller_names), &e);
        v.controller = (mc_controller_t)e;
        break;
    case FIELD_ANGLE_SOURCE:
        e = (int)v.angle_source;
        ok = read_enum(o, f->key, angle_source_names, N_NAMES(angle_source_names), &e);
        v.angle_source = (mc_angle_source_t)e;
        break;
    }
    if (ok) {
        memcpy(member, &v, field_size(f->kind));
    }
    return ok;
}

static bool read_fields(jr_object_t *o, const field_t *fields, size_t n, mc_config_t *cfg)
{
    for (size_t i = 0; i < n; i++) {
        if (!read_field(o, &fields[i], cfg)) {
            return false;
        }
    }
    return true;
}

/* The controller knows the nominal motor (the plant applies the mismatch). */
static void copy_nominal(const plant_config_t *plant, mc_config_t *cfg)
{
    const plant_motor_params_t *m = &plant->motor;
    cfg->R_ohm = (float)m->R_ohm;
    cfg->Ld_H = (float)m->Ld_H;
    cfg->Lq_H = (float)m->Lq_H;
    cfg->psi_Wb = (float)m->psi_Wb;
    cfg->pole_pairs = m->pole_pairs;
    cfg->J_kgm2 = (float)m->J_kgm2;
    cfg->B_Nms = (float)m->B_Nm_s_rad;
    cfg->f_pwm_hz = (float)plant->inverter.f_pwm_Hz;
    cfg->encoder_cpr = 4u * plant->sensors.encoder.lines;
}

/* The first given key of `fields` whose firmware default makes cfg valid. */
static const char *blame(const jr_object_t *o, const field_t *fields, size_t n,
                         const mc_config_t *cfg)
{
    mc_config_t defaults;
    mc_config_init_default(&defaults);
    for (size_t i = 0; i < n; i++) {
        if (jr_peek(o, fields[i].key) == NULL) {
            continue;
        }
        mc_config_t trial = *cfg;
        memcpy((unsigned char *)&trial + fields[i].offset,
               (const unsigned char *)&defaults + fields[i].offset, field_size(fields[i].kind));
        if (mc_config_validate(&trial) == MC_OK) {
            return fields[i].key;
        }
    }
    return NULL;
}

/* mc_config_validate() rejected cfg: name the key if one alone is the cause. */
static void report_rejected(jr_object_t *o, jr_object_t *limits, const mc_config_t *cfg,
                            mc_status_t st)
{
    const char *expected =
        "a configuration mc_config_validate() accepts (finite values, loop bandwidths "
        "stable at the sampling rate, limits consistent with the motor and the PWM rate)";
    const char *found = st == MC_ERR_NONFINITE ? "a non-finite value" : "a rejected value";
    const char *key = blame(o, controller_fields, N_FIELDS(controller_fields), cfg);
    if (key != NULL) {
        jr_fail(o, key, SCN_ERR_INVALID, expected, found);
        return;
    }
    key = blame(limits, fault_limit_fields, N_FIELDS(fault_limit_fields), cfg);
    if (key != NULL) {
        jr_fail(limits, key, SCN_ERR_INVALID, expected, found);
        return;
    }
    scenario_error_set(o->err, SCN_ERR_INVALID, o->path, expected,
                       "a rejected combination of motor, inverter, encoder and controller "
                       "values");
}

bool scenario_read_controller(jr_object_t *root, const plant_config_t *plant, mc_config_t *cfg)
{
    jr_object_t o;
    jr_object_t limits;
    copy_nominal(plant, cfg);
    if (!jr_object_opt(root, "controller", &o) ||
        !read_fields(&o, controller_fields, N_FIELDS(controller_fields), cfg) ||
        !jr_object_opt(&o, "fault_limits", &limits) ||
        !read_fields(&limits, fault_limit_fields, N_FIELDS(fault_limit_fields), cfg) ||
        !jr_finish(&limits) || !jr_finish(&o)) {
        return false;
    }
    mc_status_t st = mc_config_validate(cfg);
    if (st != MC_OK) {
        report_rejected(&o, &limits, cfg, st);
        return false;
    }
    return true;
}
