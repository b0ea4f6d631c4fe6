#!/usr/bin/env python3
"""Amplitude spectrum of the steady-state speed error of a pmsm-sim CSV trace
(paper 002, Fig. 6), as a PNG, with the disturbance lines marked and their
amplitudes printed.

The error is e = omega_m - omega_m_ref (true speed minus the firmware's
reference, in rpm) over the window [T0, T1] in profile time (t_s minus the
scenario's time_offset_s, given with --time-offset; pmsm-sim's JSON report
has it as "time_offset_s" and the window as windows.spectrum). Its mean
(the offset error) is removed, a Hann window w applied, and the one-sided
amplitude spectrum

    A(f) = 2 |sum_k w_k e_k exp(-j 2 pi f t_k)| / sum_k w_k

is evaluated on the FFT grid (resolution 1 / (N dt), about 1 / (T1 - T0):
5 Hz for a 0.2 s window) for the plot, and at the exact line frequencies for
the printed amplitudes. Dividing by sum w (= N / 2 for the Hann window, its
coherent gain 0.5) instead of N is the amplitude correction: a sinusoid
a sin(2 pi f t) reads A(f) = a, exactly on a bin, and within the window's
leakage off the grid (below 1 % once the window holds a few periods).
Hann's main lobe is 4 bins wide: lines closer than 2 / (T1 - T0) merge.

Lines (paper 002 Section IV-A, at speed n rpm; f_m = n / 60, f_e = n_p f_m):
  f_e      current-offset error (33.3 Hz at 500 rpm, n_p = 4)
  2 f_e    current-gain (scaling) error (66.7 Hz)
  6 f_e    dead time, the 6th electrical harmonic in d-q (200 Hz)
  Q f_m    cogging, the Q-th mechanical harmonic (266.7 Hz, Q = 32)

usage: plot_spectrum.py TRACE.csv OUT.png --window T0 T1 [--time-offset S]
           [--speed-rpm 500] [--pole-pairs 4] [--slots 32] [--title TEXT]
           [--fmax HZ] [--log] [--json OUT.json]
       plot_spectrum.py --self-test
Prints one line per disturbance line: name, frequency (Hz), amplitude (rpm).
Run with the project's venv (tools/setup.sh): .venv/bin/python.
"""
import argparse
import json
import sys

import numpy as np

RAD_S_TO_RPM = 30.0 / np.pi


def lines_for(speed_rpm, pole_pairs, slots):
    """The paper's disturbance lines: (name, frequency in Hz)."""
    f_m = speed_rpm / 60.0
    f_e = pole_pairs * f_m
    return [
        ("offset (f_e)", f_e),
        ("gain (2 f_e)", 2.0 * f_e),
        ("dead time (6 f_e)", 6.0 * f_e),
        ("cogging (Q f_m)", slots * f_m),
    ]


def amplitude_at(t, x, freqs):
    """Hann-windowed amplitude of x(t) at each frequency (see the module doc)."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    x = x - np.mean(x)
    n = x.size
    w = np.hanning(n + 2)[1:-1]  # symmetric Hann without the zero end points
    s = np.sum(w)
    freqs = np.atleast_1d(np.asarray(freqs, dtype=float))
    phase = np.exp(-2j * np.pi * np.outer(freqs, t - t[0]))
    return 2.0 * np.abs(phase @ (w * x)) / s


def spectrum(t, x):
    """Frequency grid (Hz) and amplitudes on it (uniform sampling assumed)."""
    dt = float(np.median(np.diff(t)))
    n = len(t)
    f = np.fft.rfftfreq(n, dt)
    return f, amplitude_at(t, x, f)


def load_error(path, t0, t1, offset):
    data = np.genfromtxt(path, delimiter=",", names=True)
    if data.size == 0 or data.dtype.names is None:
        sys.exit(f"plot_spectrum: {path}: no trace rows")
    for c in ("t_s", "omega_m_rad_s", "omega_m_ref_rad_s"):
        if c not in data.dtype.names:
            sys.exit(f"plot_spectrum: {path}: no column {c}")
    tb = data["t_s"] - offset
    sel = (tb >= t0) & (tb <= t1)
    if np.count_nonzero(sel) < 16:
        sys.exit(f"plot_spectrum: {path}: fewer than 16 samples in [{t0}, {t1}] s")
    err = (data["omega_m_rad_s"][sel] - data["omega_m_ref_rad_s"][sel]) * RAD_S_TO_RPM
    return tb[sel], err


def self_test():
    """Synthetic sinusoids: the amplitude at their frequency within 1 %."""
    dt = 2e-4  # the paper 002 traces: 10 kHz, every 2nd period
    t = np.arange(0.2, 0.4 + dt / 2, dt)
    ok = True
    for f, a in ((33.333333, 3.0), (66.666667, 1.5), (200.0, 0.7), (266.666667, 0.25)):
        x = 5.0 + a * np.sin(2 * np.pi * f * t + 0.3)
        got = amplitude_at(t, x, [f])[0]
        good = abs(got - a) <= 0.01 * a
        ok &= good
        print(f"self-test {f:9.3f} Hz: amplitude {got:.5f}, expected {a} ({'ok' if good else 'FAIL'})")
    # a mix: each line read within 1 % in the presence of the others
    mix = sum(a * np.sin(2 * np.pi * f * t) for f, a in
              ((33.333333, 3.0), (66.666667, 1.5), (200.0, 0.7), (266.666667, 0.25)))
    got = amplitude_at(t, mix, [33.333333, 66.666667, 200.0, 266.666667])
    for g, a in zip(got, (3.0, 1.5, 0.7, 0.25)):
        good = abs(g - a) <= 0.01 * a
        ok &= good
        print(f"self-test mix: amplitude {g:.5f}, expected {a} ({'ok' if good else 'FAIL'})")
    return 0 if ok else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("trace", nargs="?")
    ap.add_argument("out", nargs="?")
    ap.add_argument("--window", nargs=2, type=float, metavar=("T0", "T1"))
    ap.add_argument("--time-offset", type=float, default=0.0)
    ap.add_argument("--speed-rpm", type=float, default=500.0)
    ap.add_argument("--pole-pairs", type=int, default=4)
    ap.add_argument("--slots", type=int, default=32)
    ap.add_argument("--fmax", type=float, default=1000.0)
    ap.add_argument("--title", default=None)
    ap.add_argument("--log", action="store_true", help="logarithmic amplitude axis")
    ap.add_argument("--json", default=None, help="write the line amplitudes here")
    ap.add_argument("--self-test", action="store_true")
    args = ap.parse_args()
    if args.self_test:
        return self_test()
    if args.trace is None or args.out is None or args.window is None:
        ap.error("TRACE.csv, OUT.png and --window are required")
    t0, t1 = args.window
    t, err = load_error(args.trace, t0, t1, args.time_offset)
    lines = lines_for(args.speed_rpm, args.pole_pairs, args.slots)
    amps = amplitude_at(t, err, [f for _, f in lines])
    for (name, f), a in zip(lines, amps):
        print(f"{name:20s} {f:8.2f} Hz  {a:10.4g} rpm")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"window_s": [t0, t1], "resolution_Hz": 1.0 / (t[-1] - t[0]),
                       "lines": [{"name": n, "freq_Hz": f, "amplitude_rpm": float(a)}
                                 for (n, f), a in zip(lines, amps)]}, fh, indent=1)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    f, a = spectrum(t, err)
    keep = f <= args.fmax
    fig, ax = plt.subplots(figsize=(9, 4.5))
    ax.plot(f[keep], a[keep], lw=1.0, color="tab:blue", label="|E(f)| (Hann, amplitude-corrected)")
    for (name, fl), al in zip(lines, amps):
        ax.axvline(fl, color="tab:red", lw=0.8, ls="--")
        ax.annotate(f"{name}\n{fl:.1f} Hz: {al:.3g}", (fl, al), textcoords="offset points",
                    xytext=(3, 6), fontsize=7, color="tab:red")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("amplitude of the speed error (rpm)")
    ax.set_xlim(0, args.fmax)
    if args.log:
        ax.set_yscale("log")
        ax.set_ylim(max(1e-4, 1e-5 * float(np.max(a[keep]))), None)
    ax.set_title(args.title or f"speed error spectrum, {t0:g}-{t1:g} s "
                 f"(resolution {1.0 / (t1 - t0):.2g} Hz)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
