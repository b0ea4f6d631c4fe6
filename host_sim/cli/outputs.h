/*
 * The files a run writes (--csv, --json, --plot), checked before the run
 * and written so that a failure leaves none of them behind.
 *
 * Before the run, for each requested file: its directory must exist and
 * be writable, the name must not be a directory, an existing file there
 * must be writable (it is replaced), it must not be the scenario file and
 * no two outputs may be the same file. Each file is then written to a
 * staging directory created next to it (".<name>.pmsm-sim-XXXXXX", same
 * file system) and renamed onto the target only after the run and every
 * output succeeded; on any failure the staged files and directories are
 * removed and the targets stay as they were. With --plot but no --csv the
 * trace for the plot is a scratch file in the plot's staging directory.
 */
#ifndef PMSM_SIM_OUTPUTS_H
#define PMSM_SIM_OUTPUTS_H

#include <stdbool.h>
#include <stddef.h>

#include "cli_args.h"

#define OUTPUTS_PATH_MAX 4096

typedef enum { OUTPUT_CSV, OUTPUT_JSON, OUTPUT_PLOT, OUTPUT_COUNT } output_kind_t;

typedef struct {
    const char *option;               /* "--csv", "--json", "--plot" */
    const char *target;               /* the user's path; NULL: not requested */
    char stage_dir[OUTPUTS_PATH_MAX]; /* "": none of its own */
    char path[OUTPUTS_PATH_MAX];      /* where the run writes it; "": not written */
} output_file_t;

typedef struct {
    output_file_t files[OUTPUT_COUNT];
} outputs_t;

/* Check the requested outputs of args (against args->scenario) and stage
 * them; false with msg, and nothing created, when one cannot be written. */
bool outputs_prepare(outputs_t *o, const cli_args_t *args, char *msg, size_t msg_size);

/* The staged path of an output ("" when the run does not write it). */
const char *outputs_path(const outputs_t *o, output_kind_t kind);

/* Move every staged file onto its target and remove the staging; false
 * with msg when a rename fails (the staging is removed anyway). */
bool outputs_commit(outputs_t *o, char *msg, size_t msg_size);

/* Remove every staged file and staging directory (any failure). */
void outputs_discard(outputs_t *o);

#endif /* PMSM_SIM_OUTPUTS_H */
