/* Output files checked before the run and staged (outputs.h). */
#define _XOPEN_SOURCE 700 /* POSIX 2008 with realpath */

#include "outputs.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define SCRATCH_TRACE_NAME "trace.csv"

/* "a/b.csv" -> dir "a", base "b.csv"; "b.csv" -> ".", "b.csv"; "/b" -> "/". */
static const char *split_path(const char *target, char *dir, size_t dir_size)
{
    const char *slash = strrchr(target, '/');
    if (slash == NULL) {
        snprintf(dir, dir_size, ".");
        return target;
    }
    snprintf(dir, dir_size, "%.*s", slash == target ? 1 : (int)(slash - target), target);
    return slash + 1;
}

/* The target's directory (resolved) and name, to compare targets. */
static void canonical(const char *target, char *out, size_t size)
{
    char dir[OUTPUTS_PATH_MAX];
    const char *base = split_path(target, dir, sizeof(dir));
    char *real = realpath(dir, NULL);
    snprintf(out, size, "%s/%s", real != NULL ? real : dir, base);
    free(real);
}

static bool same_file(const char *a, const char *b)
{
    char ca[2 * OUTPUTS_PATH_MAX];
    char cb[2 * OUTPUTS_PATH_MAX];
    canonical(a, ca, sizeof(ca));
    canonical(b, cb, sizeof(cb));
    struct stat sa;
    struct stat sb;
    return strcmp(ca, cb) == 0 || (stat(a, &sa) == 0 && stat(b, &sb) == 0 &&
                                   sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino);
}

/* Whether f->target can be written; false with msg. *direct: an existing
 * file that is not a regular one (a device, a pipe: /dev/stdout) is
 * written in place, without staging. */
static bool check_target(const output_file_t *f, const char *scenario, bool *direct, char *msg,
                         size_t msg_size)
{
    const char *t = f->target;
    char dir[OUTPUTS_PATH_MAX];
    const char *base = split_path(t, dir, sizeof(dir));
    struct stat st;
    *direct = false;
    if (base[0] == '\0' || strcmp(base, ".") == 0 || strcmp(base, "..") == 0) {
        snprintf(msg, msg_size, "%s %.1000s: not a file name", f->option, t);
        return false;
    }
    if (stat(dir, &st) != 0) {
        snprintf(msg, msg_size, "%s %.1000s: the directory %.1000s %s", f->option, t, dir,
                 errno == ENOENT ? "does not exist" : strerror(errno));
        return false;
    }
    if (!S_ISDIR(st.st_mode)) {
        snprintf(msg, msg_size, "%s %.1000s: %.1000s is not a directory", f->option, t, dir);
        return false;
    }
    if (stat(t, &st) == 0) {
        if (S_ISDIR(st.st_mode)) {
            snprintf(msg, msg_size, "%s %.1000s: is a directory", f->option, t);
            return false;
        }
        if (same_file(t, scenario)) {
            snprintf(msg, msg_size,
                     "%s %.1000s: is the scenario file, which a run never overwrites", f->option,
                     t);
            return false;
        }
        if (access(t, W_OK) != 0) {
            snprintf(msg, msg_size, "%s %.1000s: exists and is not writable (%s)", f->option, t,
                     strerror(errno));
            return false;
        }
        *direct = !S_ISREG(st.st_mode);
    }
    if (!*direct && access(dir, W_OK | X_OK) != 0) {
        snprintf(msg, msg_size, "%s %.1000s: cannot create files in %.1000s (%s)", f->option, t,
                 dir, strerror(errno));
        return false;
    }
    return true;
}

/* The staging directory next to f->target and the staged path in it. */
static bool stage(output_file_t *f, char *msg, size_t msg_size)
{
    char dir[OUTPUTS_PATH_MAX];
    const char *base = split_path(f->target, dir, sizeof(dir));
    const int n_dir = snprintf(f->stage_dir, sizeof(f->stage_dir), "%s/.pmsm-sim-XXXXXX", dir);
    const int n_path = n_dir + 1 + (int)strlen(base);
    if (n_dir < 0 || (size_t)n_path >= sizeof(f->path)) {
        snprintf(msg, msg_size, "%s %.1000s: path too long", f->option, f->target);
        f->stage_dir[0] = '\0';
        return false;
    }
    if (mkdtemp(f->stage_dir) == NULL) {
        snprintf(msg, msg_size, "%s %.1000s: cannot create a staging directory in %.1000s (%s)",
                 f->option, f->target, dir, strerror(errno));
        f->stage_dir[0] = '\0';
        return false;
    }
    return snprintf(f->path, sizeof(f->path), "%s/%s", f->stage_dir, base) == n_path;
}

static bool check_all(const outputs_t *o, const char *scenario, bool direct[OUTPUT_COUNT],
                      char *msg, size_t msg_size)
{
    for (int i = 0; i < OUTPUT_COUNT; i++) {
        const output_file_t *f = &o->files[i];
        if (f->target == NULL) {
            continue;
        }
        if (!check_target(f, scenario, &direct[i], msg, msg_size)) {
            return false;
        }
        for (int j = 0; j < i; j++) {
            const output_file_t *g = &o->files[j];
            if (g->target != NULL && same_file(f->target, g->target)) {
                snprintf(msg, msg_size, "%s and %s name the same file %.1000s", g->option,
                         f->option, f->target);
                return false;
            }
        }
    }
    return true;
}

bool outputs_prepare(outputs_t *o, const cli_args_t *args, char *msg, size_t msg_size)
{
    *o = (outputs_t){ .files = { [OUTPUT_CSV] = { .option = "--csv", .target = args->csv },
                                 [OUTPUT_JSON] = { .option = "--json", .target = args->json },
                                 [OUTPUT_PLOT] = { .option = "--plot", .target = args->plot } } };
    bool direct[OUTPUT_COUNT] = { false };
    if (!check_all(o, args->scenario, direct, msg, msg_size)) {
        return false;
    }
    for (int i = 0; i < OUTPUT_COUNT; i++) {
        output_file_t *f = &o->files[i];
        if (f->target != NULL && direct[i]) {
            snprintf(f->path, sizeof(f->path), "%s", f->target);
        } else if (f->target != NULL && !stage(f, msg, msg_size)) {
            outputs_discard(o);
            return false;
        }
    }
    output_file_t *csv = &o->files[OUTPUT_CSV];
    const output_file_t *plot = &o->files[OUTPUT_PLOT];
    if (csv->target == NULL && plot->target != NULL) {
        if (plot->stage_dir[0] == '\0') { /* no place for the scratch trace */
            snprintf(msg, msg_size,
                     "--plot %.1000s: not a regular file; with a device or a pipe give --csv too",
                     plot->target);
            outputs_discard(o);
            return false;
        }
        const int n =
            snprintf(csv->path, sizeof(csv->path), "%s/%s", plot->stage_dir, SCRATCH_TRACE_NAME);
        if (n < 0 || (size_t)n >= sizeof(csv->path)) {
            snprintf(msg, msg_size, "--plot %.1000s: path too long", plot->target);
            outputs_discard(o);
            return false;
        }
    }
    return true;
}

const char *outputs_path(const outputs_t *o, output_kind_t kind)
{
    return o->files[kind].path;
}

/* Remove the staged file (not a target written in place) and f's own
 * staging directory. */
static void remove_staged(output_file_t *f)
{
    const bool in_place = f->target != NULL && f->stage_dir[0] == '\0';
    if (f->path[0] != '\0' && !in_place) {
        unlink(f->path);
    }
    if (f->stage_dir[0] != '\0') {
        rmdir(f->stage_dir);
    }
    f->path[0] = '\0';
    f->stage_dir[0] = '\0';
}

bool outputs_commit(outputs_t *o, char *msg, size_t msg_size)
{
    bool ok = true;
    for (int i = 0; i < OUTPUT_COUNT; i++) { /* the scratch trace before the plot's directory */
        output_file_t *f = &o->files[i];
        if (ok && f->target != NULL && f->stage_dir[0] != '\0' && rename(f->path, f->target) != 0) {
            snprintf(msg, msg_size, "%s %.1000s: cannot move the finished file there (%s)",
                     f->option, f->target, strerror(errno));
            ok = false;
        }
        remove_staged(f);
    }
    return ok;
}

void outputs_discard(outputs_t *o)
{
    for (int i = 0; i < OUTPUT_COUNT; i++) {
        remove_staged(&o->files[i]);
    }
}
