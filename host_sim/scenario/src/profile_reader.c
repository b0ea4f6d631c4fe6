/* Time profiles from scenario keys; format in profile_reader.h. */
#include "profile_reader.h"

#include <stdio.h>

#define MAX_TIME_S  1e6
#define MAX_FREQ_HZ 1e6

static bool read_points(jr_object_t *obj, double scale, sim_profile_t *out)
{
    jr_array_t points;
    if (!jr_array_opt(obj, "points", 1, SIM_PROFILE_MAX_POINTS, &points)) {
        return false;
    }
    for (size_t i = 0; i < points.size; i++) {
        jr_array_t pair;
        double t_s;
        double value;
        if (!jr_array_array(&points, i, 2, 2, &pair) ||
            !jr_array_number(&pair, 0, JR_CLOSED(0.0, MAX_TIME_S), &t_s) ||
            !jr_array_number(&pair, 1, JR_ANY_FINITE, &value)) {
            return false;
        }
        if (i > 0 && t_s < out->points[i - 1].t_s) {
            char key[32];
            char expected[64];
            char found[32];
            snprintf(key, sizeof(key), "points[%zu][0]", i);
            snprintf(expected, sizeof(expected), "time >= %g s (the previous point's)",
                     out->points[i - 1].t_s);
            snprintf(found, sizeof(found), "%g", t_s);
            jr_fail(obj, key, SCN_ERR_INVALID, expected, found);
            return false;
        }
        out->points[i] = (sim_profile_point_t){ .t_s = t_s, .value = value * scale };
    }
    out->n_points = (uint32_t)points.size;
    return true;
}

static bool read_sines(jr_object_t *obj, double scale, sim_profile_t *out)
{
    jr_array_t sines;
    if (!jr_array_opt(obj, "sines", 1, SIM_PROFILE_MAX_SINES, &sines)) {
        return false;
    }
    for (size_t i = 0; i < sines.size; i++) {
        jr_object_t s;
        sim_profile_sine_t *sine = &out->sines[i];
        if (!jr_array_object(&sines, i, &s) ||
            !jr_number(&s, "amplitude", JR_ANY_FINITE, &sine->amplitude) ||
            !jr_number(&s, "freq_Hz", JR_CLOSED(0.0, MAX_FREQ_HZ), &sine->freq_Hz) ||
            !jr_number_opt(&s, "phase_rad", JR_ANY_FINITE, 0.0, &sine->phase_rad) ||
            !jr_number_opt(&s, "t_start_s", JR_CLOSED(0.0, MAX_TIME_S), 0.0, &sine->t_start_s) ||
            !jr_finish(&s)) {
            return false;
        }
        sine->amplitude *= scale;
    }
    out->n_sines = (uint32_t)sines.size;
    return true;
}

static bool read_poly(jr_object_t *obj, double scale, sim_profile_t *out)
{
    jr_object_t poly;
    jr_array_t coeffs;
    if (!jr_object_opt(obj, "poly", &poly) || poly.json == NULL) {
        return jr_ok(obj);
    }
    if (!jr_array(&poly, "coeffs", 1, SIM_PROFILE_MAX_POLY_COEFFS, &coeffs)) {
        return false;
    }
    for (size_t k = 0; k < coeffs.size; k++) {
        if (!jr_array_number(&coeffs, k, JR_ANY_FINITE, &out->poly.coeffs[k])) {
            return false;
        }
        out->poly.coeffs[k] *= scale;
    }
    out->poly.n_coeffs = (uint32_t)coeffs.size;
    return jr_number_opt(&poly, "t_start_s", JR_CLOSED(0.0, MAX_TIME_S), 0.0,
                         &out->poly.t_start_s) &&
           jr_finish(&poly);
}

static bool read_noise(jr_object_t *obj, double scale, sim_profile_t *out)
{
    jr_object_t noise;
    if (!jr_object_opt(obj, "noise", &noise) || noise.json == NULL) {
        return jr_ok(obj);
    }
    sim_profile_noise_t *n = &out->noise;
    if (!jr_number(&noise, "rms", JR_CLOSED(0.0, 1e12), &n->rms) ||
        !jr_number(&noise, "cutoff_Hz", JR_POSITIVE(MAX_FREQ_HZ), &n->cutoff_Hz) ||
        !jr_uint_opt(&noise, "seed", 0, UINT32_MAX, 1, &n->seed) || !jr_finish(&noise)) {
        return false;
    }
    n->rms *= scale;
    return true;
}

bool profile_read(jr_object_t *obj, const char *key, bool required, double scale,
                  sim_profile_t *out)
{
    const cJSON *item = jr_peek(obj, key);
    if (item == NULL && !required) {
        return jr_ok(obj);
    }
    if (item == NULL || cJSON_IsNumber(item)) {
        double value;
        if (!jr_number(obj, key, JR_ANY_FINITE, &value)) {
            return false;
        }
        sim_profile_set_constant(out, value * scale);
        return true;
    }
    if (!cJSON_IsObject(item)) {
        char found[SCN_TEXT_MAX];
        jr_describe(item, found, sizeof(found));
        jr_fail(obj, key, SCN_ERR_TYPE, "number or profile object", found);
        return false;
    }
    jr_object_t profile;
    sim_profile_clear(out);
    if (!jr_object(obj, key, &profile) || !read_points(&profile, scale, out) ||
        !read_sines(&profile, scale, out) || !read_poly(&profile, scale, out) ||
        !read_noise(&profile, scale, out) || !jr_finish(&profile)) {
        return false;
    }
    const char *msg = "";
    if (sim_profile_validate(out, &msg) != SIM_PROFILE_OK) {
        jr_fail(obj, key, SCN_ERR_INVALID, "a valid profile", msg);
        return false;
    }
    return true;
}
