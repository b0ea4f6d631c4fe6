/*
 * Scenario files that extend another one (format: host_sim/scenarios/README.md):
 *
 *   {"extends": "base.json", "set": ["KEY.PATH=VALUE", ...],
 *    "name": "...", "description": "..."}
 *
 * "extends" is relative to the extending file's directory (or absolute). The
 * base is loaded (and resolved itself, up to SCENARIO_EXTENDS_MAX_DEPTH links,
 * a file never twice in one chain), its name and description are replaced by
 * the extending file's (absent: no name, so the report uses the file name,
 * and no description), then the "set" entries are applied in order with the
 * --set syntax and semantics (sim/scenario_document.h). Validation happens
 * later, on the merged document, like for any other document. An extending
 * file takes no other key.
 */
#ifndef SIM_SCENARIO_EXTENDS_H
#define SIM_SCENARIO_EXTENDS_H

#include <cjson/cJSON.h>

#include "sim/scenario_error.h"

#define SCENARIO_EXTENDS_MAX_DEPTH 4 /* "extends" links in one chain */

/* Takes ownership of doc (read from file; NULL when it came from a string:
 * a relative "extends" is then taken from the current directory). Returns
 * doc itself when it has no "extends", else the merged document; NULL with
 * the first error:
 *   SCN_ERR_IO       at "extends" of the extending file: base missing or unreadable
 *   SCN_ERR_INVALID  at "extends": a cycle, or more than the depth limit
 *   SCN_ERR_OVERRIDE at "set[i]": a bad entry (found says why, with its key path)
 *   SCN_ERR_TYPE, SCN_ERR_UNKNOWN_KEY, SCN_ERR_DUPLICATE_KEY in the extending
 *                    file's own keys; a malformed base names the base file.
 * On success err->file names file again (the merged document's errors are
 * reported against the file that was loaded). */
cJSON *scenario_extends_resolve(cJSON *doc, const char *file, scn_error_t *err);

#endif /* SIM_SCENARIO_EXTENDS_H */
