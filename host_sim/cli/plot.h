/*
 * PNG plot of a CSV trace by tools/plot_trace.py, run with the project's
 * Python virtual environment (tools/setup.sh creates it in <repo>/.venv).
 *
 * Located through, in order:
 *   python: $PMSM_SIM_PYTHON, else <source dir>/.venv/bin/python
 *   script: $PMSM_SIM_PLOT_SCRIPT, else <source dir>/tools/plot_trace.py
 * where <source dir> is the project source tree this binary was built from.
 */
#ifndef PMSM_SIM_PLOT_H
#define PMSM_SIM_PLOT_H

#include <stdbool.h>
#include <stddef.h>

/* Before a run: the Python and the script exist and the script's --check
 * (its imports) succeeds; false with msg saying what is missing. */
bool plot_check_environment(char *msg, size_t msg_size);

/* Run the plot script; false with msg when it cannot be found or fails. */
bool plot_trace(const char *csv_file, const char *png_file, const char *title, char *msg,
                size_t msg_size);

#endif /* PMSM_SIM_PLOT_H */
