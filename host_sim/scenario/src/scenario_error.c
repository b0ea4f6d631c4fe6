/* Scenario error record and its one-line rendering. */
#include "sim/scenario_error.h"

#include <stdio.h>
#include <string.h>

#include "sim/text_escape.h"

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

/* The escaped copies of the record's texts (sim/text_escape.h): keys,
 * values and file names come from the user and reach a terminal. An
 * escape takes at most 4 bytes per input byte. */
typedef struct {
    char file[4 * sizeof(((scn_error_t *)0)->file)];
    char path[4 * SCN_PATH_MAX];
    char expected[4 * SCN_TEXT_MAX];
    char found[4 * SCN_TEXT_MAX];
} escaped_error_t;

int scenario_error_format(const scn_error_t *err, char *buf, size_t size)
{
    escaped_error_t e;
    text_escape(err->file[0] != '\0' ? err->file : "<scenario>", e.file, sizeof(e.file));
    text_escape(err->path, e.path, sizeof(e.path));
    text_escape(err->expected, e.expected, sizeof(e.expected));
    text_escape(err->found, e.found, sizeof(e.found));
    char where[sizeof(e.file) + sizeof(e.path) + 32];
    if (err->line > 0) {
        snprintf(where, sizeof(where), "%s:%d:%d", e.file, err->line, err->column);
    } else if (e.path[0] != '\0') {
        snprintf(where, sizeof(where), "%s: %s", e.file, e.path);
    } else {
        snprintf(where, sizeof(where), "%s", e.file);
    }
    char detail[sizeof(e.expected) + sizeof(e.found) + 32] = "";
    if (e.expected[0] != '\0' && e.found[0] != '\0') {
        snprintf(detail, sizeof(detail), ": expected %s, found %s", e.expected, e.found);
    } else if (e.expected[0] != '\0') {
        snprintf(detail, sizeof(detail), ": expected %s", e.expected);
    } else if (e.found[0] != '\0') {
        snprintf(detail, sizeof(detail), ": found %s", e.found);
    }
    return snprintf(buf, size, "%s: %s%s", where, scenario_error_class_str(err->code), detail);
}
