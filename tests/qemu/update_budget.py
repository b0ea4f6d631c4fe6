#!/usr/bin/env python3
"""Rewrite entries of the ISR budget file (tests/qemu/isr_budget.json) from
measurements, with the reason that the file's "about" asks for.

For each image (default: every entry of the file):
  instructions  the image's ctest run in BUILD (ctest -R ^IMAGE$ -V: the
                CHECK lines of its SysTick meter: run_fast/run_slow counts,
                max and mean; run over both);
  estimate      hal/qemu_m4/cycle_estimate.py --json on the entry's window;
  estimate_whole_run (only with --whole-run, minutes per image) the same
                over every RUN ISR of the run;
  stack, size   from the window's estimate run (the stack paths, the
                image's and the firmware's sizes; state_bytes = the image's
                CHECK mc_app_bytes).
Groups the entry does not have (an image without a decimated loop has no
run_slow) stay absent. The file keeps its layout: objects and lists of
scalars on one line, the "about" list one string per line.

Usage: update_budget.py --build build/m4f --reason "what changed and why"
           [--image NAME]... [--whole-run] [--budget FILE]
"""
import argparse
import json
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
ESTIMATE = os.path.join(ROOT, "hal", "qemu_m4", "cycle_estimate.py")
GROUPS = ("run", "run_fast", "run_slow")


def checks(build, image):
    """The CHECK values the image's ctest printed (its budget check may
    fail: that is why the file is being updated)."""
    out = subprocess.run(["ctest", "--test-dir", build, "-R", f"^{image}$", "-V"],
                         capture_output=True, text=True).stdout
    vals = {m.group(1): float(m.group(2))
            for m in re.finditer(r"CHECK (\S+) (\S+)\s*$", out, re.M)}
    if "run_fast_count" not in vals:
        sys.exit(f"error: ctest {image} printed no ISR counts:\n{out[-2000:]}")
    return vals


def instructions(vals, old):
    n_f, n_s = int(vals["run_fast_count"]), int(vals["run_slow_count"])
    new = {"run": {"n": n_f + n_s, "max": int(vals["run_max_instr"]),
                   "mean": vals["run_mean_instr"]},
           "run_fast": {"n": n_f, "max": int(vals["run_fast_max_instr"]),
                        "mean": vals["run_fast_mean_instr"]},
           "run_slow": {"n": n_s, "max": int(vals["run_slow_max_instr"]),
                        "mean": vals["run_slow_mean_instr"]}}
    return {g: new[g] for g in GROUPS if g in old}


def estimate(build, image, skip, count, optional):
    elf = os.path.join(build, "tests", "qemu", f"{image}.elf")
    cmd = [sys.executable, ESTIMATE, elf, "--skip", str(skip), "--count", str(count),
           "--su-root", build, "--json"]
    for f in optional:
        cmd += ["--optional", f]
    p = subprocess.run(cmd, capture_output=True, text=True)
    lines = p.stdout.splitlines()
    if p.returncode != 0 or "{" not in lines:
        sys.exit(f"error: cycle_estimate on {image}:\n" + "\n".join(lines[-30:]))
    start = lines.index("{")
    end = max(i for i, l in enumerate(lines) if l == "}")
    return json.loads("\n".join(lines[start:end + 1]))


def estimate_groups(values, old_groups, window):
    out = {"window": window}
    keys = ("n", "max_instr", "mean_instr", "max_cycles", "mean_cycles", "cpi")
    for g in GROUPS:
        if g in old_groups:
            out[g] = {k: values["estimate"][g][k] for k in keys}
    return out


def scalar(x):
    return not isinstance(x, (dict, list))


def dump(x, indent=0):
    """JSON with objects and lists of scalars on one line; the "about"
    list (long strings) one per line."""
    pad = "  " * indent
    if scalar(x):
        return json.dumps(x)
    if isinstance(x, list):
        if all(scalar(v) for v in x) and sum(len(json.dumps(v)) for v in x) < 400:
            return json.dumps(x)
        return "[\n" + ",\n".join(pad + "  " + dump(v, indent + 1) for v in x) + "\n" + pad + "]"
    if all(scalar(v) or (isinstance(v, list) and all(scalar(w) for w in v))
           for v in x.values()) and len(json.dumps(x)) < 200:
        return json.dumps(x)
    return "{\n" + ",\n".join(f'{pad}  {json.dumps(k)}: {dump(v, indent + 1)}'
                              for k, v in x.items()) + "\n" + pad + "}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True, help="the m4f build tree (tests built)")
    ap.add_argument("--reason", required=True, help="what changed and why the values are "
                    "accepted (the entry's new reason)")
    ap.add_argument("--image", action="append", help="entry to update (repeatable; "
                    "default: all)")
    ap.add_argument("--whole-run", action="store_true", help="also re-measure "
                    "estimate_whole_run (slow)")
    ap.add_argument("--budget", default=os.path.join(HERE, "isr_budget.json"))
    a = ap.parse_args()
    budget = json.load(open(a.budget))
    names = a.image or list(budget["images"])
    optional = budget["stack_optional"]["functions"]
    for name in names:
        old = budget["images"].get(name)
        if old is None:
            sys.exit(f"error: no entry {name} in {a.budget}")
        vals = checks(a.build, name)
        w = old["estimate"]["window"]
        est = estimate(a.build, name, w["skip_run"], w["count"], optional)
        new = {"reason": a.reason,
               "instructions": instructions(vals, old["instructions"]),
               "estimate": estimate_groups(est, old["estimate"], w)}
        if "estimate_whole_run" in old:
            if a.whole_run:
                n = new["instructions"]["run"]["n"]
                ww = {"skip_run": 0, "count": n}
                new["estimate_whole_run"] = estimate_groups(
                    estimate(a.build, name, 0, n, optional), old["estimate_whole_run"], ww)
            else:
                new["estimate_whole_run"] = old["estimate_whole_run"]
        stack = est["stack"]
        new["stack"] = {k: stack[k] for k in old["stack"]}
        fw = dict(est["size"]["firmware"])
        fw["state_bytes"] = int(vals["mc_app_bytes"])
        new["size"] = {"image": est["size"]["image"], "firmware": fw}
        budget["images"][name] = new
        r = new["instructions"]["run_fast"]
        print(f"{name}: run_fast max {r['max']} mean {r['mean']}, stack ran "
              f"{stack['ran_bytes']} B")
    with open(a.budget, "w") as f:
        f.write(dump(budget) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
