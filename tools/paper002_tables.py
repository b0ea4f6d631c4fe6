#!/usr/bin/env python3
"""Side-by-side tables of the paper 002 bench (run by tools/paper002_tables.sh).

usage: paper002_tables.py TABLES.json OUT_DIR

TABLES.json: the paper's Table I / II numbers
(host_sim/scenarios/reference/paper002_tables.json). OUT_DIR holds, per run,
paper002_case{N}_{controller}.json (pmsm-sim --json) and .csv (--csv).
Per case: one row per paper metric with the paper's four controllers and the
measured value of every controller run in that case, then the amplitudes of
the four disturbance lines of the speed error over the scenario's
"spectrum" window (tools/plot_spectrum.py), whose spectrum is written to
OUT_DIR/paper002_case{N}_{controller}_spectrum.png.

Measured metrics (pmsm-sim JSON): overshoot_percent, settling_time_ms
(settling_time_s x 1000, 2 % band), offset_error_rpm, fluctuation_rpm,
fluctuation_rate_percent (the scenario's steady_window_s), decrease_rpm
(the max dip after the first load step), recovery_time_ms (its recovery
time, metrics.recovery_band).
"""
import glob
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_spectrum  # noqa: E402


def measured(report, metric):
    m = report.get("metrics", {})
    steps = report.get("load_steps", [])
    if metric == "settling_time_ms":
        v = m.get("settling_time_s")
        return None if v is None else 1e3 * v
    if metric == "decrease_rpm":
        return steps[0].get("max_dip_rpm") if steps else None
    if metric == "recovery_time_ms":
        v = steps[0].get("recovery_time_s") if steps else None
        return None if v is None else 1e3 * v
    return m.get(metric)


def fmt(v):
    return "-" if v is None else f"{v:.3g}" if abs(v) >= 100 else f"{v:.2f}"


def spectrum_lines(out_dir, name, report):
    win = report.get("windows", {}).get("spectrum")
    csv = os.path.join(out_dir, name + ".csv")
    if win is None or not os.path.exists(csv):
        return None
    t, err = plot_spectrum.load_error(csv, win["t0_s"], win["t1_s"], report["time_offset_s"])
    lines = plot_spectrum.lines_for(500.0, 4, 32)
    amps = plot_spectrum.amplitude_at(t, err, [f for _, f in lines])
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    f, a = plot_spectrum.spectrum(t, err)
    keep = f <= 1000.0
    fig, ax = plt.subplots(figsize=(9, 4))
    ax.plot(f[keep], a[keep], lw=1.0)
    for (ln, fl), al in zip(lines, amps):
        ax.axvline(fl, color="tab:red", lw=0.8, ls="--")
        ax.annotate(f"{ln}\n{al:.3g} rpm", (fl, al), textcoords="offset points", xytext=(3, 6),
                    fontsize=7, color="tab:red")
    ax.set_yscale("log")  # the lines span four decades
    ax.set_ylim(max(1e-4, 1e-5 * float(max(a[keep]))), None)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("speed error amplitude (rpm)")
    ax.set_title(f"{name}: speed error spectrum {win['t0_s']:g}-{win['t1_s']:g} s (Hann)")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, name + "_spectrum.png"), dpi=110)
    plt.close(fig)
    return list(zip(lines, amps))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    tables = json.load(open(sys.argv[1]))
    out_dir = sys.argv[2]
    ctrls = tables["controllers"]
    for n, case in sorted(tables["cases"].items()):
        runs = []
        for path in sorted(glob.glob(os.path.join(out_dir, f"paper002_case{n}_*.json"))):
            name = os.path.basename(path)[:-5]
            if not re.fullmatch(rf"paper002_case{n}_[A-Za-z0-9_]+", name):
                continue
            runs.append((name.split("_", 2)[2], name, json.load(open(path))))
        print()
        print(f"{case['title']}")
        head = ["metric"] + [f"paper {c}" for c in ctrls] + [f"sim {c}" for c, _, _ in runs]
        widths = [24] + [max(12, len(h)) for h in head[1:]]
        print("  ".join(h.ljust(w) for h, w in zip(head, widths)))
        for row in case["rows"]:
            cells = [row["label"]] + [fmt(v) for v in row["paper"]]
            cells += [fmt(measured(rep, row["metric"])) for _, _, rep in runs]
            print("  ".join(c.ljust(w) for c, w in zip(cells, widths)))
        for ctrl, name, rep in runs:
            faults = rep.get("faults", {}).get("latched", [])
            lines = spectrum_lines(out_dir, name, rep)
            text = "no spectrum window" if lines is None else ", ".join(
                f"{f:.1f} Hz {a:.3g}" for (_, f), a in lines)
            print(f"  {ctrl}: speed error lines (rpm): {text}; faults: {', '.join(faults) or 'none'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
