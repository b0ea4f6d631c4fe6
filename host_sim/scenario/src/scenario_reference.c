/* Scenario section "reference": control mode and reference profile (SI). */
#include "profile_reader.h"
#include "scenario_sections.h"

#define RPM_TO_RAD_S (3.14159265358979323846 / 30.0)

/* Names in the order of mc_mode_t. */
static const char *const mode_names[] = { "current", "speed", "position" };

const char *scenario_mode_name(mc_mode_t mode)
{
    return (size_t)mode < sizeof(mode_names) / sizeof(mode_names[0]) ? mode_names[mode] : "unknown";
}

mc_command_t scenario_command_at(const scenario_reference_t *ref, double t_s)
{
    mc_command_t cmd = { .enable = true, .mode = ref->mode };
    const double v = sim_profile_eval(&ref->value, t_s);
    switch (ref->mode) {
    case MC_MODE_SPEED: cmd.omega_m_ref_rad_s = (float)v; break;
    case MC_MODE_POSITION: cmd.theta_m_ref_rad = (float)v; break;
    case MC_MODE_CURRENT:
        cmd.i_q_ref_A = (float)v;
        cmd.i_d_ref_A = (float)sim_profile_eval(&ref->i_d_A, t_s);
        break;
    }
    return cmd;
}

static bool read_speed_reference(jr_object_t *o, scenario_reference_t *ref)
{
    bool has_rpm = jr_peek(o, "speed_rpm") != NULL;
    bool has_rad_s = jr_peek(o, "speed_rad_s") != NULL;
    if (has_rpm && has_rad_s) {
        jr_fail(o, "speed_rad_s", SCN_ERR_INVALID, "exactly one of speed_rpm, speed_rad_s", "both");
        return false;
    }
    if (has_rad_s) {
        ref->display_unit = "rad_s";
        ref->display_per_si = 1.0;
        return profile_read(o, "speed_rad_s", true, 1.0, &ref->value);
    }
    ref->display_unit = "rpm";
    ref->display_per_si = 1.0 / RPM_TO_RAD_S;
    return profile_read(o, "speed_rpm", true, RPM_TO_RAD_S, &ref->value);
}

bool scenario_read_reference(jr_object_t *root, scenario_reference_t *ref)
{
    jr_object_t o;
    size_t mode;
    sim_profile_clear(&ref->value);
    sim_profile_clear(&ref->i_d_A);
    if (!jr_object(root, "reference", &o) ||
        !jr_enum(&o, "mode", mode_names, sizeof(mode_names) / sizeof(mode_names[0]), &mode)) {
        return false;
    }
    ref->mode = (mc_mode_t)mode;
    bool ok = false;
    switch (ref->mode) {
    case MC_MODE_SPEED: ok = read_speed_reference(&o, ref); break;
    case MC_MODE_POSITION:
        ref->display_unit = "rad";
        ref->display_per_si = 1.0;
        ok = profile_read(&o, "position_rad", true, 1.0, &ref->value);
        break;
    case MC_MODE_CURRENT:
        ref->display_unit = "A";
        ref->display_per_si = 1.0;
        ok = profile_read(&o, "i_q_A", true, 1.0, &ref->value) &&
             profile_read(&o, "i_d_A", false, 1.0, &ref->i_d_A);
        break;
    }
    return ok && jr_finish(&o);
}
