/*
 * Time profiles (plant/profile.h) from a scenario key. Private to sim_scenario.
 *
 * A profile key holds either a number (a constant) or an object:
 *   {
 *     "points": [[t_s, value], ...],   piecewise linear, times non-decreasing
 *                                      (two points at one time = a step)
 *     "sines":  [{"amplitude": a, "freq_Hz": f, "phase_rad": p, "t_start_s": t0}],
 *     "poly":   {"coeffs": [c0, c1, ...], "t_start_s": t0},
 *     "noise":  {"rms": r, "cutoff_Hz": fc, "seed": s}
 *   }
 * every part optional (the profile is their sum). Values are in the unit the
 * key names; scale converts them to SI (e.g. 2 pi / 60 for "speed_rpm").
 */
#ifndef SIM_SCENARIO_PROFILE_READER_H
#define SIM_SCENARIO_PROFILE_READER_H

#include <stdbool.h>

#include "profile.h"
#include "sim/json_reader.h"

/* Reads obj.key into *out. Absent: SCN_ERR_MISSING if required, else *out
 * keeps what it holds (the caller's default). */
bool profile_read(jr_object_t *obj, const char *key, bool required, double scale,
                  sim_profile_t *out);

#endif /* SIM_SCENARIO_PROFILE_READER_H */
