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
 * Duties are clamped to [0, 1]. A stiff v_dc is evaluated once per period at
 * the period centre and held (average model; see DC link).
 * Outputs disabled (all six switches off): a six-diode bridge. Each phase
 * terminal reaches the + rail through its upper diode (conducting while the
 * current flows out of the motor, i_x < 0: v_term_x = v_dc + v_f) and the
 * - rail through its lower diode (i_x > 0: v_term_x = -v_f), v_f =
 * v_device_drop_V (0 = ideal diodes). Per phase the conduction state
 * (plant_phase_state_t) is part of the plant state:
 *   all three conducting: the terminal voltages are known; the dq model
 *     above gives di/dt;
 *   one phase x blocking (i_x = 0), the other two conducting: x's terminal
 *     floats at the voltage u that keeps di_x/dt = 0. u enters v_d, v_q
 *     linearly (through v_x - mean(v_term)), so di_x/dt = 0 with
 *       i_x = c_x i_d - s_x i_q,  c_x = cos(theta_e - 2 pi k/3),
 *       s_x = sin(theta_e - 2 pi k/3) (k = 0, 1, 2 for a, b, c),
 *       di_x/dt = c_x di_d/dt - s_x di_q/dt - omega_e (s_x i_d + c_x i_q)
 *     is one linear equation in u, with the coefficient
 *     (2/3) (c_x^2 / Ld + s_x^2 / Lq) > 0 (salient machines included);
 *   two or three blocking: all currents are zero; the phases show the
 *     back-EMF (v_d = 0, v_q = omega_e psi).
 * Mode changes (events, each located inside the RK4 substep by Illinois
 * regula falsi on the step length, to 1e-9 of a substep, and applied on the
 * far side of the crossing):
 *   a conducting phase whose current reaches zero blocks (its current is
 *     set to exactly zero: a diode does not conduct backwards);
 *   the blocking phase of the one-blocking mode starts to conduct when u
 *     leaves [-v_f, v_dc + v_f] (below: lower diode, above: upper diode);
 *   with all currents zero, conduction starts in the pair y, z of connected
 *     phases with the largest line back-EMF |e_y - e_z| once it exceeds
 *     v_dc + 2 v_f (the higher one on the upper diode).
 * While a phase floats the state is projected after every substep onto
 * i_x = 0 (the other two carry +I and -I exactly); the true state reports
 * floating phases with exactly 0 A. On entering the diode mode (outputs
 * switched off) each phase takes the diode of its current's sign (a zero
 * current blocks). The bridge draws i_bridge = sum of the currents of the
 * phases on the upper diode from the + rail (negative: rectifying into the
 * link); switching, the average model draws sum d_x i_x.
 *
 * ---- DC link (plant_dc_link_t) ---------------------------------------------
 * capacitance_F == 0: a stiff bus, v_dc = inverter.v_dc_V evaluated at the
 * middle of each period and held over it (it sources and sinks any current).
 * capacitance_F > 0: the link voltage v is a state (RK4 with the others),
 *   C dv/dt = i_source - i_bridge - i_brake,
 *   i_source = max(0, (v_s(t) - v) / R_s) while the source is connected (a
 *     series diode: the source cannot sink current), v_s = inverter.v_dc_V
 *     evaluated at each RK4 stage (on the piece of the step's midpoint);
 *   i_brake = v / R_b while the brake chopper is on: a hysteresis shunt
 *     regulator, on once v > brake_on_V, off once v < brake_off_V (events,
 *     located like the bridge's); initially on iff v0 > brake_on_V;
 *   v(0) = v0_V if v0_given, else max(v_s(0), 0).
 * The switching model then uses the instantaneous v in d_x v and in the
 * dead-time error t_dead f_pwm v. A link driven below -v_f (the drive still
 * drawing current with its source lost) is clamped there by the inverter
 * legs (a switch and the opposite leg diode from the - to the + rail): the
 * legs carry i_clamp = i_bridge + i_brake - i_source >= 0, dv/dt = 0, until
 * i_clamp returns to zero (events as above).
 *
 * ---- Runtime faults ---------------------------------------------------------
 * plant_set_phase_open, plant_set_rotor_locked, plant_set_source_connected,
 * plant_set_dead_time (below) take effect at the start of the next advance. Instantaneous
 * changes they imply (the current of a phase that opens, the kinetic energy
 * of a rotor that locks) and the residuals of the zero-current clamps leave
 * the state without passing through the integrated power flows: their
 * energy is counted in plant_energy_t.constraint_J.
 *
 * ---- Energy balance (plant_energy_t) ---------------------------------------
 *   electrical_J = copper_J + friction_J + load_J + cogging_J + constraint_J
 *                  + change of 0.75 (Ld i_d^2 + Lq i_q^2) + change of
 *                  0.5 J omega_m^2 (J with mismatch; constant inertia);
 *   bus_J - electrical_J = inverter losses (dead time, device drops);
 *   with a capacitance:
 *   source_J = source_resistor_J + capacitor_J + brake_J + bus_J
 *              + link_clamp_J.
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

/* Defaults of plant_config_default(): 20 kHz PWM, 50 substeps per period
 * (1 us). PLANT_SUBSTEPS_FAST is the fast option (see plant_config_t). */
#define PLANT_DEFAULT_F_PWM_HZ 20000.0
#define PLANT_DEFAULT_SUBSTEPS 50u
#define PLANT_SUBSTEPS_FAST    4u

/* Integrators. PLANT_SOLVER_EXACT (the default) takes a substep of the
 * switching plant in closed form (plant_exact.c): with the inverter's
 * voltage held, the stator current in d-q is the exact solution of
 * L di/dt = v - R i - j omega_e (L i + psi) for omega_e held at the
 * substep's mean speed (the back-EMF's response by the Taylor series of
 * (exp(z) - 1) / z, z = (R / L + j omega_e) h, while |z| <= 2^-10: no
 * division), plus the first correction for the speed's change within the
 * substep; the rotor angle is advanced as a unit vector
 * (exp(j omega_e h) by its Taylor series, no libm call a substep); the
 * speed from the mean electrical torque (trapezoid with end correction,
 * exact for cubics) and the other torques at the substep's middle; the
 * energies by the same quadrature. It is used where that model holds:
 * Ld == Lq, the inverter switching (outputs on) with every phase driven
 * and a stiff bus (no link capacitance). Everything else is RK4:
 * Ld != Lq (reluctance torque), outputs off (freewheeling diodes, open
 * circuit: conduction events), an open phase, the diode bridge, a DC
 * link with capacitance, and a substep in which a phase current enters
 * or leaves the dead-time model's linear zone (or crosses zero with the
 * hard sign): the dead-time voltage error is constant otherwise, so it is
 * part of the held voltage. Load, friction, cogging and g3 enter only the
 * mechanics and are evaluated at the substep's middle (any profile).
 * Agreement with RK4 at 1 us on the paper-001 benchmark: 2e-12 relative
 * (tests/sim/test_sim_exact_vs_rk4.c). PLANT_SOLVER_RK4 is classic RK4 in
 * every mode. */
typedef enum {
    PLANT_SOLVER_EXACT = 0, /* exact electrical step where the model is linear, else RK4 */
    PLANT_SOLVER_RK4        /* classic RK4 in every mode */
} plant_solver_method_t;

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
    bool overcurrent_comparator;     /* the board compares the phase
                                        currents in hardware at the level
                                        the firmware arms
                                        (hal_pwm_overcurrent_arm; the
                                        engine at each sample); false */
} plant_inverter_params_t;

/* The DC link behind the inverter (model in the notes above). */
typedef struct {
    double capacitance_F;         /* 0 = stiff bus (the default) */
    double source_resistance_ohm; /* > 0 with a capacitance, else 0 */
    double brake_resistance_ohm;  /* 0 = no brake chopper; needs a capacitance */
    double brake_on_V;            /* > brake_off_V with a brake, else 0 */
    double brake_off_V;           /* >= 0 with a brake, else 0 */
    bool v0_given;                /* false: v(0) = max(source voltage at t = 0, 0) */
    double v0_V;                  /* initial link voltage, >= 0 (capacitance only) */
} plant_dc_link_t;

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
    plant_dc_link_t dc_link;
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
    plant_solver_method_t solver_method; /* PLANT_SOLVER_EXACT by default */
    bool locked_rotor; /* initial state of plant_set_rotor_locked (omega_m0 ignored) */
    double theta_m0_rad;
    double omega_m0_rad_s;
} plant_config_t;

/* Energies [J] since t = 0, integrated with the state (RK4) unless noted;
 * the balances they close are in the notes above. */
typedef struct {
    double bus_J;             /* int v_dc i_bridge dt, drawn by the bridge from the link
                               * (< 0: regenerated); plant_advance_vdq periods add the
                               * ideal source's 1.5 (v_d i_d + v_q i_q) instead */
    double electrical_J;      /* int sum v_x i_x dt  (into the motor terminals) */
    double copper_J;          /* int 1.5 R (i_d^2 + i_q^2) dt */
    double friction_J;        /* int omega_m (B omega_m + tau_coul) dt */
    double load_J;            /* int omega_m tau_load dt */
    double cogging_J;         /* int omega_m tau_cog dt */
    double source_J;          /* int v_s i_source dt; stiff bus: bus_J */
    double source_resistor_J; /* int R_s i_source^2 dt; stiff bus: 0 */
    double capacitor_J;       /* 0.5 C (v^2 - v(0)^2), from the state; stiff bus: 0 */
    double brake_J;           /* int v i_brake dt; stiff bus: 0 */
    double link_clamp_J;      /* int -v i_clamp dt in the inverter legs; stiff bus: 0 */
    double constraint_J;      /* removed by instantaneous changes (see the notes), summed
                               * when they happen (not integrated) */
} plant_energy_t;

/* Conduction state of one phase terminal. */
typedef enum {
    PLANT_PHASE_DRIVEN = 0,  /* outputs on: the leg switches (or the ideal dq source) */
    PLANT_PHASE_BLOCKING,    /* outputs off, both diodes off: i = 0, terminal floats */
    PLANT_PHASE_UPPER_DIODE, /* outputs off, i < 0 to the + rail: v_term = v_dc + v_f */
    PLANT_PHASE_LOWER_DIODE, /* outputs off, i > 0 from the - rail: v_term = -v_f */
    PLANT_PHASE_OPEN         /* terminal disconnected (plant_set_phase_open): i = 0 */
} plant_phase_state_t;

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
    double v_dc_V;          /* link voltage now (stiff bus: held during the last period) */
    double v_source_V;      /* source voltage inverter.v_dc_V at t_s (stiff bus: v_dc_V) */
    double i_source_A;      /* into the link from the source (stiff bus: i_bridge_A) */
    double i_bridge_A;      /* drawn by the bridge from the + rail (< 0: rectifying) */
    double i_brake_A;       /* through the brake resistor */
    bool brake_on;
    bool link_clamped; /* the link held at -v_f by the inverter legs (see notes) */
    bool outputs_enabled;
    plant_phase_state_t phase_state[3];
    bool rectifying;       /* outputs off and some phase conducting through a diode */
    bool open_circuit;     /* outputs off and no phase conducting: all currents zero */
    bool phase_open[3];    /* plant_set_phase_open in effect */
    bool rotor_locked;     /* plant_set_rotor_locked in effect */
    bool source_connected; /* plant_set_source_connected in effect (stiff bus: true) */
    plant_energy_t energy;
} plant_true_state_t;

typedef struct {
    double t_s;
    double i_abc_A[3];
    double v_dc_V;
    uint32_t encoder_count;    /* 0 .. 4*lines - 1 */
    double encoder_edge_age_s; /* since the count's last edge (plant_sample);
                                  INFINITY: none (at rest, no encoder) */
    bool encoder_index;        /* index crossed since the previous sample */
} plant_measurement_t;

typedef enum {
    PLANT_OK = 0,
    PLANT_ERR_NULL = -1,
    PLANT_ERR_MOTOR = -2,    /* bad motor parameter */
    PLANT_ERR_MISMATCH = -3, /* multiplier not finite and > 0 */
    PLANT_ERR_INVERTER = -4,
    PLANT_ERR_SENSOR = -5,
    PLANT_ERR_PROFILE = -6,  /* v_dc or load profile invalid */
    PLANT_ERR_SOLVER = -7,   /* substeps / initial state */
    PLANT_ERR_STATE = -8,    /* the call needs an initialised plant */
    PLANT_ERR_DC_LINK = -9,  /* bad dc_link parameter, or a link operation on a stiff bus */
    PLANT_ERR_ARGUMENT = -10 /* argument out of range (phase index) */
} plant_err_t;

#define PLANT_PRIVATE_STATE_LEN 18u

/* Runtime faults requested by the plant_set_* calls (applied at the start
 * of the next advance). Private. */
typedef struct {
    bool phase_open[3];
    bool rotor_locked;
    bool source_connected;
    double t_dead_s; /* inverter dead time in effect (plant_set_dead_time) */
} plant_faults_t;

/* Private: constants of the exact integrator for the substep h_s (see
 * plant_exact.c). */
typedef struct {
    bool usable;                       /* solver_method EXACT and Ld == Lq */
    double decay;                      /* E = exp(-R h / L) */
    double one_minus_decay;            /* 1 - E, without cancellation */
    double decay_arg;                  /* R h / L */
    double input_gain_A_per_V;         /* (1 - E) / R; h / L when R == 0 */
    double quad_s2;                    /* h^2 / 12: the end correction of the quadratures */
    double inv_L_per_H;                /* 1 / L */
    double lambda_per_s;               /* R / L */
    double psi_per_L_A;                /* psi / L */
    double torque_const_Nm_per_A;      /* 1.5 n_p psi */
    double kt_h_2, kt_h_3;             /* torque constant x h / 2, h / 3 */
    double kt_h2_6, kt_h2_8, kt_h2_12; /* ... x h^2 / 6, / 8, / 12 */
    double turn_per_speed_s;           /* n_p h: the rotor's electrical turn per unit speed */
    double path_gain_A_s2;             /* n_p h^3 / 12 (R / L) (psi / L): the angle-path term */
    double path_q_factor;              /* 1 - (R / L) h / 2 */
    double iq_end_weight_s;            /* h / 2 + (h^2 / 12) R / L: i_q1's weight in int i_q */
    double back_emf_A[5];              /* (psi / L) E phi_1^(n)(R h / L) / n!, n = 0..4 */
} plant_exact_consts_t;

/* Private: the caller owns the storage; use the functions below. */
typedef struct {
    plant_config_t cfg;
    double R_ohm, Ld_H, Lq_H, psi_Wb, inv_J_per_kgm2; /* with mismatch */
    double n_p;
    double cog_cos_phi[PLANT_MAX_COG_HARMONICS];
    double cog_sin_phi[PLANT_MAX_COG_HARMONICS];
    double period_s, h_s;
    plant_exact_consts_t exact;
    double exact_cos, exact_sin; /* cos, sin theta_e where the exact integrator stopped */
    bool exact_carry;            /* ... valid: no other integration since, same period */
    bool link_dynamic;           /* dc_link.capacitance_F > 0: v is a state */
    double v0_link_V;            /* v(0), for capacitor_J */
    double x[PLANT_PRIVATE_STATE_LEN];
    double t_s;
    uint64_t n_periods; /* t_s = n_periods * period_s */
    plant_phase_state_t phase_state[3];
    uint32_t n_floating; /* phases BLOCKING or OPEN */
    bool diode_mode;     /* the last integrated part had the outputs off */
    bool brake_on;
    bool link_clamped;
    plant_faults_t faults;    /* in effect */
    plant_faults_t requested; /* by plant_set_*, applied at the next advance */
    double constraint_J;
    uint64_t rng_state;
    bool have_spare_gauss;
    double spare_gauss;
    int64_t encoder_turns; /* floor((theta_m + offset) / 2 pi) at last sample */
    plant_true_state_t view;
    const char *err_msg;
    bool initialised;
} plant_t;

/* Fills a valid config: the paper 001 motor's numbers (R 0.225 ohm,
 * L 3.8 mH, psi 0.17 Wb, n_p 3, J 0.012 kg m^2, B 0) read in this plant's
 * amplitude-invariant frame (kt = 1.5 n_p psi = 0.765 N m/A; the paper's
 * own machine, its Phi being two-phase, has psi = 0.17 / sqrt(3/2):
 * motor_convention.h), 48 V constant bus, 20 kHz,
 * no dead time, stiff bus (dc_link all zero), ideal sensors, 2500-line
 * encoder, zero load, no mismatch, PLANT_DEFAULT_SUBSTEPS, rotor at rest at
 * theta_m = 0. */
void plant_config_default(plant_config_t *cfg);

/* Returns PLANT_OK or a negative plant_err_t; *msg (if msg != NULL) gets a
 * static sentence naming the offending field ("ok" on success). */
int plant_config_validate(const plant_config_t *cfg, const char **msg);

/* Validates and copies cfg; state at t = 0: currents 0, theta_m0, omega_m0,
 * outputs enabled. On error the plant is left non-initialised. */
int plant_init(plant_t *p, const plant_config_t *cfg);

/* Message of the last plant_init() ("ok" after success), or of the last
 * refused plant_set_* call. */
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

/* Runtime faults (the test bench's injections). Each takes effect at the
 * start of the next advance and stays until changed; they return PLANT_OK or
 * a negative plant_err_t (the plant is then unchanged; plant_error_message
 * says why, except for PLANT_ERR_STATE on a plant that plant_init refused,
 * which keeps plant_init's message).
 *
 * Phase terminal 0..2 (a, b, c) disconnected (open == true) or reconnected:
 * the phase's current is zero in every mode (switching, diode bridge, ideal
 * dq source); a current flowing when it opens is cut (its magnetic energy
 * goes to constraint_J); the other two phases carry equal and opposite
 * currents. A reconnected phase starts blocking (outputs off) or driven. */
int plant_set_phase_open(plant_t *p, unsigned phase, bool open);

/* A shaft brake: locked == true holds omega_m = 0 and theta_m (the kinetic
 * energy at the moment it engages goes to constraint_J); released, the rotor
 * is free again from rest. config.locked_rotor is the initial state. */
int plant_set_rotor_locked(plant_t *p, bool locked);

/* The bus source connected to the link or lost (no source current). Needs
 * dc_link.capacitance_F > 0: on a stiff bus it is refused (PLANT_ERR_DC_LINK). */
int plant_set_source_connected(plant_t *p, bool connected);

/* The inverter's dead time from the next advance on (config: the initial
 * value inverter.t_dead_s): a board whose dead time changes, e.g. paper
 * 002's Case II (3 -> 7 us). Same rule as the config: finite, >= 0 and
 * below half a PWM period (else PLANT_ERR_ARGUMENT). */
int plant_set_dead_time(plant_t *p, double t_dead_s);

/* True state after the last advance (valid until the next advance). */
const plant_true_state_t *plant_true_state(const plant_t *p);

/* Period length [s] (1 / f_pwm). */
double plant_period_s(const plant_t *p);

#endif /* SIM_PLANT_H */
