#!/usr/bin/env python3
"""Cycle ESTIMATE of mc_app_fast_isr on a Cortex-M4F from a QEMU trace,
checked instruction for instruction against the image's own SysTick
meter; the ISR's stack depth; the image's sizes; the ISR budget check.

1. Trace (hal/qemu_m4/README.md, "Cycle estimate"). The closed-loop image
   runs in a copy whose qemu_loop_report (tests/qemu/closed_loop.h, in
   .data) is set: after SKIP RUN ISRs the harness waits for a character on
   its semihosting console, calls qemu_loop_report_begin (the mark),
   prints "ISR <index> <instructions> <class>" for the next COUNT ISRs
   (the meter's count; class run_fast = a RUN ISR without the decimated
   outer-loop tick, run_slow = with it, by the firmware's own flag) and
   ends the run. QEMU (7.2) runs it under -icount (the shift the image was
   built for, its qemu_m4_icount_shift) with
     -d in_asm,out_asm,nochain -dfilter <ranges>
   and, while the image waits, this script turns exec on through the QEMU
   monitor (`log in_asm,out_asm,exec,nochain`; --trace-from-start: from
   the start) and sends the character. The log, per translation block
   (TB):
     IN: <symbol>                  in_asm: the guest instructions of a TB,
     0x<pc>:  <hex>  <insn>        logged when it is translated
     OUT: [size=<n>]               out_asm: its host code; the first host
     0x<host>:  ...                address is the TB's host pointer
     Trace <cpu>: 0x<host TB> [<cs_base>/<pc>/<flags>/<cflags>] <symbol>
                                   exec: a TB entered (nochain: every one)
     Stopped execution of TB chain before 0x<host TB> [<pc>] <symbol>
                                   the TB entered last ran no instruction
                                   (icount expired, an exit request)
     cpu_io_recompile: rewound execution of TB to <pc>
                                   the TB entered last ran only the
                                   instructions before <pc> (an MMIO access,
                                   e.g. a SysTick read, inside it); a
                                   1-instruction TB at <pc> follows
   Under -icount one guest pc has several translations: the full block,
   blocks cut at an icount budget boundary (cflags & 0x1ff = their length)
   and 1-instruction I/O blocks. So every executed TB is identified by its
   host pointer, bound to the in_asm block logged for that translation
   (the IN: block followed by the OUT: block that gives the pointer; a
   later translation with the same pointer, after a TB cache flush,
   rebinds it); a TB with a count in its cflags must have that many
   instructions; its executed part is all, none (Stopped) or the prefix
   before the rewound pc. An ISR is the call instruction (the `bl` into
   mc_app_fast_isr) and every instruction from the entry of
   mc_app_fast_isr to the first TB of the wrapper __wrap_mc_app_fast_isr
   after it: exactly the meter's window (its two SysTick reads are right
   before and after that `bl`; checked in the code). The instruction count
   of every analysed ISR must equal the meter's; a mismatch, a TB without
   an in_asm block or an inconsistent count is an error (exit status 1).
   The ranges: every function the ISR can reach by direct calls and tail
   branches from mc_app_fast_isr (the ELF's static call graph: objdump
   branch targets; an indirect call on the way is an error), the wrapper
   and the mark, except the C library routines the rest of the image
   (the plant's double arithmetic) also runs; an ISR branching into one of
   those is seen (its target) and the trace is rerun with it.

   Cycle weights (ARM Cortex-M4 TRM r0p1, 3.3.1, and the FPU instruction
   table 7.2.3):
     ALU / MOV / compare / MUL / IT / FPU arithmetic (VADD, VMUL, VCVT,
     VCMP, VMOV, VMRS, VABS, VNEG) 1;
     LDR/STR (any width) 2; LDRD/STRD 3; LDM/STM/PUSH/POP 1+N;
     VLDR/VSTR 2; VLDM/VSTM/VPUSH/VPOP 1+N (N single registers);
     VMLA/VMLS/VNMLA/VNMLS/VFMA/VFMS/VFNMA/VFNMS 3; VDIV/VSQRT 14;
     MLA/MLS/SMLAL/UMLAL 2; SDIV/UDIV 12 (upper bound: 2-12);
     a branch (B, BL, BX, CBZ/CBNZ, TBB/TBH, POP {pc}, LDR pc) taken, i.e.
     the next executed instruction is not the next in memory: +2
     (pipeline refill 1 + P, P = 2, the middle of the TRM's 1-3).
   Not modelled: the back-to-back load pipelining (an over-estimate of up
   to 1 cycle per neighbouring load/store), flash wait states (zero-wait
   execution assumed, e.g. ART accelerator / CCM-SRAM), interrupt
   entry/exit (12 + 10 cycles of stacking, ~ +17 with lazy FP stacking),
   conditional instructions skipped in an IT block (counted as executed).

2. Stack (no QEMU): the deepest path of the static call graph from
   mc_app_fast_isr (bl/blx targets = calls, a branch to another function's
   start = tail call, which replaces the caller's frame), each function's
   frame from GCC's -fstack-usage (the .su files under --su-root: the
   firmware and HAL objects) or, for the C library's routines, from its
   prologue (push / vpush / sub sp); where both exist they must agree.
   static = every path; static_required = without the calls into the
   --optional functions (the budget file's stack_optional); ran (with the
   trace) = only the functions the window's ISRs entered. Excluded: the
   exception frame (32 bytes, 104 with the FP context), the caller's frame.

3. Sizes: arm-none-eabi-size of the image (text; data + bss, the 64 kB
   stack included) and, from the linker map, the input sections the image
   takes from the firmware libraries (paths under firmware/).

--profile N: the N source functions that executed the most instructions
per window ISR, each executed address attributed to the innermost function
of its inline chain (addr2line -f -i), e.g. where an inlined block's
instructions go inside mc_app_fast_isr.

--budget FILE --image NAME: the window is the entry's estimate.window
(unless --skip/--count), and the estimated cycles (max, mean per group)
and the stack depths must not exceed the entry's by more than the file's
tolerance; sizes are printed beside the entry's. --json prints the values.

Usage: cycle_estimate.py IMAGE.elf [--skip N] [--count M] [--su-root DIR]...
           [--optional FUNC]... [--budget FILE --image NAME] [--no-trace]
           [--trace-from-start] [--trace-all] [--json] [--profile N]
"""
import argparse
import json
import os
import re
import struct
import socket
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter

NM = "arm-none-eabi-nm"
OBJDUMP = "arm-none-eabi-objdump"
SIZE = "arm-none-eabi-size"
ISR = "mc_app_fast_isr"
WRAP = "__wrap_mc_app_fast_isr"
MARK = "qemu_loop_report_begin"
REPORT = "qemu_loop_report"
# C library routines traced even though the plant shares them: the ISRs
# call them (struct copies and clears), and they are cheap in the log
ALWAYS_TRACED = {"memcpy", "memset", "memmove"}


def run(cmd):
    return subprocess.run(cmd, capture_output=True, text=True, check=True).stdout


# ---------------------------------------------------------------- the ELF

def symbols(elf):
    """name -> (address without the Thumb bit, size, nm type)."""
    syms = {}
    for line in run([NM, "-S", "--defined-only", elf]).splitlines():
        p = line.split()
        if len(p) == 4:
            syms[p[3]] = (int(p[0], 16) & ~1, int(p[1], 16), p[2])
        elif len(p) == 3:
            syms[p[2]] = (int(p[0], 16) & ~1, 0, p[1])
    return syms


def read_word(elf, addr):
    dump = run([OBJDUMP, "-s", f"--start-address=0x{addr:x}",
                f"--stop-address=0x{addr + 4:x}", elf])
    word = next(l.split()[1] for l in dump.splitlines()
                if l.strip().startswith(f"{addr:x}"))
    return int.from_bytes(bytes.fromhex(word), "little")


def patch_elf(elf, addr, data, out):
    """Copy `elf` to `out` with `data` written at the virtual address
    `addr` (in a section with file contents, e.g. .data)."""
    raw = bytearray(open(elf, "rb").read())
    if raw[:4] != b"\x7fELF" or raw[4] != 1 or raw[5] != 1:
        raise SystemExit(f"{elf}: not a 32-bit little-endian ELF")
    shoff, = struct.unpack_from("<I", raw, 0x20)
    shentsize, shnum = struct.unpack_from("<HH", raw, 0x2E)
    for i in range(shnum):
        _, sh_type, _, sh_addr, sh_offset, sh_size = struct.unpack_from(
            "<IIIIII", raw, shoff + i * shentsize)
        if sh_type == 1 and sh_addr <= addr and addr + len(data) <= sh_addr + sh_size:
            off = sh_offset + addr - sh_addr
            raw[off:off + len(data)] = data
            open(out, "wb").write(raw)
            return
    raise SystemExit(f"{elf}: 0x{addr:x} is in no section with contents")


FUNC_RE = re.compile(r"^([0-9a-f]+) <(.+)>:$")
INSN_RE = re.compile(r"^\s+([0-9a-f]+):\t(\S+)(?:\t(.*))?$")
TARGET_RE = re.compile(r"^([0-9a-f]+) <([^>+]+)(\+0x[0-9a-f]+)?>")


def disassemble(elf, syms):
    """name -> {"start", "end", "insns": [(addr, mnemonic, operands)]} for
    every function symbol (type T/t) with a size."""
    funcs, cur = {}, None
    for line in run([OBJDUMP, "-d", "--no-show-raw-insn", elf]).splitlines():
        m = FUNC_RE.match(line)
        if m:
            name = m.group(2)
            s = syms.get(name)
            cur = None
            if s and s[2] in "Tt" and s[1] > 0:
                cur = funcs[name] = {"start": s[0], "end": s[0] + s[1], "insns": []}
            continue
        if cur is None:
            continue
        m = INSN_RE.match(line)
        if m and not m.group(2).startswith("."):
            cur["insns"].append((int(m.group(1), 16), m.group(2), m.group(3) or ""))
    return funcs


def call_graph(funcs):
    """name -> {"calls": set, "tails": set, "indirect": [insn text]}."""
    starts = {f["start"]: n for n, f in funcs.items()}
    graph = {}
    for name, f in funcs.items():
        g = graph[name] = {"calls": set(), "tails": set(), "indirect": []}
        for addr, mn, ops in f["insns"]:
            base = mn.split(".")[0]
            if base in ("bl", "blx"):
                m = TARGET_RE.match(ops)
                if m:
                    g["calls"].add(m.group(2))
                else:
                    g["indirect"].append(f"{addr:x}: {mn} {ops}")
            elif re.match(r"^b(eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?$", base):
                m = TARGET_RE.match(ops)
                if m:
                    t = int(m.group(1), 16)
                    if not f["start"] <= t < f["end"] and t in starts:
                        g["tails"].add(starts[t])
            elif base == "bx" and ops.strip() != "lr":
                g["indirect"].append(f"{addr:x}: {mn} {ops}")
            elif re.match(r"^(ldr|mov)", base) and ops.split(",")[0].strip() == "pc":
                # ldr pc, [sp], #4 is a return; ldr pc, [rX, rY, lsl #2] a
                # switch's jump table inside the function
                if "[sp]" not in ops and not re.search(r"\[r\d+, r\d+, lsl #2\]", ops):
                    g["indirect"].append(f"{addr:x}: {mn} {ops}")
    return graph


def reachable(graph, root):
    seen, todo = set(), [root]
    while todo:
        n = todo.pop()
        if n in seen or n not in graph:
            continue
        seen.add(n)
        todo.extend(graph[n]["calls"] | graph[n]["tails"])
    return seen


# ---------------------------------------------------------------- stack

def prologue_frame(insns):
    """Bytes a function's prologue reserves: push/stmdb sp!, vpush,
    str rX, [sp, #-N]!, sub sp (the instructions before its first
    branch)."""
    total = 0
    for _, mn, ops in insns:
        base = mn.split(".")[0]
        if base in ("push", "vpush") or (base == "stmdb" and ops.startswith("sp!")):
            total += 4 * reglist_n(ops)[0] * (2 if re.search(r"\{d", ops) else 1)
        elif base == "str" and re.search(r"\[sp, #-(\d+)\]!", ops):
            total += int(re.search(r"\[sp, #-(\d+)\]!", ops).group(1))
        elif base in ("sub", "subw") and re.match(r"sp, (sp, )?#\d+", ops):
            total += int(re.search(r"#(\d+)", ops).group(1))
        elif base.startswith("b") or base in ("cbz", "cbnz", "pop", "tbb", "tbh"):
            break
    return total


def su_frames(roots):
    """function name -> list of (bytes, kind, "file:line") from every .su
    file under the roots."""
    frames = {}
    for d, _, files in (w for root in roots for w in os.walk(root)):
        for fn in files:
            if not fn.endswith(".su"):
                continue
            for line in open(os.path.join(d, fn)):
                p = line.rstrip("\n").split("\t")
                if len(p) != 3:
                    continue
                loc, size, kind = p
                name = loc.rsplit(":", 1)[1]
                frames.setdefault(name, []).append((int(size), kind, loc.rsplit(":", 1)[0]))
    return frames


def stack_depth(funcs, graph, su, root=ISR):
    """Deepest stack of `root`'s call tree: (bytes, path [(name, frame,
    source)], problems [text])."""
    frame, source, problems = {}, {}, []

    def frame_of(name):
        if name in frame:
            return frame[name]
        pro = prologue_frame(funcs[name]["insns"])
        cands = su.get(name, [])
        if cands:
            match = [c for c in cands if c[0] == pro]
            c = match[0] if match else max(cands)
            if not match:
                problems.append(f"{name}: .su {[x[0] for x in cands]} B, prologue {pro} B")
            if c[1] != "static":
                problems.append(f"{name}: .su says {c[1]}")
            frame[name], source[name] = c[0], ".su"
        else:
            frame[name], source[name] = pro, "prologue"
        return frame[name]

    memo, active = {}, set()

    def depth(name):
        if name in memo:
            return memo[name]
        if name not in funcs:
            problems.append(f"{name}: not a sized function in the ELF")
            return 0, []
        if name in active:
            problems.append(f"recursion through {name}")
            return 0, []
        active.add(name)
        g = graph[name]
        if g["indirect"]:
            problems.append(f"{name}: indirect call {g['indirect']}")
        own = frame_of(name)
        best, best_path = own, [(name, own, source[name])]
        for c in sorted(g["calls"]):
            d, p = depth(c)
            if own + d > best:
                best, best_path = own + d, [(name, own, source[name])] + p
        for c in sorted(g["tails"]):
            d, p = depth(c)
            if d > best:  # the tail-called function replaces this frame
                best, best_path = d, [(name, 0, "tail call")] + p
        active.discard(name)
        memo[name] = (best, best_path)
        return memo[name]

    bytes_, path = depth(root)
    return bytes_, path, problems


# ---------------------------------------------------------------- sizes

def image_size(elf):
    line = run([SIZE, elf]).splitlines()[1].split()
    return {"text": int(line[0]), "data": int(line[1]), "bss": int(line[2])}


def restricted_depth(funcs, graph, su, keep, title):
    """The deepest stack of the call graph with only the calls for which
    keep(callee) holds; printed under `title`. (bytes, [names])."""
    g = {n: {"calls": {c for c in g["calls"] if keep(c)},
             "tails": {c for c in g["tails"] if keep(c)},
             "indirect": g["indirect"]} for n, g in graph.items()}
    d, path, _ = stack_depth(funcs, g, su)
    print(f"{title}: {d} bytes")
    for name, fr, src in path:
        print(f"  {fr:5d}  {name}  ({src})")
    return d, [n for n, _, _ in path]


def firmware_size(mapfile, prefix="firmware/"):
    """text/data/bss of the input sections linked from archives whose path
    starts with `prefix` (after --gc-sections: the memory map part)."""
    out = {"text": 0, "data": 0, "bss": 0}
    section, pending = None, None
    in_map = False
    for line in open(mapfile):
        line = line.rstrip("\n")
        if line.startswith("Linker script and memory map"):
            in_map = True
            continue
        if not in_map:
            continue
        m = re.match(r"^(\.[\w.]+)", line)
        if m:
            section = m.group(1)
            continue
        m = re.match(r"^ (\S+)\s+0x([0-9a-f]+)\s+0x([0-9a-f]+)\s+(\S.*)$", line)
        if m:
            name, size, path = m.group(1), int(m.group(3), 16), m.group(4)
        else:
            m2 = re.match(r"^ (\S+)$", line)
            if m2 and not line.startswith(" *"):
                pending = m2.group(1)
                continue
            m3 = re.match(r"^\s+0x([0-9a-f]+)\s+0x([0-9a-f]+)\s+(\S.*)$", line)
            if not (m3 and pending):
                pending = None
                continue
            name, size, path = pending, int(m3.group(2), 16), m3.group(3)
        pending = None
        if not path.startswith(prefix) or name.startswith("*"):
            continue
        if section == ".data":
            out["data"] += size
        elif section == ".bss":
            out["bss"] += size
        elif section in (".text", ".isr_vector", ".ARM.extab", ".ARM.exidx"):
            out["text"] += size
    return out


# ---------------------------------------------------------------- weights

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


CONDS = ("eq", "ne", "cs", "hs", "cc", "lo", "mi", "pl", "vs", "vc", "hi", "ls",
         "ge", "lt", "gt", "le", "al")
KNOWN = {"b", "bl", "blx", "bx", "cbz", "cbnz", "tbb", "tbh", "vdiv", "vsqrt",
         "vmla", "vmls", "vnmla", "vnmls", "vfma", "vfms", "vfnma", "vfnms",
         "vldr", "vstr", "vpush", "vpop", "vldmia", "vstmia", "vldmdb",
         "vstmdb", "vldm", "vstm", "push", "pop", "ldm", "ldmia", "stm",
         "stmia", "stmdb", "ldmdb", "sdiv", "udiv", "mla", "mls", "smlal",
         "umlal"}


def base_mnemonic(mn):
    """The mnemonic without width suffix and, inside an IT block, without
    its condition (popne -> pop, bxeq -> bx, bls -> b)."""
    m = mn.split(".")[0]
    if m in KNOWN or re.match(r"^(ldr|str)", m):
        return m
    if len(m) > 2 and m[-2:] in CONDS and m[:-2] in KNOWN:
        return m[:-2]
    return m


def weight(mn, ops):
    """(base cycles, may branch)."""
    m = base_mnemonic(mn)
    if m in ("b", "bl", "blx", "bx", "cbz", "cbnz", "tbb", "tbh"):
        return 1, True
    if m in ("vdiv", "vsqrt"):
        return 14, False
    if m in ("vmla", "vmls", "vnmla", "vnmls", "vfma", "vfms", "vfnma", "vfnms"):
        return 3, False
    if m in ("vldr", "vstr"):
        return 2, False
    if m in ("vpush", "vpop", "vldmia", "vstmia", "vldmdb", "vstmdb", "vldm", "vstm"):
        n, _ = reglist_n(ops)
        return 1 + n * (2 if re.search(r"\{d", ops) else 1), False
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


class Block:
    """One translation: its instructions and prefix sums of the weights."""
    __slots__ = ("start", "n", "pcs", "ends", "cyc", "div", "br", "mn", "ops", "tgt")

    def __init__(self, insns):
        self.start = insns[0][0]
        self.n = len(insns)
        self.pcs = [i[0] for i in insns]
        self.ends = [i[0] + i[1] for i in insns]
        self.mn = [i[2] for i in insns]
        self.ops = [i[3] for i in insns]
        self.cyc, self.div, self.br = [0], [0], []
        for _, _, mn, ops in insns:
            w, b = weight(mn, ops)
            self.cyc.append(self.cyc[-1] + w)
            self.div.append(self.div[-1] + (base_mnemonic(mn) in ("vdiv", "vsqrt")))
            self.br.append(b)
        # the target of a direct branch ending the block (b, bl: "#0x974")
        m = re.match(r"^#0x([0-9a-f]+)$", self.ops[-1])
        self.tgt = int(m.group(1), 16) if self.br[-1] and m else None


class TraceError(Exception):
    pass


# 0x0000097e:  f04f 23e0  mov.w    r3, #-0x1fff2000   (one space between the
# halfwords of a 32-bit instruction, a wide gap before the mnemonic)
INASM_RE = re.compile(r"^0x([0-9a-f]+):\s+([0-9a-f]{4})(?: ([0-9a-f]{4}))?\s+(\S+)\s*(.*)$")


# ---------------------------------------------------------------- trace

def connect(path, timeout=30.0):
    t_end = time.monotonic() + timeout
    while True:
        sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            sock.connect(path)
            return sock
        except OSError:
            sock.close()
            if time.monotonic() > t_end:
                raise TraceError(f"QEMU did not open {path}")
            time.sleep(0.05)


class Console(threading.Thread):
    """The image's console (semihosting through a socket chardev): keeps
    its lines; at "ISR report: waiting" turns QEMU's exec log on through
    the monitor, then lets the image go on (one character)."""

    def __init__(self, con, mon, log_items, qemu):
        super().__init__(daemon=True)
        self.con, self.mon, self.log_items, self.qemu = con, mon, log_items, qemu
        self.lines, self.error = [], None

    def monitor(self, command):
        buf = b""
        self.mon.sendall(command.encode() + b"\n")
        while buf.count(b"(qemu)") < 1:
            chunk = self.mon.recv(4096)
            if not chunk:
                raise TraceError("the QEMU monitor closed")
            buf += chunk
        text = buf.decode(errors="replace")
        if "rror" in text or "nknown" in text:
            raise TraceError(f"monitor: {command}: {text.strip()}")

    def run(self):
        buf = b""
        try:
            # the banner and the first prompt
            greeting = b""
            while b"(qemu)" not in greeting:
                chunk = self.mon.recv(4096)
                if not chunk:
                    raise TraceError("the QEMU monitor closed")
                greeting += chunk
            while True:
                chunk = self.con.recv(65536)
                if not chunk:
                    break
                buf += chunk
                *done, buf = buf.split(b"\n")
                for raw in done:
                    line = raw.decode(errors="replace").rstrip("\r")
                    self.lines.append(line)
                    if line == "ISR report: waiting":
                        self.monitor(f"log {self.log_items}")
                        self.con.sendall(b"\n")
        except (OSError, TraceError) as e:
            self.error = e
            self.qemu.kill()  # the image would wait for ever
        if buf:
            self.lines.append(buf.decode(errors="replace"))


def trace(a, elf, syms, ranges):
    """Run the patched image under the trace: (ISR records of the window
    [(instr, cycles, div_sqrt, taken)], mnemonic counts of the window,
    statistics, block starts entered in ISRs, targets of branches from an
    ISR into untraced code, the image's report lines [(index, instr,
    class)])."""
    shift = read_word(elf, syms["qemu_m4_icount_shift"][0])
    isr_entry = syms[ISR][0]
    wrap_lo, wrap_hi = syms[WRAP][0], syms[WRAP][0] + syms[WRAP][1]
    mark = syms[MARK][0]
    tmp = tempfile.mkdtemp(prefix="cycle_estimate_")
    patched = os.path.join(tmp, os.path.basename(elf))
    wait = 0 if a.trace_from_start else 1
    patch_elf(elf, syms[REPORT][0], struct.pack("<IIII", a.skip, a.count, 1, wait), patched)
    dfilter = ",".join(f"0x{lo:x}..0x{hi - 1:x}" for lo, hi in ranges)
    con_path, mon_path = os.path.join(tmp, "con"), os.path.join(tmp, "mon")
    # in_asm + out_asm from the start: every translation's instructions and
    # its host TB pointer; exec (the costly part: a line per TB entered)
    # from the window on, turned on through the monitor while the image
    # waits (--trace-from-start: from the start)
    items = "in_asm,out_asm,exec,nochain"
    cmd = [a.qemu, "-M", "mps2-an386", "-nographic",
           "-monitor", f"unix:{mon_path},server=on,wait=off", "-serial", "none",
           "-chardev", f"socket,id=semihost,path={con_path},server=on,wait=on",
           "-semihosting-config", "enable=on,target=native,chardev=semihost",
           "-icount", f"shift={shift},align=off,sleep=off",
           "-d", items if a.trace_from_start else "in_asm,out_asm,nochain",
           "-dfilter", dfilter, "-D", "/dev/stderr", "-kernel", patched]
    p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         text=True, bufsize=1 << 20)
    con = mon = console = None
    try:
        con = connect(con_path)
        mon = connect(mon_path)
        console = Console(con, mon, items, p)
        console.start()
        res = parse_log(p.stderr, isr_entry, wrap_lo, wrap_hi, mark,
                        lambda x: any(lo <= x < hi for lo, hi in ranges))
        p.wait(timeout=60)
        console.join(timeout=10)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
        p.stderr.close()
        for s_ in (con, mon):
            if s_ is not None:
                s_.close()
        for f in (patched, con_path, mon_path):
            if os.path.exists(f):
                os.remove(f)
        os.rmdir(tmp)
    if console is None or console.error:
        raise TraceError(f"the image's console: {console.error if console else 'none'}")
    lines = console.lines
    report = []
    for l in lines:
        m = re.match(r"^ISR (\d+) (\d+) (\S+)$", l)
        if m:
            report.append((int(m.group(1)), int(m.group(2)), m.group(3)))
    if "STOP after the ISR report" not in lines:
        tail = "\n".join(lines[-15:])
        raise TraceError(f"the image did not end after its ISR report:\n{tail}")
    return res + (report,)


def parse_log(stream, isr_entry, wrap_lo, wrap_hi, mark, traced):
    blocks = {}          # host TB pointer (text) -> Block
    cur_in = None        # instructions of the in_asm block being read
    last_in = None       # the Block of the latest in_asm, until its OUT:
    want_ptr = False     # in an OUT: block, before its first host address
    pend = None          # (Block, ptr) entered, its executed part not yet known
    prev_br, prev_end, prev_mn, prev_ops = False, -1, "", ""
    in_isr, in_window = False, False
    acc = None
    results = []         # (instr, cycles, div_sqrt, taken) of the window's ISRs
    execs = Counter()    # (Block id, instructions executed) in the window
    block_of_id = {}
    stats = Counter()
    entered = set()      # block starts executed inside ISRs
    untraced = set()     # targets of branches out of the traced code in ISRs

    def commit(b, k):
        nonlocal prev_br, prev_end, prev_mn, prev_ops, in_isr, acc, in_window
        if k == 0:
            return
        if b.start == isr_entry:
            if base_mnemonic(prev_mn) not in ("bl", "blx"):
                raise TraceError(f"ISR entered after {prev_mn} {prev_ops}, not a call")
            in_isr = True
            stats["ISRs in the trace"] += 1
            # the call instruction (the meter counts it); its taken branch
            # is added below like every other
            acc = [1, weight(prev_mn, prev_ops)[0], 0, 0]
        elif b.start == mark:
            in_window = True
        if in_isr:
            entered.add(b.start)
            if k == b.n and b.tgt is not None and not traced(b.tgt):
                untraced.add(b.tgt)
            if prev_br and b.start != prev_end:
                acc[1] += 2
                acc[3] += 1
            acc[0] += k
            acc[1] += b.cyc[k]
            acc[2] += b.div[k]
            if in_window:
                execs[(id(b), k)] += 1
                block_of_id[id(b)] = b
        prev_br, prev_end = b.br[k - 1], b.ends[k - 1]
        prev_mn, prev_ops = b.mn[k - 1], b.ops[k - 1]

    for line in stream:
        c = line[:1]
        if cur_in is not None:
            m = INASM_RE.match(line)
            if m:
                cur_in.append((int(m.group(1), 16), 2 if m.group(3) is None else 4,
                               m.group(4), m.group(5).strip()))
                continue
            last_in = Block(cur_in) if cur_in else None
            cur_in = None
        if want_ptr:
            if c == "0":
                # the first host instruction of the translation = its TB
                # pointer in the exec log
                blocks[line.split(":", 1)[0]] = last_in
                stats["translations"] += 1
                last_in, want_ptr = None, False
            continue
        if c == "T" and line.startswith("Trace "):
            # Trace 0: 0x7f210c09ef00 [00800400/00000974/00000010/ff020200] sym
            parts = line.split(None, 4)
            ptr = parts[2]
            fields = parts[3][1:-1].split("/")
            if pend is not None:
                commit(pend[0], pend[0].n)
                pend = None
            b = blocks.get(ptr)
            if b is None:
                raise TraceError(f"TB {ptr} at {fields[1]} entered, no in_asm/out_asm "
                                 f"logged for it")
            if b.start != int(fields[1], 16):
                raise TraceError(f"TB {ptr} entered at {fields[1]}, translated at "
                                 f"{b.start:08x}")
            count = int(fields[3], 16) & 0x1FF
            if count and count != b.n:
                raise TraceError(f"TB {ptr} at {fields[1]}: cflags count {count}, "
                                 f"{b.n} instructions")
            stats["TBs entered"] += 1
            if count:
                stats["TBs with a count (I/O, icount budget)"] += 1
            if in_isr and wrap_lo <= b.start < wrap_hi:
                # back in the wrapper: the ISR is complete
                if prev_br and b.start != prev_end:
                    acc[1] += 2  # the return branch
                    acc[3] += 1
                in_isr = False
                if in_window:
                    results.append(tuple(acc))
            pend = (b, ptr)
            continue
        if c == "S" and line.startswith("Stopped execution of TB chain before "):
            ptr = line.split()[6]
            if pend is None or pend[1] != ptr:
                raise TraceError(f"'{line.strip()}' without that TB entered")
            pend = None
            stats["TBs stopped before their first instruction"] += 1
            continue
        if c == "c" and line.startswith("cpu_io_recompile: rewound execution of TB to "):
            pc = int(line.split()[-1], 16)
            if pend is None:
                raise TraceError(f"'{line.strip()}' without a TB entered")
            b = pend[0]
            if pc not in b.pcs:
                raise TraceError(f"rewound to {pc:08x}, not in the TB at {b.start:08x}")
            commit(b, b.pcs.index(pc))
            pend = None
            stats["TBs cut at an I/O access"] += 1
            continue
        if c == "I" and line.startswith("IN:"):
            cur_in = []
            continue
        if c == "O" and line.startswith("OUT:"):
            if last_in is not None:
                want_ptr = True
            continue
    if pend is not None:
        commit(pend[0], pend[0].n)
    mnem = Counter()
    for (bid, k), n in execs.items():
        for mn in block_of_id[bid].mn[:k]:
            mnem[base_mnemonic(mn)] += n
    pcs = Counter()      # instruction address -> executions in the window
    for (bid, k), n in execs.items():
        for pc in block_of_id[bid].pcs[:k]:
            pcs[pc] += n
    return results, mnem, stats, entered, untraced, pcs


# ---------------------------------------------------------------- main

def group_stats(rows):
    """rows: [(instr, cycles, div_sqrt, taken)] -> dict."""
    if not rows:
        return None
    n = len(rows)
    out = {"n": n}
    for i, k in enumerate(("instr", "cycles", "div_sqrt", "taken")):
        v = [r[i] for r in rows]
        out[k] = {"min": min(v), "mean": round(sum(v) / n, 1), "max": max(v)}
    out["cpi"] = round(sum(r[1] for r in rows) / sum(r[0] for r in rows), 3)
    return out


def compare(label, measured, budget, tol, lines, checked=True):
    """Append the comparison; True if within budget * (1 + tol) (or not
    checked: informational)."""
    ok = measured <= budget * (1.0 + tol) or not checked
    rel = (measured - budget) / budget * 100.0 if budget else 0.0
    tag = ("ok  " if ok else "FAIL") if checked else "info"
    lines.append(f"{tag} {label} = {measured:g}, budget {budget:g} ({rel:+.2f} %)")
    return ok


def merge_ranges(funcs, names):
    rs = sorted((funcs[n]["start"], funcs[n]["end"]) for n in names)
    ranges = []
    for lo, hi in rs:
        if ranges and lo <= ranges[-1][1] + 16:
            ranges[-1] = (ranges[-1][0], max(hi, ranges[-1][1]))
        else:
            ranges.append((lo, hi))
    return ranges


def toolchain_functions(mapfile):
    """Names of the functions the image takes from the toolchain's
    libraries (libgcc, libc, libm: absolute paths in the map)."""
    names, current = set(), None
    for line in open(mapfile):
        m = re.match(r"^ \S+\s+0x[0-9a-f]+\s+0x[0-9a-f]+\s+(\S.*)$", line) or \
            re.match(r"^\s+0x[0-9a-f]+\s+0x[0-9a-f]+\s+(\S.*)$", line)
        if m:
            current = m.group(1)
            continue
        m = re.match(r"^\s+0x[0-9a-f]+\s+(\w+)$", line)
        if m and current and os.path.isabs(current):
            names.add(m.group(1))
    return names


def print_table(groups):
    print(f"{'group':9s} {'ISRs':>5s}  {'instr min/mean/max':>24s}  "
          f"{'cycles min/mean/max':>24s}  {'CPI':>5s}  {'div+sqrt':>8s}")
    for g, st in groups.items():
        i, c = st["instr"], st["cycles"]
        print(f"{g:9s} {st['n']:5d}  {i['min']:6d} {i['mean']:8.1f} {i['max']:6d}    "
              f"{c['min']:6d} {c['mean']:8.1f} {c['max']:6d}  {st['cpi']:5.3f}  "
              f"{st['div_sqrt']['mean']:8.1f}")


def print_profile(elf, pcs, n_isr, top):
    """Instructions per ISR by source function: each executed address is
    attributed to the innermost function of its inline chain
    (addr2line -f -i: the first function printed for the address)."""
    addrs = sorted(pcs)
    out = subprocess.run(["arm-none-eabi-addr2line", "-a", "-f", "-i", "-e", elf]
                         + [f"0x{x:x}" for x in addrs], capture_output=True,
                         text=True, check=True).stdout.splitlines()
    func_of = {}
    i = 0
    while i < len(out):
        addr = int(out[i], 16)
        func_of[addr] = (out[i + 1], os.path.basename(out[i + 2].split(":")[0]))
        i += 3
        while i < len(out) and not out[i].startswith("0x"):
            i += 1
    per = Counter()
    for x, n in pcs.items():
        per[func_of[x]] += n
    total = sum(pcs.values())
    print(f"profile: instructions per ISR by source function (innermost inlined), "
          f"{total / n_isr:.1f} per ISR over {n_isr} ISRs")
    for (fn, src), n in per.most_common(top):
        print(f"  {n / n_isr:8.1f}  {fn}  ({src})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("elf")
    ap.add_argument("--skip", type=int, help="RUN ISRs before the window (default: "
                    "the budget entry's window, else 0)")
    ap.add_argument("--count", type=int, help="ISRs in the window (default: the budget "
                    "entry's window, else 200)")
    ap.add_argument("--qemu", default="qemu-system-arm")
    ap.add_argument("--su-root", action="append", default=[],
                    help="directory searched for .su files (the build tree; repeatable)")
    ap.add_argument("--map", help="linker map (default: IMAGE.map beside the ELF)")
    ap.add_argument("--trace-all", action="store_true",
                    help="trace every function the ISR can reach (slow: the plant's "
                         "double arithmetic shares them)")
    ap.add_argument("--trace-from-start", action="store_true",
                    help="log every TB execution from the start (slow; a cross-check "
                         "of the default, which turns the exec log on at the window)")
    ap.add_argument("--budget", help="budget file (tests/qemu/isr_budget.json)")
    ap.add_argument("--image", help="the image's entry in the budget file")
    ap.add_argument("--optional", action="append", default=[],
                    help="a function the ISR calls only when configured so: the stack "
                         "is also given without the calls into it (default: the budget "
                         "file's stack_optional)")
    ap.add_argument("--no-trace", action="store_true", help="stack and sizes only")
    ap.add_argument("--json", action="store_true", help="print the values as JSON")
    ap.add_argument("--profile", type=int, metavar="N", default=0,
                    help="print the N source functions (inlined code resolved by "
                         "addr2line -i: the innermost function) that executed the "
                         "most instructions per window ISR")
    a = ap.parse_args()
    t_start = time.monotonic()
    entry = None
    if a.budget:
        budget = json.load(open(a.budget))
        entry = budget["images"].get(a.image)
        if entry is None:
            print(f"error: no entry {a.image} in {a.budget}")
            return 1
        tol = float(budget["tolerance"])
    window = entry["estimate"]["window"] if entry else {"skip_run": 0, "count": 200}
    if entry and not a.optional:
        a.optional = budget["stack_optional"]["functions"]
    a.skip = window["skip_run"] if a.skip is None else a.skip
    a.count = window["count"] if a.count is None else a.count

    syms = symbols(a.elf)
    funcs = disassemble(a.elf, syms)
    graph = call_graph(funcs)
    isr_funcs = reachable(graph, ISR)
    mapfile = a.map or os.path.splitext(a.elf)[0] + ".map"
    values = {}
    ok = True

    # -- stack (static: every function the ISR can reach)
    su = su_frames(a.su_root)
    depth, path, problems = stack_depth(funcs, graph, su)
    print(f"ISR call graph: {len(isr_funcs)} functions reachable from {ISR}")
    print(f"ISR stack, static (every reachable path): {depth} bytes")
    for name, fr, src in path:
        print(f"  {fr:5d}  {name}  ({src})")
    for p in problems:
        print(f"stack: problem: {p}")
    if any(k in p for p in problems
           for k in ("indirect", "recursion", "not a sized", "dynamic", "bounded")):
        ok = False
    n_su = sum(1 for f in isr_funcs if f in su)
    print(f"  frames: {n_su} from .su files, {len(isr_funcs) - n_su} from prologues "
          f"(the C library's)")
    values["stack"] = {"static_bytes": depth, "static_path": [n for n, _, _ in path]}
    # without the calls into functions that run in the ISR only when
    # configured so (the budget file's stack_optional, with its reason)
    optional = set(a.optional)
    if optional:
        d_req, p_req = restricted_depth(
            funcs, graph, su, lambda c: c not in optional,
            f"ISR stack, static without the calls into {sorted(optional)}")
        values["stack"]["static_required_bytes"] = d_req
        values["stack"]["static_required_path"] = p_req

    # -- sizes
    img = image_size(a.elf)
    fw = firmware_size(mapfile)
    print(f"image: text {img['text']}, data {img['data']}, bss {img['bss']} "
          f"(RAM {img['data'] + img['bss']}, the 64 kB stack included)")
    print(f"firmware libraries in the image: text {fw['text']}, data {fw['data']}, "
          f"bss {fw['bss']}")
    values["size"] = {"image": img, "firmware": fw}

    # -- the meter's window: the two SysTick reads around the call, nothing
    # else (isr_meter.c), which is what the trace counts as the ISR
    w = funcs[WRAP]["insns"]
    k = next((i for i, (_, mn, ops) in enumerate(w)
              if mn.split(".")[0] == "bl" and ops.endswith(f"<{ISR}>")), None)
    if k is None or not 0 < k < len(w) - 1 or \
            not all(w[j][1].split(".")[0] == "ldr" for j in (k - 1, k + 1)) or \
            w[k - 1][2].split(",", 1)[1] != w[k + 1][2].split(",", 1)[1]:
        print(f"error: {WRAP} does not read SysTick right before and after its call")
        return 1

    # -- trace
    if not a.no_trace:
        indirect = [n for n in isr_funcs if graph[n]["indirect"]]
        if indirect:
            print(f"error: indirect calls in {indirect}: the trace would miss their targets")
            return 1
        # The C library routines the rest of the image also runs (the
        # plant's double arithmetic: ~90 % of the log) are left out of the
        # trace unless an ISR calls them: a call from an ISR into an
        # untraced function is seen (its target) and the trace is rerun
        # with that function.
        g_rest = {n: g for n, g in graph.items() if n not in (ISR, WRAP)}
        rest = reachable(g_rest, "main") | reachable(g_rest, "Reset_Handler")
        lib = toolchain_functions(mapfile)
        skipped = set() if a.trace_all else (isr_funcs & rest & lib) - ALWAYS_TRACED
        starts = sorted((f["start"], f["end"], n) for n, f in funcs.items())

        def name_at(x):
            return next((n for lo, hi, n in starts if lo <= x < hi), f"0x{x:x}")

        for attempt in (1, 2):
            names = (isr_funcs - skipped) | {WRAP, MARK}
            ranges = merge_ranges(funcs, names)
            t0 = time.monotonic()
            try:
                results, mnem, stats, entered, untraced, pcs, report = \
                    trace(a, a.elf, syms, ranges)
            except TraceError as e:
                print(f"error: {e}")
                return 1
            called = {name_at(x) for x in untraced}
            print(f"trace: {len(names)} functions in {len(ranges)} address ranges "
                  f"({len(skipped)} C library routines shared with the plant left out), "
                  f"{time.monotonic() - t0:.1f} s; " +
                  ", ".join(f"{k} {v}" for k, v in sorted(stats.items())))
            if not called:
                break
            print(f"trace: the ISRs called untraced {sorted(called)}: "
                  + ("tracing them too" if attempt == 1 else "error"))
            if attempt == 2 or not called <= skipped:
                return 1
            skipped -= called
        # -- the check: the estimate's instructions = the meter's, per ISR
        if len(report) != a.count or len(results) != a.count:
            print(f"error: {a.count} ISRs requested, the image reported {len(report)}, "
                  f"the trace has {len(results)}")
            return 1
        if [r[0] for r in report] != list(range(report[0][0], report[0][0] + a.count)):
            print("error: the reported ISRs are not consecutive")
            return 1
        bad = [(t, r) for t, r in zip(results, report) if t[0] != r[1]]
        print(f"instructions per ISR, trace against the SysTick meter: "
              f"{len(results) - len(bad)} of {len(results)} equal")
        if bad:
            for t, r in bad[:10]:
                print(f"error: ISR {r[0]} ({r[2]}): trace {t[0]}, meter {r[1]} "
                      f"({t[0] - r[1]:+d})")
            return 1
        rows = {"run": [], "run_fast": [], "run_slow": [], "other": []}
        slow_idx = []
        for t, r in zip(results, report):
            if r[2] in ("run_fast", "run_slow"):
                rows["run"].append(t)
                rows[r[2]].append(t)
                if r[2] == "run_slow":
                    slow_idx.append(r[0])
            else:
                rows["other"].append(t)
        print(f"window: ISRs {report[0][0]}..{report[-1][0]} (the {a.count} after "
              f"{a.skip} RUN ISRs)")
        if len(slow_idx) > 1:
            gaps = Counter(y - x for x, y in zip(slow_idx, slow_idx[1:]))
            print("outer-loop ticks (run_slow) every " +
                  ", ".join(f"{g} ({n}x)" for g, n in sorted(gaps.items())) + " ISRs")
        groups = {g: group_stats(r) for g, r in rows.items() if r}
        print_table(groups)
        print("most executed mnemonics: " +
              ", ".join(f"{m} {n}" for m, n in mnem.most_common(12)))
        if a.profile:
            print_profile(a.elf, pcs, len(results), a.profile)
        est = {"window": {"skip_run": a.skip, "count": a.count}}
        for g in ("run", "run_fast", "run_slow"):
            if g in groups:
                st = groups[g]
                est[g] = {"n": st["n"], "mean_instr": st["instr"]["mean"],
                          "max_instr": st["instr"]["max"],
                          "mean_cycles": st["cycles"]["mean"],
                          "max_cycles": st["cycles"]["max"], "cpi": st["cpi"]}
        values["estimate"] = est

        # -- stack along the code the ISRs ran (every ISR from the first
        # to the end of the window): the static graph restricted to the
        # functions entered
        ran = {name_at(x) for x in entered} | called
        d_ran, p_ran = restricted_depth(
            funcs, graph, su, lambda c: c in ran,
            f"ISR stack along the functions the ISRs ran ({len(ran)})")
        values["stack"]["ran_bytes"] = d_ran
        values["stack"]["ran_path"] = p_ran

    # -- the budget
    if entry:
        lines = []
        bs = entry["stack"]
        ok = compare("stack static_bytes", depth, bs["static_bytes"], tol, lines) and ok
        if "static_required_bytes" in values["stack"]:
            ok = compare("stack static_required_bytes",
                         values["stack"]["static_required_bytes"],
                         bs["static_required_bytes"], tol, lines) and ok
        if "estimate" in values:
            ok = compare("stack ran_bytes", values["stack"]["ran_bytes"],
                         bs["ran_bytes"], tol, lines) and ok
            be = entry["estimate"]
            for g in ("run", "run_fast", "run_slow"):
                if g not in be:
                    continue
                st = values["estimate"].get(g)
                if st is None:
                    lines.append(f"FAIL no {g} ISR in the window")
                    ok = False
                    continue
                for k in ("max_cycles", "mean_cycles"):
                    ok = compare(f"estimate {g} {k}", st[k], be[g][k], tol, lines) and ok
        for part in ("image", "firmware"):
            for k in ("text", "data", "bss"):
                compare(f"size {part} {k}", values["size"][part][k],
                        entry["size"][part][k], tol, lines, checked=False)
        print(f"budget ({a.budget}, {a.image}; limit +{tol * 100:g} %; reason of the "
              f"entry: {entry['reason']}):")
        for l in lines:
            print("  " + l)
    if a.json:
        print(json.dumps(values, indent=1))
    print(f"[{time.monotonic() - t_start:.1f} s wall]")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
