/*
 * The drive's supervision, whatever the controller and estimator, one
 * step per slow tick (the application's decimation, mc/app.h: the
 * samples it sees are every N-th fast sample; the persistence times count
 * steps of that period) (thresholds: the protection block, mc/faults.h):
 *   overspeed   |omega_m_hat| > overspeed_rad_s (RUN, ALIGN)
 *   stall       |i_dq| > stall_current_A at |omega_m_hat| <
 *               stall_speed_rad_s for stall_time_s (RUN)
 *   I^2 t       x' = |i_dq|^2 - i_cont^2 (x >= 0, every state: a stopped
 *               motor cools at i_cont^2), fault while x > (i_peak^2 -
 *               i_cont^2) t_peak: a current i_peak may flow for t_peak from
 *               cold, i_cont for ever; after the fault the drive cools for
 *               (x - limit) / i_cont^2 before a clear is accepted
 *   limit       the current-limit loop (mc/current_limit.h) acting for
 *               current_limit_time_s without a break (RUN)
 *   sensor sum  |i_a + i_b + i_c| > current_sum_max_A for
 *               current_sum_time_s (RUN, ALIGN): an offset drift, a stuck
 *               or open channel (three sensors on a floating star carry no
 *               zero sequence)
 * The thermal state survives a stop and a fault (the motor stays hot).
 */
#ifndef MC_SUPERVISOR_H
#define MC_SUPERVISOR_H

#include <stdbool.h>
#include <stdint.h>

#include "mc/drive_io.h"
#include "mc/faults.h"
#include "mc/status.h"

typedef struct {
    float overspeed_rad_s;
    float stall_current_sq_A2, stall_speed_rad_s;
    uint32_t stall_n, stall_count;
    float i2t_cont_sq_A2, i2t_limit_A2s, step_s;
    float i2t_A2s;      /* thermal state, >= 0 */
    float i2t_comp_A2s; /* Kahan compensation of its sum: the per-sample
                           increment is far below the state's ulp near the
                           limit (a 5.01 A current would never trip) */
    float sum_max_A;
    uint32_t sum_n, sum_count;
    uint32_t limit_n, limit_count;
} mc_supervisor_t;

/* From the (validated) protection block and the period of the steps,
 * step_s > 0; the thermal state starts cold. Times are rounded to whole
 * steps; MC_ERR_PARAM when one rounds to none. Interrupt context: no. */
mc_status_t mc_supervisor_init(mc_supervisor_t *sv,
                               const mc_fault_limits_t *lim, float step_s);

/* One step: t holds the offset-corrected phase currents, the measured
 * i_d, i_q and the speed estimate. running: RUN; powered: RUN or ALIGN;
 * limiting: the current-limit loop is acting. Returns the fault bits
 * present (OVERSPEED, STALL, I2T, CURRENT_SENSOR, CURRENT_LIMIT).
 * Interrupt context: yes (bounded, no division). */
uint32_t mc_supervisor_step(mc_supervisor_t *sv, const mc_telemetry_t *t,
                            bool running, bool powered, bool limiting);

#endif /* MC_SUPERVISOR_H */
