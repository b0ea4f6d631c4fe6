/* Scenario error record and its one-line rendering. */
#include "sim/scenario_error.h"

#include <stdio.h>
#include <string.h>

static void copy_text(char *dst, size_t size, const char *src)
{
    snprintf(dst, size, "%s", src != NULL ? src : "");
}

void scenario_error_clear(scn_error_t *err)
{
    memset(err, 0, sizeof(*err));
    err->code = SCN_OK;
}

void scenario_error_set(scn_error_t *err, scn_status_t code, const char *path, const char *expected,
                        const char *found)
{
    if (err->code != SCN_OK) {
        return;
    }
    err->code = code;
    copy_text(err->path, sizeof(err->path), path);
    copy_text(err->expected, sizeof(err->expected), expected);
    copy_text(err->found, sizeof(err->found), found);
}

void scenario_error_set_file(scn_error_t *err, const char *file)
{
    copy_text(err->file, sizeof(err->file), file);
}

const char *scenario_error_class_str(scn_status_t code)
{
    switch (code) {
    case SCN_OK: return "ok";
    case SCN_ERR_IO: return "cannot read file";
    case SCN_ERR_SYNTAX: return "malformed JSON";
    case SCN_ERR_MISSING: return "missing required key";
    case SCN_ERR_TYPE: return "wrong type";
    case SCN_ERR_RANGE: return "out of range";
    case SCN_ERR_NONFINITE: return "non-finite number";
    case SCN_ERR_UNKNOWN_KEY: return "unknown key";
    case SCN_ERR_DUPLICATE_KEY: return "duplicate key";
    case SCN_ERR_OVERRIDE: return "bad --set override";
    case SCN_ERR_INVALID: return "invalid value";
    }
    return "unknown error";
}

int scenario_error_format(const scn_error_t *err, char *buf, size_t size)
{
    char where[sizeof(err->file) + sizeof(err->path) + 32];
    const char *file = err->file[0] != '\0' ? err->file : "<scenario>";
    if (err->line > 0) {
        snprintf(where, sizeof(where), "%s:%d:%d", file, err->line, err->column);
    } else if (err->path[0] != '\0') {
        snprintf(where, sizeof(where), "%s: %s", file, err->path);
    } else {
        snprintf(where, sizeof(where), "%s", file);
    }
    char detail[2 * SCN_TEXT_MAX + 32] = "";
    if (err->expected[0] != '\0' && err->found[0] != '\0') {
        snprintf(detail, sizeof(detail), ": expected %s, found %s", err->expected, err->found);
    } else if (err->expected[0] != '\0') {
        snprintf(detail, sizeof(detail), ": expected %s", err->expected);
    } else if (err->found[0] != '\0') {
        snprintf(detail, sizeof(detail), ": found %s", err->found);
    }
    return snprintf(buf, size, "%s: %s%s", where, scenario_error_class_str(err->code), detail);
}
