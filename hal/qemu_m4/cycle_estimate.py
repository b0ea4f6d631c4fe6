#!/usr/bin/env python3
"""Cycle ESTIMATE of mc_app_fast_isr on a Cortex-M4F from a QEMU trace.

Method: run the image (under -icount with the shift the image was built
for, read from its qemu_m4_icount_shift, like the tests: the firmware's
deadline check reads the SysTick counter) with
  -d in_asm,exec,nochain -dfilter <ranges>
where the ranges cover the firmware code (every function defined in the
given static libraries) plus the C library routines it calls (memcpy,
memset, lroundf). in_asm gives the instructions of each translation block
(TB), exec (with nochain) logs every TB execution, so the executed
instruction stream of each ISR is reconstructed exactly; an ISR is the
stream from the entry of mc_app_fast_isr to the next TB of the wrapper
__wrap_mc_app_fast_isr (its return). Each instruction gets a Cortex-M4
cycle weight (ARM Cortex-M4 TRM r0p1, section 3.3.1, and the FPU
instruction table 7.2.3):
  ALU / MOV / compare / MUL / IT / FPU arithmetic (VADD, VMUL, VCVT, VCMP,
  VMOV, VMRS, VABS, VNEG) 1;
  LDR/STR (any width) 2; LDRD/STRD 3; LDM/STM/PUSH/POP 1+N, +2 with pc;
  VLDR/VSTR 2; VLDM/VSTM/VPUSH/VPOP 1+N (N single registers);
  VMLA/VMLS/VNMLA/VNMLS/VFMA/VFMS/VFNMA/VFNMS 3; VDIV/VSQRT 14;
  MLA/MLS/SMLAL/UMLAL 2 (long multiply-accumulate ~ up to 7, rare here);
  SDIV/UDIV 12 (upper bound: 2-12);
  branch (B, BL, BX, CBZ/CBNZ, TBB/TBH, POP {pc}, LDR pc) taken: +2
  (pipeline refill 1 + P, P = 2, the middle of the TRM's 1-3).
Not modelled: the back-to-back load pipelining (an over-estimate of up to 1
cycle per neighbouring load/store), flash wait states (the budget assumes
zero-wait execution, e.g. ART accelerator / CCM-SRAM), interrupt entry/exit
(12 + 10 cycles of stacking, added separately in the report).

Usage: cycle_estimate.py IMAGE.elf LIB.a... [--skip N] [--count M]
  skip the first N ISRs, analyse the next M (then stop QEMU).
"""
import argparse
import re
import subprocess
import sys
from collections import Counter

NM = "arm-none-eabi-nm"


def func_names(libs):
    names = set()
    for lib in libs:
        out = subprocess.run([NM, "--defined-only", lib], capture_output=True,
                             text=True, check=True).stdout
        for line in out.splitlines():
            p = line.split()
            if len(p) == 3 and p[1] in "Tt":
                names.add(p[2])
    return names | {"memcpy", "memset", "lroundf"}


def ranges(elf, names):
    out = subprocess.run([NM, "-S", "--defined-only", elf], capture_output=True,
                         text=True, check=True).stdout
    rs, syms = [], {}
    for line in out.splitlines():
        p = line.split()
        if len(p) == 4 and p[2] in "Tt":
            addr, size = int(p[0], 16) & ~1, int(p[1], 16)
            syms[p[3]] = addr
            if p[3] in names:
                rs.append((addr, addr + size))
    rs.sort()
    merged = []
    for a, b in rs:
        if merged and a <= merged[-1][1] + 64:
            merged[-1] = (merged[-1][0], max(b, merged[-1][1]))
        else:
            merged.append((a, b))
    return merged, syms


def icount_shift(elf):
    """The -icount shift the image was built for (its qemu_m4_icount_shift)."""
    out = subprocess.run([NM, "--defined-only", elf], capture_output=True, text=True,
                         check=True).stdout
    addr = next(int(p[0], 16) for p in (l.split() for l in out.splitlines())
                if len(p) == 3 and p[2] == "qemu_m4_icount_shift")
    dump = subprocess.run(["arm-none-eabi-objdump", "-s", f"--start-address=0x{addr:x}",
                           f"--stop-address=0x{addr + 4:x}", elf],
                          capture_output=True, text=True, check=True).stdout
    word = next(l.split()[1] for l in dump.splitlines() if l.strip().startswith(f"{addr:x}"))
    return int.from_bytes(bytes.fromhex(word), "little")


def reglist_n(ops):
    m = re.search(r"\{([^}]*)\}", ops)
    if not m:
        return 1, False
    n, pc = 0, False
    for part in m.group(1).split(","):
        part = part.strip()
        if "-" in part:
            a, b = part.split("-")
            n += int(re.sub(r"\D", "", b)) - int(re.sub(r"\D", "", a)) + 1
        else:
            n += 1
            pc = pc or part == "pc"
    return n, pc


BRANCH = re.compile(r"^(b|bl|blx|bx|cbz|cbnz|tbb|tbh)(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?(\.[nw])?$")


def weight(mn, ops):
    """(base cycles, is_branch_like)."""
    m = mn.split(".")[0]
    if BRANCH.match(mn):
        return 1, True
    if m in ("vdiv", "vsqrt"):
        return 14, False
    if m in ("vmla", "vmls", "vnmla", "vnmls", "vfma", "vfms", "vfnma", "vfnms"):
        return 3, False
    if m in ("vldr", "vstr"):
        return 2, False
    if m in ("vpush", "vpop", "vldmia", "vstmia", "vldmdb", "vstmdb", "vldm", "vstm"):
        n, _ = reglist_n(ops)
        return 1 + n, False
    if m in ("push", "pop", "ldm", "ldmia", "stm", "stmia", "stmdb", "ldmdb"):
        n, pc = reglist_n(ops)
        return 1 + n, pc
    if re.match(r"^(ldrd|strd)", m):
        return 3, False
    if re.match(r"^(ldr|str)", m):
        return 2, ops.split(",")[0].strip() == "pc"
    if m in ("sdiv", "udiv"):
        return 12, False
    if m in ("mla", "mls", "smlal", "umlal"):
        return 2, False
    return 1, False


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("elf")
    ap.add_argument("libs", nargs="+")
    ap.add_argument("--skip", type=int, default=0)
    ap.add_argument("--count", type=int, default=2000)
    ap.add_argument("--qemu", default="qemu-system-arm")
    a = ap.parse_args()

    names = func_names(a.libs)
    rs, syms = ranges(a.elf, names)
    isr_entry = syms["mc_app_fast_isr"]
    wrap = syms["__wrap_mc_app_fast_isr"]
    dfilter = ",".join(f"0x{lo:x}..0x{hi - 1:x}" for lo, hi in rs)
    cmd = [a.qemu, "-M", "mps2-an386", "-nographic", "-monitor", "none",
           "-serial", "none", "-semihosting-config", "enable=on,target=native",
           "-icount", f"shift={icount_shift(a.elf)},align=off,sleep=off",
           "-d", "in_asm,exec,nochain", "-dfilter", dfilter,
           "-D", "/dev/stderr", "-kernel", a.elf]
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         text=True, bufsize=1 << 20)
    tbs = {}          # start pc -> list of (pc, size, mnemonic, ops)
    cur_tb = None
    in_isr = False
    isr_index = -1
    prev_last = None  # (pc, size, branch_like) of the last insn of the previous TB
    acc = None
    results = []
    classes_total = Counter()
    insn_re = re.compile(r"^0x([0-9a-f]+):\s+([0-9a-f]{4})(?: ([0-9a-f]{4}))?\s+(\S+)\s*(.*)$")
    exec_re = re.compile(r"^Trace \d+: 0x[0-9a-f]+ \[[0-9a-f]+/([0-9a-f]+)/")
    for line in p.stderr:
        if line.startswith("IN:"):
            cur_tb = []
            continue
        if cur_tb is not None:
            m = insn_re.match(line)
            if m:
                pc = int(m.group(1), 16)
                size = 2 if m.group(3) is None else 4
                cur_tb.append((pc, size, m.group(4), m.group(5)))
                continue
            if cur_tb:
                tbs[cur_tb[0][0]] = cur_tb
            cur_tb = None
        m = exec_re.match(line)
        if not m:
            continue
        pc = int(m.group(1), 16)
        if pc == isr_entry:
            in_isr = True
            isr_index += 1
            acc = {"instr": 0, "cycles": 0, "div_sqrt": 0, "taken": 0}
            prev_last = None
        elif in_isr and wrap <= pc < wrap + 0x100:
            in_isr = False
            if prev_last and prev_last[2]:
                acc["cycles"] += 2  # the return branch into the wrapper
            if isr_index >= a.skip:
                results.append(acc)
                if len(results) >= a.count:
                    p.kill()
                    break
            continue
        if not in_isr:
            continue
        if prev_last is not None and prev_last[2] and pc != prev_last[0] + prev_last[1]:
            acc["cycles"] += 2
            acc["taken"] += 1
        tb = tbs.get(pc)
        if tb is None:
            print(f"warning: TB 0x{pc:x} not seen in in_asm", file=sys.stderr)
            prev_last = None
            continue
        for (ipc, size, mn, ops) in tb:
            w, br = weight(mn, ops)
            acc["instr"] += 1
            acc["cycles"] += w
            if mn.split(".")[0] in ("vdiv", "vsqrt"):
                acc["div_sqrt"] += 1
            if isr_index >= a.skip:
                classes_total[mn.split(".")[0]] += 1
        last = tb[-1]
        prev_last = (last[0], last[1], weight(last[2], last[3])[1])
    p.wait()
    if not results:
        print("no ISR analysed")
        return 1

    def stat(k):
        v = [r[k] for r in results]
        return min(v), sum(v) / len(v), max(v)
    print(f"ISRs analysed: {len(results)} (skipped {a.skip})")
    for k in ("instr", "cycles", "div_sqrt", "taken"):
        lo, mean, hi = stat(k)
        print(f"{k:9s} min {lo:7.0f}  mean {mean:9.1f}  max {hi:7.0f}")
    cpi = sum(r["cycles"] for r in results) / sum(r["instr"] for r in results)
    print(f"estimated CPI {cpi:.3f}")
    print("most executed mnemonics:",
          ", ".join(f"{m} {n}" for m, n in classes_total.most_common(12)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
