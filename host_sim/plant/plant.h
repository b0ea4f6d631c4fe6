/*
 * plant.h - PMSM + inverter + sensors plant model of the host simulator.
 *
 * Portable C11 (also built into the Cortex-M4 QEMU image): no allocation, no
 * stdio, no OS calls; double precision. Deterministic: the same config (incl.
 * seeds) and the same inputs give bit-identical results.
 *
 * ---- Conventions -----------------------------------------------------------
 * theta_m  mechanical rotor angle [rad], continuous (not wrapped);
 * theta_e  = n_p * theta_m, electrical angle of the d axis (PM flux axis)
 *          measured from the phase-a magnetic axis [rad];
 * omega_m  = d theta_m / dt [rad/s],  omega_e = n_p * omega_m.
 * Phase currents are positive flowing from the inverter INTO the motor.
 * Clarke/Park are amplitude invariant:
 *   i_alpha = (2 i_a - i_b - i_c)/3,  i_beta = (i_b - i_c)/sqrt(3)
 *   i_d =  cos(theta_e) i_alpha + sin(theta_e) i_beta
 *   i_q = -sin(theta_e) i_alpha + cos(theta_e) i_beta
 * so a balanced set i_a = I cos(theta_e) ... gives i_d = I, and the power
 * into the motor is sum_x v_x i_x = 1.5 (v_d i_d + v_q i_q).
 * Motor model (dq, rotor frame):
 *   v_d = R i_d + Ld di_d/dt - omega_e Lq i_q
 *   v_q = R i_q + Lq di_q/dt + omega_e (Ld i_d + psi)
 *   tau_e = 1.5 n_p (psi i_q + (Ld - Lq) i_d i_q)
 *   domega_m/dt = g3(t) (tau_e - B omega_m - tau_coul(omega_m) - tau_load(t)
 *                        - tau_cog(theta_m)),   g3(t) = 1/J + A sin(Omega t)
 *   (paper 000 section 6; A = 0: constant inertia J).
 *   tau_cog(theta_m) = sum_k A_k cos(k Q theta_m + phi_k)  (paper 002 (2)),
 *   a torque OPPOSING the motion like the load: positive tau_cog brakes.
 *   tau_coul(omega) = Tc * omega / sqrt(omega^2 + eps^2): Coulomb friction,
 *   smoothed over |omega| ~ eps so the ODE stays smooth (no stiction).
 * The plant uses nominal * mismatch multiplier for R, Ld, Lq, psi and J.
 *
 * ---- Inverter (switching-period average model) -----------------------------
 * Terminal voltage of phase x (w.r.t. the negative rail) averaged over a PWM
 * period: d_x v_dc + dead-time and device-drop errors:
 *   v_term_x = d_x v_dc - s(i_x) (t_dead f_pwm v_dc + v_drop)
 * where s() is sign(i) (hard), or i/i_band clipped to [-1, 1] when
 * dead_time_current_band_A > 0 (a linear zone that models the current
 * ripple crossing zero). The star point floats: phase voltages are
 * v_x = v_term_x - mean(v_term_a, v_term_b, v_term_c).
 * Duties are clamped to [0, 1]. v_dc is evaluated once per period at the
 * period centre and held (average model).
 * Outputs disabled (all six switches off): each phase current freewheels
 * through a diode: i_x > 0 sees the negative rail (v_term = 0), i_x < 0 the
 * positive one (v_term = v_dc), so the currents are driven to zero against
 * the bus. Once every |i_x| is below the change one substep can make
 * (2 v_dc h / min(Ld, Lq)), the currents are set to exactly zero and stay
 * zero ("open circuit") while disabled. This model does NOT include diode
 * rectification of a back-EMF larger than the bus: if, while open, the peak
 * line back-EMF sqrt(3) psi |omega_e| exceeds v_dc, the state flag
 * rectification_unmodelled is set (sticky) so a scenario can report it.
 *
 * ---- Sensors (plant_sample) -----------------------------------------------
 * Currents: i_meas_x = Q(gain_x * i_x + offset_x + n_x), n_x ~ N(0, rms^2)
 * Q: mid-tread quantiser, LSB = 2 full_scale / 2^bits, codes clipped to
 * [-2^(bits-1), 2^(bits-1) - 1]; bits == 0 means no quantisation.
 * Bus voltage likewise with its own gain, offset, noise, bits, full scale
 * (codes in [0, 2^bits - 1], LSB = full_scale / 2^bits).
 * Encoder: x4 quadrature, cpr = 4 * lines,
 *   count = floor((theta_m + offset) * cpr / (2 pi)) mod cpr  (0..cpr-1),
 * increasing with theta_m. The index mark is at theta_m + offset = 0 mod
 * 2 pi; encoder_index is true if the shaft crossed it since the previous
 * plant_sample(). lines == 0: no encoder (count 0, index false).
 * Noise comes from the plant's own seeded PRNG (never rand()).
 */
#ifndef SIM_PLANT_H
#define SIM_PLANT_H

#include <stdbool.h>
#include <stdint.h>

#include "profile.h"

#define PLANT_MAX_COG_HARMONICS 8u

/* Defaults of plant_config_default(): 20 kHz PWM, 50 RK4 steps per period
 * (1 us). PLANT_SUBSTEPS_FAST is the fast option (see plant_config_t). */
#define PLANT_DEFAULT_F_PWM_HZ 20000.0
#define PLANT_DEFAULT_SUBSTEPS 50u
#define PLANT_SUBSTEPS_FAST    4u

typedef struct {
    uint32_t slots;                               /* Q: number of stator slots */
    uint32_t n_harmonics;                         /* 0 = no cogging */
    double amplitude_Nm[PLANT_MAX_COG_HARMONICS]; /* A_k of harmonic k+1 */
    double phase_rad[PLANT_MAX_COG_HARMONICS];    /* phi_k of harmonic k+1 */
} plant_cogging_t;

typedef struct {
    double R_ohm;
    double Ld_H;
    double Lq_H; /* Ld == Lq: surface-mounted */
    double psi_Wb;
    uint32_t pole_pairs;
    double J_kgm2;
    double B_Nm_s_rad;
    double tau_coulomb_Nm;    /* 0 = none */
    double coulomb_eps_rad_s; /* smoothing speed, > 0 if tau_coulomb */
    plant_cogging_t cogging;
    double g3_amplitude_per_kgm2; /* A of g3 = 1/J + A sin(Omega t) */
    double g3_omega_rad_s;        /* Omega; |A| < 1/J required */
} plant_motor_params_t;

typedef struct { /* plant = nominal * multiplier; all 1 = no mismatch */
    double R;
    double L; /* both axes */
    double psi;
    double J;
} plant_mismatch_t;

/* When the inverter latches the duties computed from a sample (the timer's
 * update event; the engine applies it, see sim_engine.h). */
typedef enum {
    PLANT_DUTY_UPDATE_NEXT_PERIOD = 0, /* at the next period start: 1.5 Ts */
    PLANT_DUTY_UPDATE_HALF_PERIOD      /* half a period later: 1.0 Ts */
} plant_duty_update_t;

typedef struct {
    double f_pwm_Hz;
    plant_duty_update_t duty_update;
    sim_profile_t v_dc_V;
    double t_dead_s;
    double v_device_drop_V;
    double dead_time_current_band_A; /* 0 = hard sign(i) */
} plant_inverter_params_t;

typedef struct {
    double gain[3]; /* per phase, 1 = ideal */
    double offset_A[3];
    double noise_rms_A;
    uint32_t adc_bits;   /* 0 = ideal (no quantisation), else 1..24 */
    double full_scale_A; /* measurable range [-full_scale, +full_scale) */
} plant_current_sensor_t;

typedef struct {
    double gain;
    double offset_V;
    double noise_rms_V;
    uint32_t adc_bits;   /* 0 = ideal, else 1..24 */
    double full_scale_V; /* range [0, full_scale) */
} plant_vdc_sensor_t;

typedef struct {
    uint32_t lines;    /* 0 = no encoder; cpr = 4 * lines */
    double offset_rad; /* mechanical, added to theta_m */
} plant_encoder_t;

typedef struct {
    plant_current_sensor_t current;
    plant_vdc_sensor_t vdc;
    plant_encoder_t encoder;
    uint64_t seed;
} plant_sensor_params_t;

typedef struct {
    plant_motor_params_t motor;
    plant_mismatch_t mismatch;
    plant_inverter_params_t inverter;
    plant_sensor_params_t sensors;
    sim_profile_t load_torque_Nm; /* opposes positive rotation when > 0 */
    /* Classic RK4 steps per PWM period. PLANT_DEFAULT_SUBSTEPS (1 us at
     * 20 kHz) is the reference; PLANT_SUBSTEPS_FAST (12.5 us) is the fast
     * option, ~10x faster: test_plant_electrical keeps it within 1e-5 A and
     * 1e-7 rad/s of the reference over 1 s of random duties at 3000 rpm (with
     * dead time, dead_time_current_band_A > 0). With the hard sign(i)
     * dead-time model the zero crossings are discontinuities that no fixed
     * step resolves: both step sizes then chatter around i = 0 differently. */
    uint32_t substeps_per_period;
    bool locked_rotor; /* omega_m held at 0, theta_m at theta_m0 */
    double theta_m0_rad;
    double omega_m0_rad_s;
} plant_config_t;

typedef struct {         /* all in J, integrated with the state (RK4) from t = 0 */
    double bus_J;        /* int v_dc * sum d_x i_x dt (drawn from the bus) */
    double electrical_J; /* int sum v_x i_x dt  (into the motor terminals) */
    double copper_J;     /* int 1.5 R (i_d^2 + i_q^2) dt */
    double friction_J;   /* int omega_m (B omega_m + tau_coul) dt */
    double load_J;       /* int omega_m tau_load dt */
    double cogging_J;    /* int omega_m tau_cog dt */
} plant_energy_t;

typedef struct {
    double t_s;
    double i_d_A, i_q_A;
    double i_abc_A[3];
    double omega_m_rad_s;
    double theta_m_rad; /* continuous */
    double theta_e_rad; /* n_p * theta_m wrapped to [0, 2 pi) */
    double tau_e_Nm;
    double tau_load_Nm;
    double tau_cog_Nm;
    double tau_friction_Nm; /* B omega + Coulomb */
    double v_abc_V[3];      /* phase voltages averaged over the last period */
    double v_dc_V;          /* bus voltage held during the last period */
    bool outputs_enabled;
    bool open_circuit;             /* disabled and currents extinguished */
    bool rectification_unmodelled; /* see the inverter notes above */
    plant_energy_t energy;
} plant_true_state_t;

typedef struct {
    double t_s;
    double i_abc_A[3];
    double v_dc_V;
    uint32_t encoder_count; /* 0 .. 4*lines - 1 */
    bool encoder_index;     /* index crossed since the previous sample */
} plant_measurement_t;

typedef enum {
    PLANT_OK = 0,
    PLANT_ERR_NULL = -1,
    PLANT_ERR_MOTOR = -2,    /* bad motor parameter */
    PLANT_ERR_MISMATCH = -3, /* multiplier not finite and > 0 */
    PLANT_ERR_INVERTER = -4,
    PLANT_ERR_SENSOR = -5,
    PLANT_ERR_PROFILE = -6, /* v_dc or load profile invalid */
    PLANT_ERR_SOLVER = -7,  /* substeps / initial state */
    PLANT_ERR_STATE = -8    /* plant_advance on a non-initialised plant */
} plant_err_t;

#define PLANT_PRIVATE_STATE_LEN 13u

/* Private: the caller owns the storage; use the functions below. */
typedef struct {
    plant_config_t cfg;
    double R_ohm, Ld_H, Lq_H, psi_Wb, inv_J_per_kgm2; /* with mismatch */
    double n_p;
    double cog_cos_phi[PLANT_MAX_COG_HARMONICS];
    double cog_sin_phi[PLANT_MAX_COG_HARMONICS];
    double period_s, h_s;
    double x[PLANT_PRIVATE_STATE_LEN];
    double t_s;
    uint64_t n_periods; /* t_s = n_periods * period_s */
    bool open_circuit;
    bool rectification_unmodelled;
    uint64_t rng_state;
    bool have_spare_gauss;
    double spare_gauss;
    int64_t encoder_turns; /* floor((theta_m + offset) / 2 pi) at last sample */
    plant_true_state_t view;
    const char *err_msg;
    bool initialised;
} plant_t;

/* Fills a valid config: the paper 001 motor (R 0.225 ohm, L 3.8 mH,
 * psi 0.17 Wb, n_p 3, J 0.012 kg m^2, B 0), 48 V constant bus, 20 kHz,
 * no dead time, ideal sensors, 2500-line encoder, zero load, no mismatch,
 * PLANT_DEFAULT_SUBSTEPS, rotor at rest at theta_m = 0. */
void plant_config_default(plant_config_t *cfg);

/* Returns PLANT_OK or a negative plant_err_t; *msg (if msg != NULL) gets a
 * static sentence naming the offending field ("ok" on success). */
int plant_config_validate(const plant_config_t *cfg, const char **msg);

/* Validates and copies cfg; state at t = 0: currents 0, theta_m0, omega_m0,
 * outputs enabled. On error the plant is left non-initialised. */
int plant_init(plant_t *p, const plant_config_t *cfg);

/* Message of the last plant_init() ("ok" after success). */
const char *plant_error_message(const plant_t *p);

/* What the ADC/encoder see now (the PWM centre in the simulator's timing):
 * consumes PRNG draws only when noise is configured. */
void plant_sample(plant_t *p, plant_measurement_t *m);

/* Integrates exactly one PWM period (1/f_pwm) with duty_abc held (clamped to
 * [0, 1]); outputs_enabled == false models all switches off (see above). */
void plant_advance(plant_t *p, const double duty_abc[3], bool outputs_enabled);

/* Integrates one PWM period whose first half has duty_first / outputs_first
 * and second half duty_second / outputs_second (duties that change at the
 * middle of the period: an update event half a period after the sample).
 * plant_config_validate requires an even substeps_per_period with
 * PLANT_DUTY_UPDATE_HALF_PERIOD, so the change falls on a substep boundary
 * (called with an odd count, the change is at substep floor(n/2)). */
void plant_advance_split(plant_t *p, const double duty_first[3], bool outputs_first,
                         const double duty_second[3], bool outputs_second);

/* Integrates one PWM period with an IDEAL rotor-frame voltage source
 * v_d, v_q (no inverter, no dead time): model checks and identification. */
void plant_advance_vdq(plant_t *p, double v_d_V, double v_q_V);

/* True state after the last advance (valid until the next advance). */
const plant_true_state_t *plant_true_state(const plant_t *p);

/* Period length [s] (1 / f_pwm). */
double plant_period_s(const plant_t *p);

#endif /* SIM_PLANT_H */
