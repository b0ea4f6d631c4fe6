/* Plot a CSV trace with the project's Python (see plot.h). */
#define _POSIX_C_SOURCE 200809L

#include "plot.h"

#include <errno.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#ifndef PMSM_SIM_SOURCE_DIR
#error "PMSM_SIM_SOURCE_DIR (the project source tree) must be defined by the build"
#endif

extern char **environ;

/* $env_name if set, else PMSM_SIM_SOURCE_DIR/relative. */
static void locate(const char *env_name, const char *relative, char *buf, size_t size)
{
    const char *from_env = getenv(env_name);
    if (from_env != NULL && from_env[0] != '\0') {
        snprintf(buf, size, "%s", from_env);
    } else {
        snprintf(buf, size, "%s/%s", PMSM_SIM_SOURCE_DIR, relative);
    }
}

/* The Python and the script (see plot.h); false with msg when either is
 * missing. */
static bool locate_environment(char *python, char *script, size_t size, char *msg, size_t msg_size)
{
    locate("PMSM_SIM_PYTHON", ".venv/bin/python", python, size);
    locate("PMSM_SIM_PLOT_SCRIPT", "tools/plot_trace.py", script, size);
    if (access(python, X_OK) != 0) {
        snprintf(msg, msg_size,
                 "no Python at %.1000s (%s): run tools/setup.sh or set PMSM_SIM_PYTHON", python,
                 strerror(errno));
        return false;
    }
    if (access(script, R_OK) != 0) {
        snprintf(msg, msg_size, "no plot script at %.1000s (%s): set PMSM_SIM_PLOT_SCRIPT", script,
                 strerror(errno));
        return false;
    }
    return true;
}

/* Run argv[0] (the Python) and wait; false with msg unless it exits 0. */
static bool run_python(char *const argv[], const char *what, char *msg, size_t msg_size)
{
    pid_t pid;
    int rc = posix_spawn(&pid, argv[0], NULL, NULL, argv, environ);
    if (rc != 0) {
        snprintf(msg, msg_size, "cannot start %.1000s: %s", argv[0], strerror(rc));
        return false;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            snprintf(msg, msg_size, "waiting for %s failed: %s", what, strerror(errno));
            return false;
        }
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        snprintf(msg, msg_size, "%s %.1000s failed (%s %d)", what, argv[1],
                 WIFEXITED(status) ? "exit status" : "signal",
                 WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
        return false;
    }
    return true;
}

bool plot_check_environment(char *msg, size_t msg_size)
{
    char python[4096];
    char script[4096];
    if (!locate_environment(python, script, sizeof(python), msg, msg_size)) {
        return false;
    }
    char check_flag[] = "--check";
    char *const argv[] = { python, script, check_flag, NULL };
    char detail[2048];
    if (!run_python(argv, "the plotting environment check", detail, sizeof(detail))) {
        snprintf(msg, msg_size,
                 "the plotting environment is not usable: %s (its Python cannot import what "
                 "the script needs: run tools/setup.sh, or set PMSM_SIM_PYTHON / "
                 "PMSM_SIM_PLOT_SCRIPT)",
                 detail);
        return false;
    }
    return true;
}

bool plot_trace(const char *csv_file, const char *png_file, const char *title, char *msg,
                size_t msg_size)
{
    char python[4096];
    char script[4096];
    if (!locate_environment(python, script, sizeof(python), msg, msg_size)) {
        return false;
    }
    char title_flag[] = "--title";
    char *const argv[] = { python,        script, (char *)csv_file, (char *)png_file, title_flag,
                           (char *)title, NULL };
    return run_python(argv, "the plot script", msg, msg_size);
}
