#!/usr/bin/env python3
"""Expected values of the M3 closed-loop images (tests/qemu_m3), in double.

Independent of the images' code: the current loop as a linear discrete
model, in the rotor frame, of what the image implements (foc_m3.h) and the
plant does (host_sim/plant/plant.h) - a surface PMSM (Ld = Lq = L), ideal
inverter on a stiff bus, PI with kp = L w_c, ki = R w_c (backward-Euler
integrator, the form of mc/pi.h and mc/pi_q31.h), the voltage of the call
at t_k applied over [t_k+1, t_k+2) (1.5 periods after the sample):

  q axis + rotor:  L di_q/dt = v_q - R i_q - n_p psi w_m,
                   J dw_m/dt = 1.5 n_p psi i_q      (w_m = 0 while locked)
  d axis:          L di_d/dt = v_d - R i_d + n_p w_m L i_q

v held over each period, so the q axis and the rotor advance by the exact
transition matrix of the 2x2 system (series of exp(A Ts)); the d axis by
its exact scalar step with the coupling term held at the period's mean.
The model ignores what the images add and bounds it instead:

  - ADC: mid-tread, |error| <= h = i_fs / 2^bits per phase; through the
    three-phase Clarke (and any rotation) at most 4/3 h on each of d, q;
  - PWM: compare values rounded, |duty error| <= 1 / (2 arr) per phase, so
    <= 4/3 v_dc / (2 arr) on each of v_d, v_q;
  - these enter the loop linearly: the deviation of the true current from
    the model is at most l1(measurement -> current) * 4/3 h +
    l1(voltage -> current) * 4/3 v_dc / (2 arr), with l1 the sum of the
    absolute values of the impulse response (computed here, locked and
    free rotor, the larger of the two);
  - angle: the count's middle, |error| <= n_p pi / cpr electrical: the true
    i_d may differ by |i_q| sin of that;
  - a margin for what is far below the above: the Q31 (or float32)
    arithmetic and gains, the sine table (5e-6 of full scale), and with the
    rotor turning the rotation of the applied voltage during the delay
    (w_e 1.5 Ts <= 4e-3 rad) and the L i_d w_e term of the q axis.

Prints for CMake: "EXPECT <key> <value> <tol>", "MAX <key> <limit>" and
"INFO ..." lines; exits non-zero if the model itself leaves the linear range
(PI limit or SVPWM circle reached: the scenario would be invalid).
"""
import argparse
import math
import sys


def expm_2x2(a, h, terms=40):
    """exp(A h) and int_0^h exp(A s) ds for a 2x2 A (lists), by series."""
    phi = [[1.0, 0.0], [0.0, 1.0]]
    gam = [[h, 0.0], [0.0, h]]
    term = [[1.0, 0.0], [0.0, 1.0]]
    for n in range(1, terms):
        term = [[sum(term[i][k] * a[k][j] for k in range(2)) * h / n
                 for j in range(2)] for i in range(2)]
        for i in range(2):
            for j in range(2):
                phi[i][j] += term[i][j]
                gam[i][j] += term[i][j] * h / (n + 1)
    return phi, gam


class Loop:
    """The discrete loop; one step() per PWM period."""

    def __init__(self, p):
        self.p = p
        ts = 1.0 / p.f_pwm
        self.kp = p.L * p.w_c
        self.ki_ts = p.R * p.w_c * ts
        self.a_d = math.exp(-p.R * ts / p.L)
        self.g_d = (1.0 - self.a_d) / p.R
        kt = 1.5 * p.n_p * p.psi
        a_free = [[-p.R / p.L, -p.n_p * p.psi / p.L], [kt / p.J, 0.0]]
        a_lock = [[-p.R / p.L, 0.0], [0.0, 0.0]]
        self.free = expm_2x2(a_free, ts)
        self.lock = expm_2x2(a_lock, ts)
        self.reset()

    def reset(self):
        self.i_q = self.w_m = self.i_d = 0.0
        self.int_q = self.int_d = 0.0
        self.v_q_prev = self.v_d_prev = 0.0

    def control(self, r_q, n_q=0.0, n_d=0.0):
        """The call at t_k: PI on the measured currents (+ errors n)."""
        e_q = r_q - (self.i_q + n_q)
        e_d = 0.0 - (self.i_d + n_d)
        self.int_q += self.ki_ts * e_q
        self.int_d += self.ki_ts * e_d
        return self.kp * e_q + self.int_q, self.kp * e_d + self.int_d

    def advance(self, locked, dv_q=0.0):
        """[t_k, t_k+1) with the previous call's voltages (+ error dv)."""
        phi, gam = self.lock if locked else self.free
        v = self.v_q_prev + dv_q
        b = 1.0 / self.p.L  # input vector (1/L, 0)
        x0, x1 = self.i_q, self.w_m
        i_q = phi[0][0] * x0 + phi[0][1] * x1 + gam[0][0] * b * v
        w_m = phi[1][0] * x0 + phi[1][1] * x1 + gam[1][0] * b * v
        if locked:
            w_m = 0.0
        coupling = (self.p.n_p * 0.5 * (self.w_m + w_m) * self.p.L *
                    0.5 * (self.i_q + i_q))
        self.i_d = self.a_d * self.i_d + self.g_d * (self.v_d_prev + coupling)
        self.i_q, self.w_m = i_q, w_m


def l1_norms(p, locked, n=20000):
    """Sum |i_q| of the responses to a unit measurement error and to a unit
    voltage error, both in the first period, with every reference 0."""
    out = []
    for kind in ("meas", "volt"):
        m = Loop(p)
        total = 0.0
        for k in range(n):
            first = k == 0
            v_q, v_d = m.control(0.0, n_q=1.0 if first and kind == "meas" else 0.0)
            m.advance(locked, dv_q=1.0 if first and kind == "volt" else 0.0)
            m.v_q_prev, m.v_d_prev = v_q, v_d
            total += abs(m.i_q)
        out.append(total)
    return out


def main():
    ap = argparse.ArgumentParser()
    for name in ("R", "L", "psi", "J", "v_dc", "f_pwm", "w_c", "i_fs",
                 "theta_m0", "iq_step", "iq_free"):
        ap.add_argument("--" + name.replace("_", "-"), type=float, required=True)
    for name in ("n_p", "enc_lines", "adc_bits", "arr", "step_k",
                 "release_k", "end_k"):
        ap.add_argument("--" + name.replace("_", "-"), type=int, required=True)
    ap.add_argument("--checkpoints", required=True,
                    help="comma-separated periods after the step")
    p = ap.parse_args()
    checkpoints = [int(c) for c in p.checkpoints.split(",")]
    if checkpoints != sorted(set(checkpoints)) or \
            p.step_k + checkpoints[-1] > p.release_k:
        sys.exit("checkpoints must increase and lie within the locked phase")

    # Bounds of the errors the model leaves out (docstring).
    h = p.i_fs / 2 ** p.adc_bits
    e_meas = 4.0 / 3.0 * h
    e_volt = 4.0 / 3.0 * p.v_dc / (2.0 * p.arr)
    l1 = [max(a, b) for a, b in zip(l1_norms(p, True), l1_norms(p, False))]
    quant = l1[0] * e_meas + l1[1] * e_volt
    delta = p.n_p * math.pi / (4 * p.enc_lines)
    margin_locked = 1e-4
    margin_free = 1e-3
    tol_locked = quant + margin_locked
    tol_free = quant + margin_free

    m = Loop(p)
    lim = 0.5 * p.v_dc  # FOC_PI_LIMIT_PU (foc_m3.h)
    circle = p.v_dc / math.sqrt(3.0)
    v_max = 0.0
    iq_at = {}
    id_free_max = 0.0
    for k in range(p.end_k):
        locked = k < p.release_k
        r = 0.0 if k < p.step_k else (p.iq_step if locked else p.iq_free)
        v_q, v_d = m.control(r)
        v_max = max(v_max, abs(v_q), abs(v_d))
        if max(abs(v_q), abs(v_d)) >= lim or math.hypot(v_q, v_d) >= circle:
            sys.exit(f"model saturates at period {k}: scenario outside the linear range")
        m.advance(locked)
        m.v_q_prev, m.v_d_prev = v_q, v_d
        n = k + 1 - p.step_k
        if n in checkpoints:
            iq_at[n] = m.i_q
        if k + 1 > p.release_k:
            id_free_max = max(id_free_max, abs(m.i_d))

    t_free = (p.end_k - p.release_k) / p.f_pwm
    kt_over_j = 1.5 * p.n_p * p.psi / p.J
    # (no semicolons: CMake reads the output as a list of lines)
    print(f"INFO l1 norms: measurement {l1[0]:.4f}, voltage {l1[1]:.4f} A/V, "
          f"quantisation bound {quant * 1e3:.3f} mA, angle bound {delta:.3e} rad, "
          f"model max |v| {v_max:.3f} V")
    for n in checkpoints:
        print(f"EXPECT step_iq_n{n}_A {iq_at[n]:.6f} {tol_locked:.6f}")
    print(f"MAX locked_max_abs_i_d_A {quant + p.iq_step * math.sin(delta) + margin_locked:.6f}")
    print(f"MAX free_max_abs_i_d_A "
          f"{id_free_max + quant + p.iq_free * math.sin(delta) + margin_free:.6f}")
    print(f"EXPECT final_i_q_A {m.i_q:.6f} {tol_free:.6f}")
    # the rotor integrates the current: a deviation bounded by tol_free at
    # every sample moves the speed by at most kt / J * tol_free * t_free
    print(f"EXPECT final_omega_m_rad_s {m.w_m:.5f} {kt_over_j * tol_free * t_free:.5f}")
    print("EXPECT saturated_isrs 0 0")
    print(f"EXPECT isr_count {p.end_k} 0")
    return 0


if __name__ == "__main__":
    sys.exit(main())
