/* The keys a rejected firmware configuration names (firmware_blame.h). */
#include "firmware_blame.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "sim/scenario.h"

#define SCALE_PER_OCTAVE 16  /* factors 2^(k/16): steps of 4.4 % */
#define SCALE_STEPS      160 /* k = 1..160: up to 1024 either way */
#define BISECT_STEPS     64
#define MAX_SUSPECTS     8
#define NAME_MAX_LEN     64

#define EXPECTED                                                                                   \
    "values mc_config_validate() accepts together (each block's ranges in its header under "       \
    "firmware/include/mc, loop bandwidths stable at the sampling rate, limits consistent "         \
    "with the motor, the PWM rate and each other)"

typedef struct {
    char name[NAME_MAX_LEN]; /* "<block>.<field>" or "<field>" (top level) */
    bool given;              /* the file sets it */
    double now;              /* its value in the rejected configuration */
    double valid;            /* a value that alone makes it valid */
} suspect_t;

static void param_name(const mc_param_block_t *b, const mc_param_t *p, char *buf, size_t size)
{
    snprintf(buf, size, "%s%s%s", b->name, b->name[0] != '\0' ? "." : "", p->name);
}

static double get_number(const mc_config_t *cfg, size_t at, mc_param_type_t type)
{
    const unsigned char *field = (const unsigned char *)cfg + at;
    if (type == MC_PARAM_F32) {
        float f;
        memcpy(&f, field, sizeof f);
        return (double)f;
    }
    uint32_t u;
    memcpy(&u, field, sizeof u);
    return (double)u;
}

/* Store v; false when the field's type cannot hold it. */
static bool set_number(mc_config_t *cfg, size_t at, mc_param_type_t type, double v)
{
    unsigned char *field = (unsigned char *)cfg + at;
    if (type == MC_PARAM_F32) {
        if (!(fabs(v) <= (double)FLT_MAX)) {
            return false;
        }
        const float f = (float)v;
        memcpy(field, &f, sizeof f);
        return true;
    }
    if (!(v >= 0.0 && v <= (double)UINT32_MAX)) {
        return false;
    }
    const uint32_t u = (uint32_t)floor(v + 0.5);
    memcpy(field, &u, sizeof u);
    return true;
}

static bool valid_with(const mc_config_t *cfg, size_t at, mc_param_type_t type, double v)
{
    mc_config_t trial = *cfg;
    return set_number(&trial, at, type, v) && mc_config_validate(&trial) == MC_OK;
}

/* A value of the field that alone makes cfg valid, nearest to now in
 * ratio first (now * 2^(+-k/16)), its default last. */
static bool find_valid(const mc_config_t *cfg, size_t at, mc_param_type_t type, double now,
                       double def, double *valid)
{
    for (int k = 1; now != 0.0 && k <= SCALE_STEPS; k++) {
        const double factor = exp2((double)k / SCALE_PER_OCTAVE);
        const double candidates[2] = { now * factor, now / factor };
        for (int c = 0; c < 2; c++) {
            if (valid_with(cfg, at, type, candidates[c])) {
                *valid = candidates[c];
                return true;
            }
        }
    }
    if (def != now && valid_with(cfg, at, type, def)) {
        *valid = def;
        return true;
    }
    return false;
}

/* Between the rejected now and a valid value: the valid end of a boundary
 * (by ratio when both have one sign, else linearly; whole numbers for
 * U32). */
static double bisect(const mc_config_t *cfg, size_t at, mc_param_type_t type, double now,
                     double valid)
{
    double bad = now;
    double good = valid;
    const bool by_ratio = bad * good > 0.0;
    for (int i = 0; i < BISECT_STEPS; i++) {
        double mid = by_ratio ? copysign(sqrt(bad * good), good) : 0.5 * (bad + good);
        if (type == MC_PARAM_U32) {
            mid = floor(mid + 0.5);
        } else {
            mid = (double)(float)mid;
        }
        if (mid == bad || mid == good) {
            break;
        }
        if (valid_with(cfg, at, type, mid)) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    return good;
}

/* x rounded to digits significant digits, up or down. */
static double round_digits(double x, int digits, bool up)
{
    if (x == 0.0) {
        return 0.0;
    }
    const double q = pow(10.0, floor(log10(fabs(x))) - (double)(digits - 1));
    return (up ? ceil(x / q) : floor(x / q)) * q;
}

/* A short value between the boundary and the valid value that is valid
 * itself (the boundary when none is). */
static double short_valid(const mc_config_t *cfg, size_t at, mc_param_type_t type, double boundary,
                          double valid)
{
    const bool up = valid > boundary;
    for (int digits = 2; digits <= 7; digits++) {
        const double r = round_digits(boundary, digits, up);
        const bool between = up ? (r >= boundary && r <= valid) : (r <= boundary && r >= valid);
        const bool whole = type != MC_PARAM_U32 || r == floor(r);
        if (between && whole && valid_with(cfg, at, type, r)) {
            return r;
        }
    }
    return boundary;
}

/* The number keys that alone can make cfg valid; given keys first. */
static size_t number_suspects(jr_object_t *objects, const mc_config_t *cfg,
                              const mc_config_t *defaults, suspect_t *out)
{
    size_t n = 0;
    for (int pass = 0; pass < 2; pass++) { /* given keys, then the others */
        size_t i = 0;
        for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; b++, i++) {
            for (const mc_param_t *p = b->params; p->name != NULL && n < MAX_SUSPECTS; p++) {
                const bool number = p->type == MC_PARAM_F32 || p->type == MC_PARAM_U32;
                const bool given = jr_peek(&objects[i], p->name) != NULL;
                if (!number || scenario_firmware_from_plant(b->name, p->name) ||
                    given != (pass == 0)) {
                    continue;
                }
                const size_t at = b->offset + p->offset;
                const double now = get_number(cfg, at, p->type);
                double valid;
                if (find_valid(cfg, at, p->type, now, get_number(defaults, at, p->type), &valid)) {
                    suspect_t *s = &out[n++];
                    param_name(b, p, s->name, sizeof(s->name));
                    s->given = given;
                    s->now = now;
                    s->valid =
                        short_valid(cfg, at, p->type, bisect(cfg, at, p->type, now, valid), valid);
                }
            }
        }
    }
    return n;
}

/* A given switch (boolean, controller, estimator) whose default makes cfg
 * valid; the top-level selection last. */
static bool switch_suspect(jr_object_t *objects, const mc_config_t *cfg,
                           const mc_config_t *defaults, char *name, size_t size)
{
    for (int top = 0; top < 2; top++) {
        size_t i = 0;
        for (const mc_param_block_t *b = mc_config_params(); b->name != NULL; b++, i++) {
            if ((b->name[0] == '\0') != (top == 1)) {
                continue;
            }
            for (const mc_param_t *p = b->params; p->name != NULL; p++) {
                const bool number = p->type == MC_PARAM_F32 || p->type == MC_PARAM_U32;
                if (number || jr_peek(&objects[i], p->name) == NULL) {
                    continue;
                }
                mc_config_t trial = *cfg;
                const size_t at = b->offset + p->offset;
                memcpy((unsigned char *)&trial + at, (const unsigned char *)defaults + at,
                       mc_param_size(p->type));
                if (mc_config_validate(&trial) == MC_OK) {
                    param_name(b, p, name, size);
                    return true;
                }
            }
        }
    }
    return false;
}

/* Append to buf (size) at *len, keeping it NUL-terminated; false (and
 * nothing appended) when it does not fit whole. */
__attribute__((format(printf, 4, 5))) static bool append(char *buf, size_t size, size_t *len,
                                                         const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    const int n = vsnprintf(buf + *len, size - *len, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= size - *len) {
        buf[*len] = '\0';
        return false;
    }
    *len += (size_t)n;
    return true;
}

static void report_suspects(jr_object_t *fw, const suspect_t *s, size_t n)
{
    char path[SCN_PATH_MAX] = "";
    char expected[SCN_TEXT_MAX] = EXPECTED ": e.g. ";
    char found[SCN_TEXT_MAX] = "";
    size_t path_len = 0;
    size_t expected_len = strlen(expected);
    size_t found_len = 0;
    bool path_full = false;
    for (size_t k = 0; k < n; k++) {
        const char *sep = k > 0 ? ", " : "";
        /* a key that does not fit (leaving room for ", ...") ends the list */
        const size_t need = strlen(sep) + strlen("firmware.") + strlen(s[k].name);
        if (!path_full && path_len + need + strlen(", ...") < sizeof(path)) {
            append(path, sizeof(path), &path_len, "%sfirmware.%s", sep, s[k].name);
        } else if (!path_full) {
            append(path, sizeof(path), &path_len, ", ...");
            path_full = true;
        }
        append(expected, sizeof(expected), &expected_len, "%s%s = %.7g", k > 0 ? " or " : "",
               s[k].name, s[k].valid);
        append(found, sizeof(found), &found_len, "%s%s = %.7g%s", sep, s[k].name, s[k].now,
               s[k].given ? "" : " (default)");
    }
    append(expected, sizeof(expected), &expected_len, "%s", n > 1 ? ", each alone" : "");
    scenario_error_set(fw->err, SCN_ERR_INVALID, path, expected, found);
}

void scenario_firmware_blame(jr_object_t *fw, jr_object_t *objects, const mc_config_t *cfg,
                             mc_status_t st)
{
    mc_config_t defaults;
    mc_config_init_default(&defaults);
    suspect_t suspects[MAX_SUSPECTS];
    const size_t n = number_suspects(objects, cfg, &defaults, suspects);
    if (n > 0) {
        report_suspects(fw, suspects, n);
        return;
    }
    char name[NAME_MAX_LEN];
    if (switch_suspect(objects, cfg, &defaults, name, sizeof(name))) {
        char path[SCN_PATH_MAX];
        snprintf(path, sizeof(path), "firmware.%s", name);
        scenario_error_set(fw->err, SCN_ERR_INVALID, path,
                           EXPECTED ", which this key's default gives", "a rejected value");
        return;
    }
    scenario_error_set(fw->err, SCN_ERR_INVALID, fw->path, EXPECTED,
                       st == MC_ERR_NONFINITE ? "a non-finite value"
                                              : "a rejected combination of motor, inverter, "
                                                "encoder and firmware values");
}
