/*
 * Sensorless start from any rotor angle (test_p001_start_sweep.c, built
 * once per controller and half of the angles so each executable stays
 * short under ASan): the benchmark of test_p001_bench.h up to the end
 * of the 50 rpm hold (tb = 2.5 s, through the 1 N m load step at tb = 1 s)
 * from P001_SWEEP_N initial rotor angles (plant theta_m0), B = 0, no load
 * before tb = 1 s, nominal parameters.
 *
 * Acceptance for every angle: no fault; RUN before tb = 0; at the first RUN
 * sample the TRUE electrical angle within 0.02 rad of align.angle_e_rad
 * (where the observers start) and |omega_m| <= 0.01 rad/s (0.1 rpm); peak
 * phase current during ALIGN <= 3 A (the nominal acceptance's peak;
 * hypot(2 A, 2 A) = 2.83 A by design); then, like the nominal run: RMS
 * speed error in the 50 rpm hold (tb 1.5-2.5 s) <= 0.05 rpm (the
 * nominal RMS acceptance), dip after the 1 N m step <= 20 rpm, RMS
 * electrical angle error at 50 rpm (tb 1.5-2.5 s) <= 1e-3 rad.
 */
#ifndef P001_START_SWEEP_H
#define P001_START_SWEEP_H

#include "test_p001_bench.h"

/* Electrical offsets from the alignment angle: k * 30 deg, k = 0..11
 * (180 deg, the dead point of a one-step alignment, at k = 6; 270 deg, the
 * dead point of the first phase, at k = 9), then 180 deg - 1 mrad. */
#define P001_SWEEP_N 13u

double p001_sweep_offset_e_rad(unsigned k);

/* Run the cases k_begin <= k < k_end with this controller and assert the
 * acceptance of each. */
void p001_sweep_assert_range(mc_controller_t controller, unsigned k_begin, unsigned k_end);

#endif /* P001_START_SWEEP_H */
