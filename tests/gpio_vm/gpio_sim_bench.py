#!/usr/bin/env python3
"""pmsm-gpio-bench (the real binary, on the system's libgpiod) against a
simulated GPIO chip: run by tools/vm/run.sh --gpio-sim inside the VM, which
gives PMSM_GPIO_SIM_CHIP (/dev/gpiochipN) and PMSM_GPIO_SIM_SYSFS (the
chip's sysfs directory: sim_gpioK/value reads line K, sim_gpioK/pull sets
its level while it is an input).

sto: the line's level is read through the simulator's sysfs value attribute
(not through libgpiod) while the tool holds it (assert / release, active
high and low, until SIGTERM or --hold), after the tool has left (back to the
pull), and sampled through a pulse. isr: gpio_sim_pulses toggles the line's
pull with a known pattern; the tool must count exactly the pulses generated
and measure durations and periods inside the bounds the generator's own
timestamps give (each edge's kernel timestamp lies between the generator's
clock readings just before and just after the write that made it). Three
captures: ended by --seconds, by SIGTERM, and one stopped (SIGSTOP) while
1200 edges overflow the kernel's 1024-event buffer: exactly the 176 oldest
edges lost (seqno gaps), the rest measured.

Also: a line in use (exit 1, EBUSY), a wrong chip path (exit 2).
Exit status 0 when every check holds, else 1 (the failed checks listed).
"""
import argparse
import json
import os
import select
import signal
import subprocess
import sys
import time

TOOL_TIMEOUT_S = 60  # any one tool run (TCG is slow, but not this slow)
EVENT_BYTES = 48  # sizeof(struct gpio_v2_line_event): what the tool read()s per edge
KERNEL_EVENTS = 1024  # the kernel's event buffer of the tool's request (its maximum)

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)
    return ok


class Sim:
    def __init__(self, bench):
        self.bench = bench
        try:
            self.chip = os.environ["PMSM_GPIO_SIM_CHIP"]
            self.sysfs = os.environ["PMSM_GPIO_SIM_SYSFS"]
            self.lines = int(os.environ["PMSM_GPIO_SIM_LINES"])
        except KeyError as e:
            sys.exit(f"gpio_sim_bench: no {e.args[0]}: run under tools/vm/run.sh --gpio-sim")

    def attr(self, line, name):
        return f"{self.sysfs}/sim_gpio{line}/{name}"

    def pull(self, line, up):
        with open(self.attr(line, "pull"), "w") as f:
            f.write("pull-up" if up else "pull-down")

    def value(self, line):
        with open(self.attr(line, "value")) as f:
            return int(f.read())

    def tool(self, command, line, *rest, active_low=False):
        """The tool's command line for this chip."""
        cmd = [self.bench, command, "--chip", self.chip, "--line", str(line)]
        return cmd + (["--active-low"] if active_low else []) + [str(x) for x in rest]


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True, timeout=TOOL_TIMEOUT_S)


def start(cmd):
    return subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def read_line(proc, timeout_s):
    """The tool's next stdout line, or '' after timeout_s or at its end."""
    ready, _, _ = select.select([proc.stdout], [], [], timeout_s)
    return proc.stdout.readline() if ready else ""


def sto_hold(sim, line, pull_up, active_low, action, hold_s=0):
    """sto assert/release until SIGTERM (hold_s 0) or for --hold hold_s: the
    line's level while held and after."""
    held = 1 if (action == "assert") != active_low else 0
    name = (f"sto {action}{' --active-low' if active_low else ''}"
            f"{f' --hold {hold_s}' if hold_s else ''} (line {line}, pull-{'up' if pull_up else 'down'})")
    sim.pull(line, pull_up)
    check(sim.value(line) == int(pull_up), f"{name}: the line at its pull before")
    proc = start(sim.tool("sto", line, "--hold", hold_s, action, active_low=active_low))
    first = read_line(proc, TOOL_TIMEOUT_S)
    level = "low" if held == 0 else "high"
    check(f"line {line} {'asserted' if action == 'assert' else 'released'} ({level})" in first,
          f"{name}: the tool says {first.strip()!r}")
    check(sim.value(line) == held, f"{name}: sysfs value {held} while held")
    if line == 0 and action == "assert" and not active_low:
        # the line is in use: a second request fails with EBUSY, exit 1
        busy = run(sim.tool("sto", line, "pulse", 1))
        check(busy.returncode == 1 and "Device or resource busy" in busy.stderr,
              f"line in use: exit {busy.returncode} (1), {busy.stderr.strip()!r}")
        check(sim.value(line) == held, f"{name}: still {held} after the refused request")
    if not hold_s:
        proc.send_signal(signal.SIGTERM)
    out, err = proc.communicate(timeout=TOOL_TIMEOUT_S + hold_s)
    check(proc.returncode == 0 and "released to the chip after" in out,
          f"{name}: exit {proc.returncode}{'' if hold_s else ' on SIGTERM'}, {out.strip()!r} "
          f"{err.strip()!r}")
    if hold_s:
        after = float(out.split("released to the chip after ", 1)[-1].split(" s", 1)[0] or 0)
        check(after >= hold_s, f"{name}: held {after:.3f} s >= {hold_s} s")
    check(sim.value(line) == int(pull_up), f"{name}: back to the pull ({int(pull_up)}) after")


def sto_pulse(sim, line, ms):
    """sto pulse MS, the line's value sampled through sysfs meanwhile."""
    name = f"sto pulse {ms} (line {line})"
    sim.pull(line, False)
    fd = os.open(sim.attr(line, "value"), os.O_RDONLY)

    def sample():
        # the value holds at some instant between the two clock reads
        t0 = time.monotonic_ns()
        value = int(os.pread(fd, 8, 0))
        return (t0, value, time.monotonic_ns())

    samples = [sample()]  # (ns before, value, ns after); low: the tool is not started yet
    proc = start(sim.tool("sto", line, "pulse", ms))
    deadline = time.monotonic() + TOOL_TIMEOUT_S
    while proc.poll() is None and time.monotonic() < deadline:
        samples.append(sample())
    samples += [sample() for _ in range(3)]  # the tool has left: low
    os.close(fd)
    out, err = proc.communicate(timeout=TOOL_TIMEOUT_S)
    if not check(proc.returncode == 0, f"{name}: exit {proc.returncode} {err.strip()!r}"):
        return
    # "... asserted (high) for W ms (pulse MS ms), released (low)"
    try:
        width_ms = float(out.split(" for ", 1)[1].split(" ms", 1)[0])
    except (IndexError, ValueError):
        check(False, f"{name}: no width in {out.strip()!r}")
        return
    highs = [k for k, (_, v, _) in enumerate(samples) if v == 1]
    if not check(len(highs) > 0 and samples[0][1] == 0 and samples[-1][1] == 0,
                 f"{name}: sampled low, high ({len(highs)} of {len(samples)} samples), low"):
        return
    first, last = highs[0], highs[-1]
    check(last - first + 1 == len(highs), f"{name}: one high run in the samples")
    gap = max(b[2] - a[0] for a, b in zip(samples[first - 1:], samples[first:last + 2])) / 1e6
    # the tool's width runs from after its request to before its release,
    # both inside the high time H = fall - rise; a sample's value held at
    # an instant between its clock reads (before t0, after t1), so
    # t0[first - 1] < rise <= t1[first] and t0[last] <= fall < t1[last + 1]:
    # t0[last] - t1[first] <= H <= t1[last + 1] - t0[first - 1]
    h_lo = (samples[last][0] - samples[first][2]) / 1e6
    h_hi = (samples[last + 1][2] - samples[first - 1][0]) / 1e6
    check(width_ms >= ms, f"{name}: width {width_ms:.3f} ms >= {ms} ms")
    check(width_ms <= h_hi,
          f"{name}: width {width_ms:.3f} ms <= the sampled high time's bound {h_hi:.3f} ms")
    check(h_lo >= width_ms - 2 * gap,
          f"{name}: sampled high {h_lo:.3f} ms >= width - 2 sample gaps ({2 * gap:.3f} ms)")


def wait_armed(timeout_s):
    """Until the tool's edge interrupt (named after its consumer) is requested."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        with open("/proc/interrupts") as f:
            if "pmsm-gpio-bench" in f.read():
                return True
        time.sleep(0.005)
    return False


def rchar(pid):
    with open(f"/proc/{pid}/io") as f:
        return int(next(v for k, v in (row.split(":") for row in f) if k == "rchar"))


def wait_read(pid, target, timeout_s):
    """Until the process has read target bytes in all (rchar), or timeout."""
    deadline = time.monotonic() + timeout_s
    while rchar(pid) < target:
        if time.monotonic() > deadline:
            return False
        time.sleep(0.005)
    return True


def in_range(name, value, lo, hi):
    """value (the tool's, ns) within the generator's bounds [lo, hi] (ns); the
    tool prints means to 0.001 ns."""
    return check(lo - 0.001 <= value <= hi + 0.001,
                 f"{name} {value / 1e3:.3f} us within [{lo / 1e3:.3f}, {hi / 1e3:.3f}] us")


def isr_run(sim, pulses, out_dir, line, active_low, n, width_us, period_us, end):
    """isr against n generated pulses. end: "deadline" (--seconds: the
    generator's time plus 1 s), "sigterm" (SIGTERM once the tool has read
    every edge), "overflow" (the tool stopped, SIGSTOP, while the 2 n edges
    overflow the kernel's event buffer, continued, SIGCONT, then SIGTERM once
    it has read the buffer: the oldest edges lost)."""
    pol = " --active-low" if active_low else ""
    name = f"isr{pol} (line {line}, {n} pulses {width_us} us / {period_us} us, {end})"
    sim.pull(line, active_low)  # idle level: inactive
    gen_s = (n + 1) * period_us / 1e6
    kept = min(2 * n, KERNEL_EVENTS)  # the edges the tool can get
    lost = 2 * n - kept
    js = os.path.join(out_dir, f"isr_line{line}.json")
    seconds = gen_s + 1.0 if end == "deadline" else 600
    proc = start(sim.tool("isr", line, "--seconds", f"{seconds:.3f}", "--expect-period-us",
                          period_us, "--max-lost", lost, "--json", js, active_low=active_low))
    if not check(wait_armed(TOOL_TIMEOUT_S), f"{name}: the tool's edge interrupt requested"):
        proc.kill()
        return
    if end == "overflow":
        proc.send_signal(signal.SIGSTOP)
    before = rchar(proc.pid)
    gen = run([pulses, sim.attr(line, "pull"), str(n), str(width_us), str(period_us)]
              + (["--low"] if active_low else []))
    if end == "deadline":
        check(proc.poll() is None, f"{name}: the capture still on when the generator ended "
              "(else this host was too slow for the 1 s margin)")
    if end == "overflow":
        check(rchar(proc.pid) == before, f"{name}: nothing read while stopped")
        proc.send_signal(signal.SIGCONT)
    if end != "deadline":
        if check(wait_read(proc.pid, before + kept * EVENT_BYTES, TOOL_TIMEOUT_S),
                 f"{name}: the tool read {kept} events"):
            proc.send_signal(signal.SIGTERM)
        else:
            proc.kill()
    out, err = proc.communicate(timeout=TOOL_TIMEOUT_S + seconds)
    sys.stdout.write(out)
    if not check(gen.returncode == 0, f"{name}: generator {gen.stderr.strip()!r}"):
        return
    if not check(proc.returncode == 0, f"{name}: exit {proc.returncode} {err.strip()!r}"):
        return
    edges = [tuple(int(x) for x in row.split()) for row in gen.stdout.splitlines()]
    # the tool sees the last kept / 2 pulses (the oldest edges are dropped,
    # whole pulses: 2 n and the buffer are even)
    starts = [(b, a) for s, b, a in edges if s == 1][n - kept // 2:]
    ends = [(b, a) for s, b, a in edges if s == 0][n - kept // 2:]
    m = len(starts)
    with open(js) as f:
        r = json.load(f)
    # counts: exactly what was generated, less what the kernel's buffer dropped
    check(r["edges"] == {"total": 2 * m, "rising": m, "falling": m}, f"{name}: edges {r['edges']}")
    check(r["lost"] == {"line_seqno": lost, "global_seqno": lost},
          f"{name}: lost {r['lost']} ({lost})")
    check(r["glitches"] == 0 and r["sequence_errors"] == 0 and r["timestamps_back"] == 0,
          f"{name}: no glitch, sequence error, timestamp back")
    check(r["active_low"] == active_low and r["passed"] is True, f"{name}: active_low, passed")
    check(r["isr_duration"]["count"] == m and r["period"]["count"] == m - 1,
          f"{name}: {r['isr_duration']['count']} durations ({m}), "
          f"{r['period']['count']} periods ({m - 1})")
    # timing: a pulse's duration lies in [end.before - start.after,
    # end.after - start.before], a period likewise between two starts; the
    # tool's min, mean and max are then within the min, mean and max of
    # those bounds
    dur = [(e[0] - s[1], e[1] - s[0]) for s, e in zip(starts, ends)]
    per = [(b[0] - a[1], b[1] - a[0]) for a, b in zip(starts, starts[1:])]
    for key, bounds in (("isr_duration", dur), ("period", per)):
        lo = [b[0] for b in bounds]
        hi = [b[1] for b in bounds]
        st = r[key]
        in_range(f"{name}: {key} min", st["min"], min(lo), min(hi))
        in_range(f"{name}: {key} mean", st["mean"], sum(lo) / len(lo), sum(hi) / len(hi))
        in_range(f"{name}: {key} max", st["max"], max(lo), max(hi))
    # jitter against the expected period, its histogram holds every period
    p_ns = period_us * 1000
    j, h = r["jitter"], r["histogram"]
    check(r["jitter_reference"] == "expected" and r["jitter_reference_period"] == p_ns
          and j["count"] == m - 1 and j["min"] == r["period"]["min"] - p_ns
          and j["max"] == r["period"]["max"] - p_ns,
          f"{name}: jitter = period - {period_us} us")
    check(h["complete"] is True and sum(b["count"] for b in h["bins"]) == m - 1
          and h["bins"][0]["lo"] <= j["min"] and j["max"] < h["bins"][-1]["lo"] + h["bin"],
          f"{name}: histogram of {m - 1} periods, {len(h['bins'])} bins of "
          f"{h['bin'] / 1e3:.3f} us")
    spread = max(a - b for b, a in starts + ends)
    print(f"     {name}: the generator's writes took up to {spread / 1e3:.1f} us (the bounds' "
          f"width); {(edges[-1][2] - edges[0][1]) / 1e6:.0f} ms for {len(edges)} edges")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bench", required=True, help="the pmsm-gpio-bench binary")
    ap.add_argument("--pulses", required=True, help="the gpio_sim_pulses binary")
    ap.add_argument("--out", required=True, help="directory for the JSON reports")
    args = ap.parse_args()
    sim = Sim(args.bench)
    os.makedirs(args.out, exist_ok=True)
    check(sim.lines >= 6, f"{sim.chip}: {sim.lines} simulated lines (6 used)")

    # a wrong chip path: exit 2, the chips there listed; not a chip: exit 2
    other = os.path.join(os.path.dirname(sim.chip), "gpiochip99")
    r = run([args.bench, "isr", "--chip", other, "--line", "0", "--seconds", "1"])
    check(r.returncode == 2 and os.path.basename(sim.chip) in r.stderr,
          f"absent chip: exit {r.returncode} (2), {r.stderr.strip()!r}")
    r = run([args.bench, "isr", "--chip", "/dev/null", "--line", "0", "--seconds", "1"])
    check(r.returncode == 2 and "not a GPIO chip" in r.stderr,
          f"not a chip: exit {r.returncode} (2), {r.stderr.strip()!r}")

    sto_hold(sim, 0, False, False, "assert")
    sto_hold(sim, 0, True, False, "release", hold_s=2)
    sto_hold(sim, 1, True, True, "assert")
    sto_hold(sim, 1, False, True, "release")
    sto_pulse(sim, 2, 300)
    isr_run(sim, args.pulses, args.out, 3, False, n=25, width_us=4000, period_us=10000,
            end="deadline")
    isr_run(sim, args.pulses, args.out, 4, True, n=25, width_us=4000, period_us=10000,
            end="sigterm")
    isr_run(sim, args.pulses, args.out, 5, False, n=600, width_us=1000, period_us=2500,
            end="overflow")

    if failures:
        print(f"gpio_sim_bench: {len(failures)} check(s) failed:", file=sys.stderr)
        for f in failures:
            print(f"  {f}", file=sys.stderr)
        return 1
    print("gpio_sim_bench: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
