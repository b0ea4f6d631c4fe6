/*
 * Errors of scenario loading: one struct that says where (file, key path,
 * line/column for malformed JSON), what was expected and what was found.
 *
 * Error classes and their one-line text (scenario_error_class_str):
 *   SCN_ERR_IO            "cannot read file"
 *   SCN_ERR_SYNTAX        "malformed JSON"          (line and column set)
 *   SCN_ERR_MISSING       "missing required key"
 *   SCN_ERR_TYPE          "wrong type"
 *   SCN_ERR_RANGE         "out of range"
 *   SCN_ERR_NONFINITE     "non-finite number"       (e.g. 1e999 parses as inf)
 *   SCN_ERR_UNKNOWN_KEY   "unknown key"             (expected lists the known keys)
 *   SCN_ERR_DUPLICATE_KEY "duplicate key"
 *   SCN_ERR_OVERRIDE      "bad --set override"
 *   SCN_ERR_INVALID       "invalid value"           (a rule across several keys)
 */
#ifndef SIM_SCENARIO_ERROR_H
#define SIM_SCENARIO_ERROR_H

#include <stddef.h>

#define SCN_PATH_MAX 128
#define SCN_TEXT_MAX 512

typedef enum {
    SCN_OK = 0,
    SCN_ERR_IO,
    SCN_ERR_SYNTAX,
    SCN_ERR_MISSING,
    SCN_ERR_TYPE,
    SCN_ERR_RANGE,
    SCN_ERR_NONFINITE,
    SCN_ERR_UNKNOWN_KEY,
    SCN_ERR_DUPLICATE_KEY,
    SCN_ERR_OVERRIDE,
    SCN_ERR_INVALID
} scn_status_t;

typedef struct {
    scn_status_t code;
    char file[256];              /* scenario file name ("" if from a string) */
    char path[SCN_PATH_MAX];     /* key path, e.g. "motor.R_ohm", "load.points[2]" */
    char expected[SCN_TEXT_MAX]; /* e.g. "number in (0, 1000]" */
    char found[SCN_TEXT_MAX];    /* e.g. "string \"abc\"", "-1", "inf" */
    int line;                    /* 1-based, SCN_ERR_SYNTAX only (else 0) */
    int column;                  /* 1-based, SCN_ERR_SYNTAX only (else 0) */
} scn_error_t;

/* Set code OK and clear every text field. */
void scenario_error_clear(scn_error_t *err);

/* Record an error unless one is already recorded (the first error wins).
 * path/expected/found may be NULL. */
void scenario_error_set(scn_error_t *err, scn_status_t code, const char *path, const char *expected,
                        const char *found);

/* Name the source file of what follows (NULL: ""); kept by later errors. */
void scenario_error_set_file(scn_error_t *err, const char *file);

const char *scenario_error_class_str(scn_status_t code);

/* One line, e.g.
 *   "p001.json: motor.R_ohm: out of range: expected number in (0, 1000], found -1"
 *   "p001.json:12:7: malformed JSON: found 'x, }'"
 * Returns the snprintf-style length. */
int scenario_error_format(const scn_error_t *err, char *buf, size_t size);

#endif /* SIM_SCENARIO_ERROR_H */
