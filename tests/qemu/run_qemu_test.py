#!/usr/bin/env python3
"""Run a Cortex-M4 image in QEMU (mps2-an386, -icount) and check its output.

The image prints "CHECK <key> <value>" lines over semihosting and exits via
semihosting with a status. This script requires that status and compares
the values: --expect "key value tol" (|x - value| <= tol), --max "key limit"
(x <= limit). Every key named must have been printed exactly once.
"""
import argparse
import re
import subprocess
import sys
import time


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--qemu", default="qemu-system-arm")
    ap.add_argument("--icount-shift", type=int, required=True)
    ap.add_argument("--exit-status", type=int, default=0)
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("--expect", action="append", default=[])
    ap.add_argument("--max", action="append", default=[])
    ap.add_argument("image")
    a = ap.parse_args()

    cmd = [a.qemu, "-M", "mps2-an386", "-nographic", "-monitor", "none",
           "-serial", "none",
           "-semihosting-config", "enable=on,target=native",
           "-icount", f"shift={a.icount_shift},align=off,sleep=off",
           "-kernel", a.image]
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           timeout=a.timeout, check=False)
    except subprocess.TimeoutExpired:
        print(f"FAIL: QEMU did not exit within {a.timeout} s")
        return 1
    out = p.stdout.decode(errors="replace")
    print(out, end="" if out.endswith("\n") else "\n")
    print(f"[qemu exit status {p.returncode}, {time.monotonic() - t0:.1f} s wall]")

    ok = True
    if p.returncode != a.exit_status:
        print(f"FAIL: exit status {p.returncode}, expected {a.exit_status}")
        ok = False

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
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
