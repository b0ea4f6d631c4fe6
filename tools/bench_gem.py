#!/usr/bin/env python3
"""Speed of pmsm-sim beside gym-electric-motor on the same motor, step and
duration, in one sitting (a benchmark, not a test).

Motor: paper 001 as the shipped benchmark scenario's plant sees it
(R 0.225 ohm, Ld = Lq 3.8 mH, psi 0.17 / sqrt(3/2) Wb from the paper's
power-invariant 0.17 Wb, 3 pole pairs, J 0.012 kg m^2), 48 V bus, 20 kHz.

pmsm-sim: `pmsm-sim bench` on host_sim/scenarios/paper001_benchmark_foc.json
(closed loop: plant, host HAL and firmware) with the chosen substeps per
PWM period. gym-electric-motor: its continuous current-control PMSM
environment with that motor, tau = one PWM period (50 us) and its Euler
solver with the same substeps, stepped with a constant action (no agent,
so only the environment is timed). Real-time factor = simulated seconds
per wall-clock second; both wall times by time.perf_counter / pmsm-sim's
own CLOCK_MONOTONIC.

Usage: bench_gem.py PMSM_SIM [--substeps N] [--duration S] [--repeats R]
"""
import argparse
import math
import re
import statistics
import subprocess
import sys
import time

F_PWM_HZ = 20000.0
MOTOR = dict(p=3, l_d=3.8e-3, l_q=3.8e-3, j_rotor=0.012, r_s=0.225,
             psi_p=0.17 / math.sqrt(1.5))
SCENARIO = "host_sim/scenarios/paper001_benchmark_foc.json"


def pmsm_sim_rtf(exe, substeps, duration_s):
    out = subprocess.run(
        [exe, "bench", SCENARIO, "--quiet",
         "--set", f"solver.substeps_per_period={substeps}",
         "--set", f"duration_s={duration_s}"],
        check=True, capture_output=True, text=True).stdout
    m = re.search(r"= ([0-9.]+) simulated s per wall s", out)
    if m is None:
        sys.exit(f"unexpected pmsm-sim output:\n{out}")
    return float(m.group(1))


def gem_rtf(substeps, duration_s):
    import gym_electric_motor as gem
    from gym_electric_motor.physical_systems import PolynomialStaticLoad
    from gym_electric_motor.physical_systems.solvers import EulerSolver

    tau = 1.0 / F_PWM_HZ
    env = gem.make(
        "Cont-CC-PMSM-v0",
        motor=dict(motor_parameter=MOTOR,
                   limit_values=dict(i=40.0, u=48.0, omega=400.0),
                   nominal_values=dict(i=20.0, u=48.0, omega=300.0)),
        supply=dict(u_nominal=48.0),
        load=PolynomialStaticLoad(load_parameter=dict(a=0.0, b=0.0, c=0.0, j_load=1e-6)),
        ode_solver=EulerSolver(nsteps=substeps),
        visualization=(),
        tau=tau)
    env.reset(seed=1)
    action = env.action_space.low * 0.0 + 0.1  # a constant (normalised) voltage
    n = int(round(duration_s * F_PWM_HZ))
    t0 = time.perf_counter()
    for _ in range(n):
        _, _, terminated, truncated, _ = env.step(action)
        if terminated or truncated:
            env.reset()
    return n * tau / (time.perf_counter() - t0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pmsm_sim")
    ap.add_argument("--substeps", type=int, default=50)
    ap.add_argument("--duration", type=float, default=1.0)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    sim = [pmsm_sim_rtf(a.pmsm_sim, a.substeps, a.duration) for _ in range(a.repeats)]
    ref = [gem_rtf(a.substeps, a.duration) for _ in range(a.repeats)]
    step_us = 1e6 / F_PWM_HZ / a.substeps
    ms, mg = statistics.median(sim), statistics.median(ref)
    print(f"step {step_us:.3g} us ({a.substeps} substeps at 20 kHz), "
          f"{a.duration:g} s simulated, {a.repeats} runs each (median, min-max):")
    print(f"pmsm-sim (closed loop, firmware in the loop): {ms:.3g}x real time "
          f"({min(sim):.3g}-{max(sim):.3g})")
    print(f"gym-electric-motor 3.0.3 (Euler, constant action): {mg:.3g}x real time "
          f"({min(ref):.3g}-{max(ref):.3g})")
    if mg > 0.0:
        print(f"ratio pmsm-sim / gym-electric-motor: {ms / mg:.3g}")


if __name__ == "__main__":
    main()
