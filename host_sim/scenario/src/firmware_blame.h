/*
 * Which keys to name when mc_config_validate() rejects the configuration
 * of a scenario's "firmware" section (private to sim_scenario).
 *
 * The firmware's validation is the one judge of the values, so the reader
 * asks it: a number key (F32, U32) is named when some other value of it
 * alone makes the configuration valid (its value scaled by 2^(k/16),
 * k = +-1..+-160: steps of 4.4 % up to a factor of 1024 either way, or its
 * default). A rule
 * between keys (the speed loop at most half the PLL bandwidth, i_max below
 * the trip level, ...) therefore names every key it involves, whether the
 * file gives it or not, and a range error names its one key. For each key
 * the message gives a value that alone makes the configuration valid,
 * found by bisection towards the rule's boundary and rounded to two
 * significant digits or more (checked valid again). The switches (booleans, the controller and the
 * estimator) are tried only when no number key can help: another
 * controller or estimator turns off the checks of the selected one's
 * blocks and would hide the value that is really wrong. A switch is named
 * when the file gives it and its default makes the configuration valid;
 * when nothing alone helps the error is at "firmware".
 */
#ifndef SIM_SCENARIO_FIRMWARE_BLAME_H
#define SIM_SCENARIO_FIRMWARE_BLAME_H

#include <stddef.h>

#include "mc/config.h"
#include "sim/json_reader.h"

/* Record the error for cfg, which mc_config_validate() rejected with st.
 * objects[i] is the reader's object of the i-th block of mc_config_params()
 * (NULL json when the file does not have it); fw is the "firmware" object. */
void scenario_firmware_blame(jr_object_t *fw, jr_object_t *objects, const mc_config_t *cfg,
                             mc_status_t st);

#endif /* SIM_SCENARIO_FIRMWARE_BLAME_H */
