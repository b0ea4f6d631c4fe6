#!/usr/bin/env python3
"""Run a Cortex-M4 image in QEMU (mps2-an386, -icount) and check its output.

The image prints "CHECK <key> <value>" lines over semihosting (or a serial
port: --serial-stdio N) and exits via semihosting with a status (or, with
--run-for S, is stopped after S seconds; --expect-line REGEX: some output
line must match). This script requires that status and compares
the values: --expect "key value tol" (|x - value| <= tol), --max "key limit"
(x <= limit). Every key named must have been printed exactly once.

--budget FILE --budget-image NAME: the ISR instruction budget
(tests/qemu/isr_budget.json, entry NAME, "instructions"): for each group
there (run = all RUN ISRs, run_fast = without the outer-loop tick,
run_slow = with it) the image's run_<group>_max_instr and
run_<group>_mean_instr (run: run_max_instr, run_mean_instr) must not
exceed the file's max and mean by more than the file's tolerance (2 %).
The comparison is printed; values more than that BELOW the budget are
noted (the file may then be lowered, with a reason).
"""
import argparse
import json
import re
import subprocess
import sys
import time


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--qemu", default="qemu-system-arm")
    ap.add_argument("--machine", default="mps2-an386", help="QEMU -M (the board)")
    ap.add_argument("--icount-shift", type=int, required=True)
    ap.add_argument("--exit-status", type=int, default=0)
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("--expect", action="append", default=[])
    ap.add_argument("--max", action="append", default=[])
    ap.add_argument("--budget", help="ISR budget file (tests/qemu/isr_budget.json)")
    ap.add_argument("--budget-image", help="the image's entry in the budget file")
    ap.add_argument("--serial-stdio", type=int, default=None, metavar="N",
                    help="route the board's serial port N (0-based) to stdout, "
                         "the others to nothing (default: no serial port)")
    ap.add_argument("--run-for", type=float, default=None, metavar="S",
                    help="the image is not expected to exit: stop QEMU after S s "
                         "of wall time and check only its output")
    ap.add_argument("--expect-line", action="append", default=[], metavar="REGEX",
                    help="some output line must match REGEX (re.search)")
    ap.add_argument("image")
    a = ap.parse_args()

    serial = ["-serial", "none"]
    if a.serial_stdio is not None:
        serial = ["-serial", "null"] * a.serial_stdio + ["-serial", "stdio"]
    cmd = [a.qemu, "-M", a.machine, "-nographic", "-monitor", "none",
           *serial,
           "-semihosting-config", "enable=on,target=native",
           "-icount", f"shift={a.icount_shift},align=off,sleep=off",
           "-kernel", a.image]
    t0 = time.monotonic()
    stopped = False
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           timeout=a.run_for if a.run_for is not None else a.timeout,
                           check=False)
        out, status = p.stdout, p.returncode
    except subprocess.TimeoutExpired as e:
        if a.run_for is None:
            print(f"FAIL: QEMU did not exit within {a.timeout} s")
            return 1
        out, status, stopped = e.stdout or b"", None, True
    out = out.decode(errors="replace")
    print(out, end="" if out.endswith("\n") else "\n")
    print(f"[qemu {'stopped after --run-for' if stopped else f'exit status {status}'}, "
          f"{time.monotonic() - t0:.1f} s wall]")

    ok = True
    if a.run_for is not None and not stopped:
        print(f"FAIL: the image exited (status {status}) within --run-for {a.run_for} s")
        ok = False
    elif a.run_for is None and status != a.exit_status:
        print(f"FAIL: exit status {status}, expected {a.exit_status}")
        ok = False
    for rx in a.expect_line:
        good = re.search(rx, out, re.M) is not None
        print(f"{'ok  ' if good else 'FAIL'} a line matches /{rx}/")
        ok = ok and good

    values = {}
    for m in re.finditer(r"^CHECK (\S+) (\S+)\s*$", out, re.M):
        key, val = m.group(1), m.group(2)
        if key in values:
            print(f"FAIL: {key} printed twice")
            ok = False
        values[key] = float(val)

    def get(key):
        if key not in values:
            print(f"FAIL: the image printed no CHECK {key}")
            return None
        return values[key]

    for spec in a.expect:
        key, want, tol = spec.split()
        x = get(key)
        if x is None:
            ok = False
            continue
        good = abs(x - float(want)) <= float(tol)
        print(f"{'ok  ' if good else 'FAIL'} {key} = {x:g}, expected "
              f"{float(want):g} +- {float(tol):g}")
        ok = ok and good
    for spec in a.max:
        key, limit = spec.split()
        x = get(key)
        if x is None:
            ok = False
            continue
        good = x <= float(limit)
        print(f"{'ok  ' if good else 'FAIL'} {key} = {x:g} <= {float(limit):g}")
        ok = ok and good
    if a.budget:
        ok = check_budget(a.budget, a.budget_image, get) and ok
    return 0 if ok else 1


def check_budget(path, image, get):
    """The instruction budget of `image` (module docstring); True if kept."""
    budget = json.load(open(path))
    tol = float(budget["tolerance"])
    entry = budget["images"].get(image)
    if entry is None:
        print(f"FAIL no entry {image} in {path}")
        return False
    print(f"ISR instruction budget ({path}, {image}; limit +{tol * 100:g} %; "
          f"reason of the entry: {entry['reason']})")
    ok = True
    for group, b in entry["instructions"].items():
        prefix = "run" if group == "run" else group
        for stat in ("max", "mean"):
            key = f"{prefix}_{stat}_instr"
            x = get(key)
            if x is None:
                ok = False
                continue
            limit = b[stat] * (1.0 + tol)
            rel = (x - b[stat]) / b[stat] * 100.0
            good = x <= limit
            note = ""
            if x < b[stat] * (1.0 - tol):
                note = " (more than the tolerance below: the budget may be lowered)"
            print(f"{'ok  ' if good else 'FAIL'} budget {key} = {x:.7g}, budget {b[stat]:.7g} "
                  f"({rel:+.2f} %){note}")
            ok = ok and good
    return ok


if __name__ == "__main__":
    sys.exit(main())
