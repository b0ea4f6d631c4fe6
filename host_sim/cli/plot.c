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

bool plot_trace(const char *csv_file, const char *png_file, const char *title, char *msg,
                size_t msg_size)
{
    char python[4096];
    char script[4096];
    locate("PMSM_SIM_PYTHON", ".venv/bin/python", python, sizeof(python));
    locate("PMSM_SIM_PLOT_SCRIPT", "tools/plot_trace.py", script, sizeof(script));
    if (access(python, X_OK) != 0) {
        snprintf(msg, msg_size, "no Python at %.1000s: run tools/setup.sh or set PMSM_SIM_PYTHON",
                 python);
        return false;
    }
    if (access(script, R_OK) != 0) {
        snprintf(msg, msg_size, "no plot script at %.1000s: set PMSM_SIM_PLOT_SCRIPT", script);
        return false;
    }
    char title_flag[] = "--title";
    char *const argv[] = { python,        script, (char *)csv_file, (char *)png_file, title_flag,
                           (char *)title, NULL };
    pid_t pid;
    int rc = posix_spawn(&pid, python, NULL, NULL, argv, environ);
    if (rc != 0) {
        snprintf(msg, msg_size, "cannot start %.1000s: %s", python, strerror(rc));
        return false;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0) {
        if (errno != EINTR) {
            snprintf(msg, msg_size, "waiting for the plot script failed: %s", strerror(errno));
            return false;
        }
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        snprintf(msg, msg_size, "the plot script %.1000s failed (status %d)", script,
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
        return false;
    }
    return true;
}
