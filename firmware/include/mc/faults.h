/*
 * Fault codes and the protection checks of the fast ISR.
 *
 * Faults are bits of a uint32_t mask. mc_faults_check_sample() evaluates the
 * conditions of one sample (which causes are present NOW); the application
 * latches them (mc/app.h): a latched fault disables the PWM outputs in the
 * same ISR call and is cleared only by an explicit command once its cause is
 * gone.
 */
#ifndef MC_FAULTS_H
#define MC_FAULTS_H

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#include "mc/compiler.h"
#include "mc/finite.h"
#include "mc/status.h"

typedef enum {
    MC_FAULT_NONE = 0u,
    MC_FAULT_OVERCURRENT = 1u << 0,     /* |i_a|, |i_b| or |i_c| > trip level */
    MC_FAULT_DC_OVERVOLTAGE = 1u << 1,  /* v_dc > v_dc_max_V */
    MC_FAULT_DC_UNDERVOLTAGE = 1u << 2, /* v_dc < v_dc_min_V (while powered) */
    MC_FAULT_NONFINITE = 1u << 3,       /* NaN/Inf in a measurement, estimate,
                                           reference or output */
    MC_FAULT_ISR_OVERRUN = 1u << 4,     /* fast-ISR cost > PWM period */
    MC_FAULT_EXTERNAL = 1u << 5,        /* fault/STO input asserted */
    MC_FAULT_CALIBRATION = 1u << 6,     /* current offset outside its limit */
    MC_FAULT_ENCODER = 1u << 7,         /* count outside [0, cpr), or the
                                           encoder's angle/speed against the
                                           measured back-EMF (slip, freeze:
                                           mc/emf_monitor.h) */
    MC_FAULT_ESTIMATE = 1u << 8,        /* sensorless estimate implausible
                                           (speed, load or flux out of its
                                           bounds: diverged observer;
                                           tested on the slow tick, the
                                           flux's lower bound every
                                           sample: mc/est_flux_front.h) */
    MC_FAULT_OVERSPEED = 1u << 9,       /* |omega_m_hat| > overspeed_rad_s */
    MC_FAULT_STALL = 1u << 10,          /* high current at near-zero speed
                                           for stall_time_s */
    MC_FAULT_I2T = 1u << 11,            /* thermal model: sustained current
                                           above the continuous rating */
    MC_FAULT_CURRENT_SENSOR = 1u << 12, /* |i_a + i_b + i_c| implausible
                                           (offset drift, stuck channel) */
    MC_FAULT_LOSS_OF_LOCK = 1u << 13,   /* sensorless: the estimate turns,
                                           the measured back-EMF says the
                                           rotor does not */
    MC_FAULT_CURRENT_LIMIT = 1u << 14,  /* the current-limit loop acted
                                           for current_limit_time_s without
                                           a break */
    MC_FAULT_COMM_TIMEOUT = 1u << 15    /* no valid command within the
                                           command link's timeout while
                                           enabled (mc_command_t.comm_lost;
                                           reaction: PWM off, coast) */
} mc_fault_t;

/* Every fault bit (for masks and reports). */
#define MC_FAULT_ALL ((uint32_t)((MC_FAULT_COMM_TIMEOUT << 1) - 1u))

/* Protection thresholds (SI units): the configuration block "protection". */
typedef struct {
    float i_trip_A;       /* over-current trip on each phase, > 0 */
    float v_dc_max_V;     /* over-voltage trip, > v_dc_min_V */
    float v_dc_min_V;     /* under-voltage trip, >= 0 (0: off; a
                             drive still trips below FLT_MIN, where it
                             could not modulate: mc/app.h) */
    float i_offset_max_A; /* calibration fault above this offset, > 0 */
    float estimate_omega_max_rad_s; /* |omega_m_hat| above:
                                       MC_FAULT_ESTIMATE, > 0 */
    float estimate_tau_max_Nm;      /* |tau_L_hat| above:
                                       MC_FAULT_ESTIMATE, > 0 */
    float overspeed_rad_s;          /* |omega_m_hat| above (RUN, ALIGN):
                                       MC_FAULT_OVERSPEED, > 0 */
    float stall_current_A;          /* stall: |i_dq| above this ... > 0 */
    float stall_speed_rad_s;        /* ... at |omega_m_hat| below this ...
                                       > 0 */
    float stall_time_s;             /* ... for this long (RUN):
                                       MC_FAULT_STALL, > 0 */
    float current_limit_A;          /* measured |i_dq| above: the current-
                                       limit loop acts on the voltage of
                                       every controller (mc/current_limit.h),
                                       >= limits.i_max_A, < i_trip_A */
    float current_limit_time_s;     /* the loop acting this long without a
                                       break: MC_FAULT_CURRENT_LIMIT, > 0 */
    float i2t_continuous_A;         /* thermal model: no heating below this
                                       |i_dq|, > 0 */
    float i2t_peak_A;               /* ... this current may flow for ... */
    float i2t_peak_time_s;          /* ... this long from cold:
                                       integral (|i|^2 - i_cont^2) dt >
                                       (i_peak^2 - i_cont^2) t_peak is
                                       MC_FAULT_I2T; i_peak > i_cont */
    float current_sum_max_A;        /* |i_a + i_b + i_c| above ... > 0 */
    float current_sum_time_s;       /* ... for this long (RUN, ALIGN):
                                       MC_FAULT_CURRENT_SENSOR, > 0 */
} mc_fault_limits_t;

/* Check the limits: all finite, i_trip_A > 0, 0 <= v_dc_min_V < v_dc_max_V,
 * current_limit_A < i_trip_A, i2t_peak_A > i2t_continuous_A, the others
 * > 0. Returns MC_OK, MC_ERR_NONFINITE (a NaN/Inf limit) or
 * MC_ERR_PARAM.
 * Interrupt context: no (init only). */
mc_status_t mc_fault_limits_validate(const mc_fault_limits_t *limits);

/* Causes present in one sample of phase currents (A, offset-corrected;
 * by value, so a fast path's caller keeps them in registers) and DC-bus
 * voltage (V). check_undervoltage: false while the drive is IDLE
 * (the bus may legitimately be down); the application checks it in every
 * other state, FAULT included, so a clear waits for the bus. A non-finite
 * current or voltage gives MC_FAULT_NONFINITE (and no other bit for that
 * quantity).
 * Interrupt context: yes (bounded, no division). */
uint32_t mc_faults_check_sample(const mc_fault_limits_t *limits, float i_a_A,
                                float i_b_A, float i_c_A, float v_dc_V,
                                bool check_undervoltage);

/* The bus voltage within its limits (each comparison false for a NaN; an
 * infinite voltage exceeds the maximum or -FLT_MAX): at most v_dc_max_V,
 * and at least v_dc_min_V, or without the under-voltage check -FLT_MAX
 * (the validated v_dc_min_V >= 0 is above it: the same as "v_dc_min_V or
 * else -FLT_MAX"). Interrupt context: yes. */
MC_STATIC_FORCEINLINE bool mc_faults_bus_clear(const mc_fault_limits_t *limits,
                                               float v_dc_V,
                                               bool check_undervoltage)
{
    const float v_min_V = check_undervoltage ? limits->v_dc_min_V : -FLT_MAX;
    return MC_LIKELY(v_dc_V <= limits->v_dc_max_V && v_dc_V >= v_min_V);
}

/* The same result, for the fast ISR: one chain of comparisons decides
 * that no cause is present (each is false for a NaN; an infinite current
 * exceeds the trip level) and only a sample that fails it is classified
 * by mc_faults_check_sample. Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_faults_check_sample_fast(
    const mc_fault_limits_t *limits, const float i_abc_A[3], float v_dc_V,
    bool check_undervoltage)
{
    const float i_max = limits->i_trip_A;
    if (MC_LIKELY(fabsf(i_abc_A[0]) <= i_max && fabsf(i_abc_A[1]) <= i_max &&
                  fabsf(i_abc_A[2]) <= i_max &&
                  mc_faults_bus_clear(limits, v_dc_V, check_undervoltage))) {
        return MC_FAULT_NONE;
    }
    return mc_faults_check_sample(limits, i_abc_A[0], i_abc_A[1], i_abc_A[2],
                                  v_dc_V, check_undervoltage);
}

/* For a drive whose phase-current levels the HAL's comparators watch
 * (hal_pwm_overcurrent_arm): no cause if the bus is within its limits,
 * else mc_faults_check_sample's classification of the whole sample. The
 * currents are not tested here, their finiteness neither: a non-finite
 * current reaches the estimator's or the controller's one finiteness test
 * in the same ISR (MC_FAULT_NONFINITE there). Interrupt context: yes. */
MC_STATIC_FORCEINLINE uint32_t mc_faults_check_bus_fast(
    const mc_fault_limits_t *limits, const float i_abc_A[3], float v_dc_V,
    bool check_undervoltage)
{
    if (MC_LIKELY(mc_faults_bus_clear(limits, v_dc_V, check_undervoltage))) {
        return MC_FAULT_NONE;
    }
    return mc_faults_check_sample(limits, i_abc_A[0], i_abc_A[1], i_abc_A[2],
                                  v_dc_V, check_undervoltage);
}

#endif /* MC_FAULTS_H */
