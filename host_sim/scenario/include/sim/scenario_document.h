/*
 * A scenario as a JSON document: read it, report malformed JSON with line and
 * column, and apply command-line overrides before validation.
 *
 * Override syntax (pmsm-sim --set):  KEY.PATH=VALUE
 *   KEY.PATH  object keys separated by '.', array elements as [i]
 *             ("motor.R_ohm", "reference.speed_rpm.points[2][1]").
 *             Missing intermediate objects are created, so an optional key
 *             that the file omits can be set; a misspelt key is then
 *             reported by validation as an unknown key.
 *   VALUE     parsed as JSON (0.3, true, [1, 2], {"a": 1}); if that fails,
 *             taken as a string (foc_pi).
 */
#ifndef SIM_SCENARIO_DOCUMENT_H
#define SIM_SCENARIO_DOCUMENT_H

#include <stdbool.h>

#include <cjson/cJSON.h>

#include "sim/scenario_error.h"

/* Parse text; on malformed JSON returns NULL with SCN_ERR_SYNTAX, the 1-based
 * line and column of the error and the text found there. file names the
 * source in messages (may be NULL). Free the result with cJSON_Delete. */
cJSON *scenario_document_parse(const char *text, const char *file, scn_error_t *err);

/* Read and parse a file (SCN_ERR_IO if it cannot be read). */
cJSON *scenario_document_load(const char *file, scn_error_t *err);

/* Apply one "KEY.PATH=VALUE" override (SCN_ERR_OVERRIDE on a bad path,
 * a missing '=', an index out of range or a path through a non-container). */
bool scenario_document_set(cJSON *root, const char *assignment, scn_error_t *err);

#endif /* SIM_SCENARIO_DOCUMENT_H */
