#!/usr/bin/env python3
"""Plot a pmsm-sim CSV trace into one PNG. The columns are read by name (their
table: host_sim/cli/trace_csv.c); a trace without a column a panel needs is
an error naming it.

Panels: speed (actual, reference, estimate) in rpm; position when the trace
has a position reference; d/q currents with their references; d/q voltage
references with the bus voltage; electromagnetic and load torque (and the
firmware's load estimate when it has one); angle error of the controller's
electrical angle.

usage: plot_trace.py TRACE.csv OUT.png [--title TEXT]
       plot_trace.py --check   (exit 0 when this Python has what the plot needs;
                                pmsm-sim runs it before a run with --plot)
Run with the project's venv (tools/setup.sh): .venv/bin/python.
"""
import argparse
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (backend first)
import numpy as np  # noqa: E402

RAD_S_TO_RPM = 30.0 / np.pi


# Every column a panel reads.
COLUMNS = (
    "t_s", "omega_m_rad_s", "omega_m_est_rad_s", "omega_m_ref_rad_s", "theta_m_rad",
    "theta_m_ref_rad", "angle_error_e_rad", "i_d_A", "i_q_A", "i_d_ref_A", "i_q_ref_A",
    "v_d_ref_V", "v_q_ref_V", "v_dc_V", "tau_e_Nm", "tau_load_Nm", "tau_load_est_Nm",
)


def load(path):
    data = np.genfromtxt(path, delimiter=",", names=True)
    if data.size == 0 or data.dtype.names is None:
        sys.exit(f"plot_trace: {path}: no trace rows")
    missing = [c for c in COLUMNS if c not in data.dtype.names]
    if missing:
        sys.exit(f"plot_trace: {path}: missing column(s) {', '.join(missing)}")
    return np.atleast_1d(data)


def speed_panel(ax, d):
    t = d["t_s"]
    ax.plot(t, d["omega_m_ref_rad_s"] * RAD_S_TO_RPM, "k--", lw=1.0, label="reference")
    ax.plot(t, d["omega_m_rad_s"] * RAD_S_TO_RPM, lw=1.2, label="actual")
    ax.plot(t, d["omega_m_est_rad_s"] * RAD_S_TO_RPM, lw=0.8, alpha=0.7, label="estimate")
    ax.set_ylabel("speed [rpm]")


def position_panel(ax, d):
    t = d["t_s"]
    ax.plot(t, d["theta_m_ref_rad"], "k--", lw=1.0, label="reference")
    ax.plot(t, d["theta_m_rad"], lw=1.2, label="actual")
    ax.set_ylabel("position [rad]")


def current_panel(ax, d):
    t = d["t_s"]
    ax.plot(t, d["i_d_A"], lw=1.0, label="i_d")
    ax.plot(t, d["i_q_A"], lw=1.0, label="i_q")
    ax.plot(t, d["i_d_ref_A"], "--", lw=0.8, label="i_d ref")
    ax.plot(t, d["i_q_ref_A"], "--", lw=0.8, label="i_q ref")
    ax.set_ylabel("current [A]")


def voltage_panel(ax, d):
    t = d["t_s"]
    ax.plot(t, d["v_d_ref_V"], lw=1.0, label="v_d ref")
    ax.plot(t, d["v_q_ref_V"], lw=1.0, label="v_q ref")
    ax.plot(t, d["v_dc_V"], "k:", lw=0.8, label="v_dc")
    ax.set_ylabel("voltage [V]")


def torque_panel(ax, d):
    t = d["t_s"]
    ax.plot(t, d["tau_e_Nm"], lw=1.0, label="electromagnetic")
    ax.plot(t, d["tau_load_Nm"], lw=1.0, label="load")
    if np.any(d["tau_load_est_Nm"] != 0.0):
        ax.plot(t, d["tau_load_est_Nm"], "--", lw=0.8, label="load estimate")
    ax.set_ylabel("torque [N m]")


def angle_error_panel(ax, d):
    ax.plot(d["t_s"], np.degrees(d["angle_error_e_rad"]), lw=0.8, label="controller - true")
    ax.set_ylabel("angle error [deg el.]")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", nargs="?", help="trace written by pmsm-sim run --csv")
    parser.add_argument("png", nargs="?", help="output image")
    parser.add_argument("--title", default=None, help="figure title")
    parser.add_argument("--check", action="store_true",
                        help="only check the environment (the imports above succeeded)")
    args = parser.parse_args()
    if args.check:
        return
    if args.csv is None or args.png is None:
        parser.error("TRACE.csv and OUT.png are required")

    d = load(args.csv)
    panels = [speed_panel]
    if np.any(d["theta_m_ref_rad"] != 0.0):
        panels.append(position_panel)
    panels += [current_panel, voltage_panel, torque_panel]
    if np.any(d["angle_error_e_rad"] != 0.0):
        panels.append(angle_error_panel)

    fig, axes = plt.subplots(len(panels), 1, sharex=True, figsize=(10, 2.2 * len(panels)))
    for ax, panel in zip(axes, panels):
        panel(ax, d)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize="small", ncol=4)
    axes[-1].set_xlabel("time [s]")
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.png, dpi=110)


if __name__ == "__main__":
    main()
