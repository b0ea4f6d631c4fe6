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

--tables prints, from the file alone, the two markdown tables made from it:
README.md's "ISR cost on the Cortex-M4F" and hal/qemu_m4/README.md's "ISR
budget".

Usage: update_budget.py --build build/m4f --reason "what changed and why"
           [--image NAME]... [--whole-run] [--budget FILE]
       update_budget.py --tables [--budget FILE]
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


# README.md's row labels
LABELS = {
    "qemu_p001_foc_encoder": "FOC PI, encoder (p001), 20 kHz",
    "qemu_p001_idapbc_sensorless": "IDA-PBC, sensorless (p001), 20 kHz",
    "qemu_p001_nam_sensorless": "NAM: flux observer + PLL + FOC PI, sensorless (p001), 20 kHz",
    "qemu_p000_eeo": "EEO position regulator (p000), 20 kHz",
    "qemu_p002_cdobc": "CDOBC speed regulator (p002), 10 kHz",
}


def tables(budget):
    def mm(g, k_mean="mean", k_max="max", fmt="{:.1f}"):
        return "-" if g is None else f"{fmt.format(g[k_mean])} / {g[k_max]}"

    print("| controller | fast instr mean / max | slow instr mean / max | est. cycles mean "
          "(fast) / max (all) | stack ran / static (B) | firmware flash (B) | state RAM (B) |")
    print("|---|---|---|---|---|---|---|")
    for name, e in budget["images"].items():
        ins, w, st = e["instructions"], e["estimate_whole_run"], e["stack"]
        fw = e["size"]["firmware"]
        print(f"| {LABELS.get(name, name)} | {mm(ins['run_fast'])} | {mm(ins.get('run_slow'))} | "
              f"{w['run_fast']['mean_cycles']:.0f} / {w['run']['max_cycles']} | "
              f"{st['ran_bytes']} / {st['static_required_bytes']} | {fw['text']} | "
              f"{fw['state_bytes']} |")
    print()
    print("| image | instr fast max / mean | instr slow max / mean | est. cycles fast max / "
          "mean (window) | est. cycles slow max / mean (window) | stack static / required / "
          "ran | text (fw) | RAM = data + bss |")
    print("|---|---|---|---|---|---|---|---|")
    for name, e in budget["images"].items():
        ins, est, st, sz = e["instructions"], e["estimate"], e["stack"], e["size"]

        def rev(g, a, b):
            return "-" if g is None else f"{g[a]} / {g[b]:.1f}" if isinstance(g[b], float) \
                else f"{g[a]} / {g[b]}"
        img, fw = sz["image"], sz["firmware"]
        print(f"| `{name}` | {rev(ins['run_fast'], 'max', 'mean')} | "
              f"{rev(ins.get('run_slow'), 'max', 'mean')} | "
              f"{rev(est['run_fast'], 'max_cycles', 'mean_cycles')} | "
              f"{rev(est.get('run_slow'), 'max_cycles', 'mean_cycles')} | "
              f"{st['static_bytes']} / {st['static_required_bytes']} / {st['ran_bytes']} | "
              f"{img['text']} ({fw['text']}) | {img['data']} + {img['bss']} (fw {fw['data']} + "
              f"{fw['bss']}; mc_app_t {fw['state_bytes']}) |")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", help="the m4f build tree (tests built)")
    ap.add_argument("--reason", help="what changed and why the values are "
                    "accepted (the entry's new reason)")
    ap.add_argument("--tables", action="store_true", help="print the README tables")
    ap.add_argument("--image", action="append", help="entry to update (repeatable; "
                    "default: all)")
    ap.add_argument("--whole-run", action="store_true", help="also re-measure "
                    "estimate_whole_run (slow)")
    ap.add_argument("--budget", default=os.path.join(HERE, "isr_budget.json"))
    a = ap.parse_args()
    budget = json.load(open(a.budget))
    if a.tables:
        tables(budget)
        return 0
    if not a.build or not a.reason:
        ap.error("--build and --reason are required to update")
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
