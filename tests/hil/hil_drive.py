"""HIL test of a drive over real SocketCAN (tests/hil).

The drive is node N on a CAN interface: with --drive sim (the default) the
harness starts `pmsm-sim run SCENARIO --can IF --can-node N --realtime`
itself; with --drive external it talks CAN only, to whatever is node N (a
board running the firmware, or a simulated drive started elsewhere), and
reads nothing from a simulator. From the drive's CAN telemetry it checks:
  1. speed tracking of a commanded ramp 0 -> 500 rpm and the scenario's
     1.5 N m load step against the same scenario in pure simulation (run
     first, same binary) plus an allowance from the commands' age;
  2. status telemetry at 1 kHz for >= 10 s without a lost, repeated or
     corrupted frame (E2E counter and CRC of every telemetry frame);
  3. the fast ISR's cost (Tlm_IsrCost: the firmware's HAL cycle counter,
     DWT cycles on an MCU) against the PWM period and the overrun counter
     (Tlm_Counters);
  4. COMM_TIMEOUT 100 ms after the last command, PWM off;
  5. >= 10,000 malformed frames of its node and 2 s of foreign frames at a
     saturated 1 Mbit/s bus's rate change nothing, are all counted, and a
     valid command still gets through.
The PWM period is read over CAN (parameter timing.f_pwm_Hz) and checked
against --period-us and the scenario's when given. With --drive sim the
simulator's JSON report adds the rejection totals by cause, the link
counters, the pacing and the drive's own fault record. With --drive
external the checks that need the simulator (the load step, the report's
figures; the pure simulation's bounds without --scenario) are listed as not
applicable, with the reason; with --scenario the tracking bounds hold only
if the scenario models the board's motor and load. The session ends by
itself 0.6 s of the drive's time after the last command (a simulated drive
ends with its run, duration_s); the external drive is then left disabled,
its telemetry rates back at the firmware's defaults.
The harness only records frames while the drive runs (raw AF_CAN socket,
no decoding) and checks everything afterwards: a TCG virtual machine is
slow. Scheduling is in the drive's time, read off the Tlm_Status stream
(1 frame per ms of ISRs, none lost), so that pacing errors of a simulated
drive do not stretch the profile; the JSON's realtime figures are reported.

usage: hil_drive.py --pmsm-sim PATH --scenario FILE --out DIR
                    [--channel vcan0] [--node 1] [--seed 1] [--period-us US]
       hil_drive.py --drive external --out DIR [--channel can0] [--node 1]
                    [--period-us US] [--scenario FILE --pmsm-sim PATH]
Exit status 0 when every applicable check passes, 1 otherwise (each failed
check is named), 2 on a setup error.
"""
import argparse
import csv
import errno
import json
import math
import os
import random
import select
import socket
import struct
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tools", "pmsm_can"))
from pmsm_can.protocol import TelemetryMonitor, e2e_crc, faults_text, param_id  # noqa: E402

RPM = math.pi / 30.0
FRAME = struct.Struct("=IB3x8s")
CAN_RTR_FLAG = 0x40000000
CAN_EFF_FLAG = 0x80000000
# message numbers
ENABLE, MODE, CURRENT, SPEED, POSITION, CLEAR, PREAD, PWRITE, CTRL, RATE = range(1, 11)
STATUS, CURRENTS, VOLTAGES, MOTION, ESTIMATES, REFS, COST, ERRORS, COUNTERS = range(16, 25)
RSP_PARAM, RSP_ERROR = 25, 26
DLC = {ENABLE: 1, MODE: 1, CURRENT: 8, SPEED: 4, POSITION: 4, CLEAR: 0, PREAD: 2,
       PWRITE: 7, CTRL: 1, RATE: 3}
STATE_IDLE, STATE_RUN, STATE_FAULT = 0, 2, 3
COMM_TIMEOUT_BIT = 1 << 15
ISR_OVERRUN_BIT = 1 << 4
PWM_PARAM = "timing.f_pwm_Hz"   # read over CAN: the PWM period, one fast ISR each
DEFAULT_STATUS_DEC = 1000       # the firmware's Tlm_Status rate before the harness sets it (ISRs)
FAST_HZ, SLOW_HZ = 1000, 100    # telemetry rates: status, motion, references; cost, errors, counters

# the profile (the drive's time, s, from the host's start of the ramp / of
# the 1 kHz status stream)
T_CMD = 0.010            # command period
LOAD_PHASE_RPM = 2.0  # dip vs the step's instant, pure simulation: 1.3 rpm, rounded up
RAMP_S, RAMP_RPM = 0.5, 500.0
T_BURST = 3.0            # malformed burst from here (the load is off at 2.5256 s)
N_MALFORMED = 10000
T_FLOOD = 4.5            # foreign frames from here, for FLOOD_S
FLOOD_S = 2.0
BATCH = 24              # frames sent per turn of the loop at most (the commands keep their period)
BUS_FRAMES_S = 9100      # a saturated 1 Mbit/s bus: 8-byte frames of 108 bits + 3 bits IFS, no stuffing
T_NEW_SPEED, NEW_RPM = 7.0, 300.0
T_LAST = 10.6            # the last command (>= 10 s of status at 1 kHz before it)
DURATION_EXTRA = 0.6     # the drive's time after the last command (the session's end)
CAN_TIMEOUT = 0.1        # the firmware's command timeout (mc_can_node default)
SILENT_S = 5.0           # host seconds without a frame of the drive: it has gone
NA = "not applicable with an external drive"


class Fail(Exception):
    pass


def ramp(t):
    return 0.0 if t <= 0 else RAMP_RPM * min(t / RAMP_S, 1.0)


def decimation(period, hz):
    """ISRs per telemetry frame for at least hz frames/s."""
    return max(1, int(1.0 / (period * hz) + 1e-6))


# ---------------------------------------------------------------------------
def pure_simulation(args, out):
    """The scenario without CAN, its own reference (the same ramp): the
    estimated speed every 1 ms."""
    csv_path = os.path.join(out, "sim.csv")
    json_path = os.path.join(out, "sim.json")
    r = subprocess.run([args.pmsm_sim, "run", args.scenario, "--quiet", "--csv", csv_path,
                        "--json", json_path, "--set", "output.trace_decimation=10"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise Fail(f"pure simulation failed ({r.returncode}): {r.stderr}")
    rep = json.load(open(json_path))
    t0 = rep["time_offset_s"]
    rows = []
    with open(csv_path) as f:
        for row in csv.DictReader(f):
            rows.append((float(row["t_s"]) - t0, float(row["omega_m_est_rad_s"]) / RPM,
                         float(row["tau_load_Nm"])))
    return rep, rows


def sim_metrics(rows, rep):
    """Max |ref - speed| in the ramp window (profile time 0 .. RAMP_S + 0.3)
    and over the hold with the load on and off (RAMP_S + 0.5 .. end)."""
    e_ramp = max(abs(ramp(t) - w) for t, w, _ in rows if 0.0 <= t <= RAMP_S + 0.3)
    e_load = max(abs(RAMP_RPM - w) for t, w, _ in rows if t >= RAMP_S + 0.5)
    loads = [t for (t, _, l), (_, _, l0) in zip(rows[1:], rows) if l != l0]
    return {"ramp_max_err_rpm": e_ramp, "load_max_err_rpm": e_load,
            "fluctuation_rpm": rep["metrics"]["fluctuation_rpm"],
            "load_changes_profile_s": [round(t, 4) for t in loads],
            "load_max_dip_rpm": rep["load_steps"][0]["max_dip_rpm"] if rep["load_steps"] else None,
            "period_us": rep["duration_s"] / rep["pwm_periods"] * 1e6}


# ---------------------------------------------------------------------------
class Link:
    def __init__(self, channel, node):
        self.base = node * 32
        self.s = socket.socket(socket.PF_CAN, socket.SOCK_RAW, socket.CAN_RAW)
        # the drive's frames only: our node's messages 16..31
        self.s.setsockopt(socket.SOL_CAN_RAW, socket.CAN_RAW_FILTER,
                          struct.pack("=II", self.base + 16, 0x7F0 | CAN_EFF_FLAG | CAN_RTR_FLAG))
        try:
            self.s.setsockopt(socket.SOL_SOCKET, 33, 64 << 20)  # SO_RCVBUFFORCE
        except OSError:
            self.s.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 64 << 20)
        self.s.setsockopt(socket.SOL_SOCKET, 40, 1)  # SO_RXQ_OVFL
        self.s.bind((channel,))
        self.s.setblocking(False)
        self.frames = []   # (host time, id, data)
        self.kernel_drops = 0
        self.send_retries = 0

    def send_raw(self, can_id, data, dlc=None):
        dlc = len(data) if dlc is None else dlc
        self.send_packed(FRAME.pack(can_id, dlc, bytes(data).ljust(8, b"\0")))

    def send_packed(self, frame):
        while True:
            try:
                self.s.send(frame)
                return
            except OSError as e:
                if e.errno not in (errno.ENOBUFS, errno.EAGAIN):
                    raise
                self.send_retries += 1
                select.select([], [], [], 0.0002)

    def send(self, msg, data):
        self.send_raw(self.base + msg, data)

    def drain(self):
        """Take what the socket holds; returns the frames taken."""
        new = []
        while True:
            try:
                b, anc, _, _ = self.s.recvmsg(16, 64)
            except BlockingIOError:
                break
            now = time.monotonic()
            for lvl, typ, val in anc:
                if lvl == socket.SOL_SOCKET and typ == 40 and len(val) >= 4:
                    self.kernel_drops = struct.unpack("=I", val[:4])[0]
            can_id, dlc, data = FRAME.unpack(b)
            new.append((now, can_id, data[:dlc]))
        self.frames.extend(new)
        return new


def speed_cmd(rpm):
    return struct.pack("<f", rpm * RPM)


def s24(b):
    v = b[0] | b[1] << 8 | b[2] << 16
    return v - (1 << 24) if v & 0x800000 else v


# ---------------------------------------------------------------------------
def malformed_frames(rng, n):
    """n frames of our node that the drive must reject, each with its cause:
    (message number, payload, dlc, rtr, cause)."""
    out = []
    unknown = [0, 11, 12, 13, 14, 15, 27, 28, 29, 30, 31]
    nan = struct.pack("<f", float("nan"))
    for _ in range(n):
        kind = rng.randrange(3)
        if kind == 0:  # unknown message, or a remote frame of a command
            if rng.randrange(4) == 0:
                m = rng.randrange(1, 11)
                out.append((m, b"", rng.randrange(9), True, "unknown_message"))
            else:
                d = rng.randrange(9)
                out.append((rng.choice(unknown), bytes(rng.randrange(256) for _ in range(d)), d,
                            False, "unknown_message"))
        elif kind == 1:  # a command with a wrong DLC
            m = rng.randrange(1, 11)
            d = rng.choice([x for x in range(9) if x != DLC[m]])
            out.append((m, bytes(rng.randrange(256) for _ in range(d)), d, False, "wrong_dlc"))
        else:  # right DLC, a value out of range or not finite
            m = rng.choice([MODE, CURRENT, SPEED, POSITION, CTRL, RATE])
            if m == MODE:
                p = bytes([rng.randrange(3, 256)])
            elif m == CTRL:
                p = bytes([rng.randrange(4, 256)])
            elif m == RATE:
                p = bytes([rng.choice(list(range(16)) + list(range(25, 256))),
                           rng.randrange(256), rng.randrange(256)])
            elif m == CURRENT:
                good = struct.pack("<f", rng.uniform(-5, 5))
                bad = rng.choice([nan, struct.pack("<f", rng.choice([-1, 1]) * rng.uniform(1001, 1e30)),
                                  struct.pack("<f", float("inf"))])
                p = good + bad if rng.randrange(2) else bad + good
            else:
                lim = 10000.0 if m == SPEED else 1e6
                p = rng.choice([nan, struct.pack("<f", float("-inf")),
                                struct.pack("<f", rng.choice([-1, 1]) * rng.uniform(lim * 1.01, 1e30))])
            out.append((m, p, len(p), False, "bad_value"))
    return out


def foreign_frame(rng, node):
    """A frame of another node (standard id with id >> 5 != node), or an
    extended one whose low 11 bits look like ours."""
    if rng.randrange(10) == 0:
        ident = (rng.randrange(1, 1 << 18) << 11 | node * 32 + rng.randrange(32)) | CAN_EFF_FLAG
    else:
        while True:
            ident = rng.randrange(0x800)
            if ident >> 5 != node:
                break
    d = rng.randrange(9)
    return ident, bytes(rng.randrange(256) for _ in range(d)), d


# ---------------------------------------------------------------------------
def rate(msg, dec):
    """Cmd_TelemetryRate payload: message msg every dec fast ISRs (0: off)."""
    return bytes([msg, dec & 0xFF, dec >> 8])


class Stream:
    """Frames packed beforehand, sent at a saturated bus's frame rate from
    the first pump, BATCH at most per pump (the commands keep their
    period)."""

    def __init__(self, packed):
        self.packed = packed
        self.sent = 0
        self.t0 = None      # host time of the first pump
        self.wall = None    # host seconds from it to the latest pump

    def done(self):
        return self.sent == len(self.packed)

    def pump(self, link, now):
        if self.t0 is None:
            self.t0 = now
        due = min(len(self.packed), int((now - self.t0) * BUS_FRAMES_S) + 1, self.sent + BATCH)
        while self.sent < due:
            link.send_packed(self.packed[self.sent])
            self.sent += 1
        self.wall = now - self.t0


class Session:
    """The live part: commands on the drive's time (Tlm_Status frames
    counted at 1 kHz), frames recorded with their host time."""

    def __init__(self, args, link, rng, drive):
        self.a, self.link, self.rng, self.drive = args, link, rng, drive
        self.period = None       # the PWM period read over CAN, s
        self.dec_fast = None     # ISRs per frame at 1 kHz
        self.start_state = None  # the drive's state when the harness found it
        self.fast = False        # the 1 kHz status stream has started
        self.n_status = 0        # its frames so far
        self.n_slow = 0          # status frames before it (one per 0.1 s)
        self.n_after_last = 0    # status frames after the last command (one per ISR)
        self.last_sent = False
        self.run_seen = False
        self.ramp_start = None   # host's clock of the drive's time at the ramp start
        self.cmds = []           # (host clock S, host time, rpm) of every Cmd_Speed
        self.events = {}
        self.last_rx = time.monotonic()
        self.deadline = None
        malformed = malformed_frames(rng, N_MALFORMED)
        self.expected = {}
        for *_, cause in malformed:
            self.expected[cause] = self.expected.get(cause, 0) + 1
        # everything packed before the session (a TCG VM is slow)
        self.burst = Stream([
            FRAME.pack((link.base + m) | (CAN_RTR_FLAG if rtr else 0), dlc, p.ljust(8, b"\0"))
            for m, p, dlc, rtr, _ in malformed])
        foreign = [foreign_frame(rng, args.node) for _ in range(int(FLOOD_S * BUS_FRAMES_S) + 1)]
        self.flood = Stream([FRAME.pack(ident, dlc, p.ljust(8, b"\0")) for ident, p, dlc in foreign])
        self.lag = {}            # phase -> max (host time - drive time) growth, s
        self.lag0 = None

    def clock(self):
        return self.n_status * self.dec_fast * self.period

    def phase(self):
        S = self.clock()
        for name, end in (("ramp_load", T_BURST), ("burst", T_FLOOD), ("flood", T_FLOOD + FLOOD_S),
                          ("new_speed", T_LAST)):
            if S < end:
                return name
        return "timeout"

    def on_frames(self, frames):
        for t, ident, data in frames:
            if ident == self.link.base + REFS and not self.fast:
                self.fast = True
                self.events["fast_stream_host_t"] = t
                # the drive's time then: its status every DEFAULT_STATUS_DEC ISRs so far
                self.events["fast_stream_start_S"] = max(0, self.n_slow - 1) * DEFAULT_STATUS_DEC * self.period
                # a simulated drive's load step is in its scenario's time: the profile must start with it
                if self.drive.scenario_time and self.n_slow > 5:
                    raise Fail(f"the 1 kHz stream started late: {self.n_slow} status frames at 0.1 s before it")
            elif ident == self.link.base + STATUS and not self.fast:
                self.n_slow += 1
            elif ident == self.link.base + STATUS and self.fast:
                self.n_status += 1
                if self.last_sent:
                    self.n_after_last += 1
                lag = t - self.clock()
                if self.lag0 is None:
                    self.lag0 = lag
                ph = self.phase()
                self.lag[ph] = max(self.lag.get(ph, 0.0), lag - self.lag0)
                if not self.run_seen and len(data) == 8 and (data[1] >> 4) == STATE_RUN:
                    self.run_seen = True

    def receive(self):
        frames = self.link.drain()
        if frames:
            self.last_rx = frames[-1][0]
        self.on_frames(frames)
        return frames

    def await_frame(self, match, timeout_s, what):
        """Record until a frame (host time, id, data) that match accepts."""
        end = time.monotonic() + timeout_s
        while True:
            for f in self.receive():
                if match(f):
                    return f
            gone = self.drive.ended()
            if gone:
                raise Fail(f"{gone} before {what}")
            if time.monotonic() > end:
                raise Fail(f"no {what} within {timeout_s:g} s")
            select.select([self.link.s], [], [], 0.05)

    def is_msg(self, msg):
        return lambda f: f[1] == self.link.base + msg

    def speed(self, rpm, now):
        self.link.send(SPEED, speed_cmd(rpm))
        self.cmds.append((self.clock(), now, rpm))

    # --- before the profile
    def to_idle(self, status):
        """A drive found running or in FAULT (a board after an earlier
        session): Enable 0 and ClearFaults, then its status must say IDLE."""
        self.start_state = status[1] >> 4 if len(status) == 8 else None
        if self.start_state == STATE_IDLE:
            return
        self.link.send(ENABLE, b"\x00")
        self.link.send(CLEAR, b"")
        idle = self.is_msg(STATUS)
        self.await_frame(lambda f: idle(f) and len(f[2]) == 8 and f[2][1] >> 4 == STATE_IDLE, 2.0,
                         f"Tlm_Status IDLE after Enable 0 and ClearFaults (found in state {self.start_state})")

    def read_period(self):
        """The PWM period from the drive's configuration (Cmd_ParamRead)."""
        key = struct.pack("<H", param_id(PWM_PARAM))
        self.link.send(PREAD, key)
        reply = self.is_msg(RSP_PARAM)
        d = self.await_frame(lambda f: reply(f) and f[2][:2] == key, 2.0, f"Rsp_Param of {PWM_PARAM}")[2]
        if len(d) != 8 or d[2] != 0 or d[3] != 0:
            raise Fail(f"Rsp_Param of {PWM_PARAM}: {d.hex()} (expected type 0 f32, status 0 ok)")
        f_pwm = struct.unpack("<f", d[4:8])[0]
        if not (math.isfinite(f_pwm) and f_pwm >= FAST_HZ):
            raise Fail(f"{PWM_PARAM} = {f_pwm}: the profile needs a PWM frequency of at least {FAST_HZ} Hz")
        return 1.0 / f_pwm

    def start(self):
        """Find the drive, bring it to IDLE, read its PWM period, set the
        telemetry rates and enable it in speed mode at 0 rpm."""
        L = self.link
        self.deadline = time.monotonic() + 180
        # (a drive started by a script may wait for this line)
        print(f"hil: listening on {self.a.channel} for node {self.a.node}", flush=True)
        status = self.await_frame(self.is_msg(STATUS), 60, "Tlm_Status from the drive")
        self.to_idle(status[2])
        self.period = self.read_period()
        self.dec_fast = decimation(self.period, FAST_HZ)
        slow = decimation(self.period, SLOW_HZ)
        # telemetry: status, motion, references at 1 kHz; cost, errors, counters at 100 Hz
        for m, dec in ((STATUS, self.dec_fast), (REFS, self.dec_fast), (MOTION, self.dec_fast),
                       (COST, slow), (ERRORS, slow), (COUNTERS, slow)):
            L.send(RATE, rate(m, dec))
        L.send(MODE, b"\x01")
        self.speed(0.0, time.monotonic())
        L.send(ENABLE, b"\x01")
        self.events["enable_host_t"] = time.monotonic()

    # --- the profile
    def profile_rpm(self, S):
        if self.ramp_start is None:
            return 0.0
        return ramp(S - self.ramp_start) if S < T_NEW_SPEED else NEW_RPM

    def last_command(self, S):
        """The status at every ISR from shortly before the last command (its
        frames count the ISRs), and the last command: a marker seen in the
        telemetry of the very poll that takes it, Tlm_Estimates on, every
        ISR. The host's time first: the drive may answer before send
        returns."""
        if S >= T_LAST - 0.05 and "status_every_isr_host_t" not in self.events:
            self.events["status_every_isr_host_t"] = time.monotonic()
            self.link.send(RATE, rate(STATUS, 1))
        if S >= T_LAST:
            self.events["last_cmd_host_t"] = time.monotonic()
            self.link.send(RATE, rate(ESTIMATES, 1))
            self.events["last_cmd_S"] = S
            self.last_sent = True

    def pump_frames(self, S, now):
        """The malformed burst, then 100 % bus load of foreign frames, each at
        the bus's frame rate."""
        if S >= T_BURST and not self.burst.done():
            if self.burst.t0 is None:
                self.events["burst_S"] = S
            self.burst.pump(self.link, now)
            if self.burst.done():
                self.events["burst_wall_s"] = self.burst.wall
        if T_FLOOD <= S < T_NEW_SPEED - 0.3 and not self.flood.done():
            if self.flood.t0 is None:
                self.events["flood_S"] = S
            self.flood.pump(self.link, now)
            self.events["flood_wall_s"] = self.flood.wall

    def run(self):
        self.start()
        last_cmd = time.monotonic()
        last_cmd_S = 0.0
        while not self.drive.session_over(self):
            select.select([self.link.s], [], [], 0.0005)
            self.receive()
            now = time.monotonic()
            if now > self.deadline:
                raise Fail("the session took over 3 minutes")
            if now - self.last_rx > SILENT_S:
                raise Fail(f"no frame from the drive for {SILENT_S:g} s")
            if self.last_sent:
                continue
            S = self.clock()
            if self.run_seen and self.ramp_start is None:
                self.ramp_start = S
                self.events["ramp_start_S"] = S
            self.last_command(S)
            if self.last_sent:
                continue
            if S - last_cmd_S >= T_CMD or now - last_cmd >= T_CMD:
                last_cmd, last_cmd_S = now, S
                self.speed(self.profile_rpm(S), now)
            self.pump_frames(S, now)
        self.receive()


# ---------------------------------------------------------------------------
class SimDrive:
    """--drive sim: `pmsm-sim run SCENARIO --can --realtime`, started here;
    the session lasts its run (duration_s), its JSON report is read at the
    end."""
    scenario_time = True   # the profile lines up with the scenario's time (its load step)

    def __init__(self, a):
        self.json = os.path.join(a.out, "hil.json")
        self.err = os.path.join(a.out, "pmsm-sim.stderr")
        duration = T_LAST + DURATION_EXTRA + 0.5
        self.cmd = [a.pmsm_sim, "run", a.scenario, "--can", a.channel, "--can-node", str(a.node),
                    "--realtime", "--quiet", "--set", f"duration_s={duration}", "--json", self.json]
        self.proc = None

    def start(self):
        with open(self.err, "w") as err:
            self.proc = subprocess.Popen(self.cmd, stdout=subprocess.DEVNULL, stderr=err)

    def ended(self):
        rc = self.proc.poll()
        return None if rc is None else f"pmsm-sim ended ({rc})"

    def session_over(self, sess):
        return self.proc.poll() is not None

    def finish(self):
        rc = self.proc.wait(timeout=60)
        if rc != 0:
            with open(self.err) as f:
                raise Fail(f"pmsm-sim --can ended with {rc}: {f.read()}")
        with open(self.json) as f:
            return json.load(f)

    def close(self, link):
        if self.proc is not None and self.proc.poll() is None:
            self.proc.kill()


class ExternalDrive:
    """--drive external: whatever is the node on the channel, CAN only. The
    session ends DURATION_EXTRA of the drive's time (its status frames, one
    per ISR then) after the last command; the drive is left disabled, its
    telemetry rates back at the firmware's defaults."""
    scenario_time = False

    def start(self):
        pass

    def ended(self):
        return None  # a drive that stops sending: SILENT_S

    def session_over(self, sess):
        return sess.n_after_last * sess.period >= DURATION_EXTRA

    def finish(self):
        return None

    def close(self, link):
        try:
            link.send(ENABLE, b"\x00")
            for m in range(STATUS, COUNTERS + 1):
                link.send(RATE, rate(m, DEFAULT_STATUS_DEC if m == STATUS else 0))
        except OSError as e:
            print(f"hil: could not leave the drive disabled at its default telemetry rates: {e}",
                  file=sys.stderr)


# ---------------------------------------------------------------------------
def write_log(path, channel, frames):
    """The frames received, candump -L style (host monotonic time)."""
    with open(path, "w") as f:
        for t, ident, data in frames:
            name = f"{ident & 0x1FFFFFFF:08X}" if ident & CAN_EFF_FLAG else f"{ident & 0x7FF:03X}"
            f.write(f"({t:.6f}) {channel} {name}#{data.hex().upper()}\n")


def le(d, k, n):
    """Unsigned little-endian integer of n bytes from d[k]."""
    return int.from_bytes(bytes(d[k:k + n]), "little")


def omega(p):
    d = p.get(MOTION)
    return s24(d[2:5]) * 0.001 / RPM if d else None


def oref(p):
    d = p.get(REFS)
    return s24(d[2:5]) * 0.001 / RPM if d else None


class Analysis:
    """The checks, from the frames recorded; with --drive sim also from the
    simulator's JSON report rep (None with an external drive). simm: the
    pure simulation's figures (None without --scenario)."""

    def __init__(self, sess, link, rep, simm, checks, fig):
        self.sess, self.link, self.rep, self.simm = sess, link, rep, simm
        self.checks, self.fig = checks, fig
        self.external = rep is None
        self.base = link.base
        self.period = sess.period
        self.dt = sess.dec_fast * sess.period   # between two 1 kHz polls

    def check(self, name, ok, detail):
        self.checks.append((name, ok, detail))

    def na(self, name, reason):
        self.checks.append((name, None, f"{NA}: {reason}"))

    def sim_only(self, name, reason, ok_detail):
        """A check on the simulator's JSON report: ok_detail() -> (ok,
        detail); with an external drive not applicable, for reason."""
        if self.external:
            self.na(name, reason)
        else:
            self.check(name, *ok_detail())

    def against_sim(self, name, figure, ok_detail):
        """A bound from the pure simulation: ok_detail() -> (ok, detail).
        Without --scenario not applicable, the figure reported only; with an
        external drive the bound holds only where the scenario models it."""
        if self.simm is None:
            self.na(name, f"no --scenario, so no pure simulation to bound it; {figure} (reported only)")
            return
        if self.external:
            name += " [external drive: holds only if the scenario models the board's motor and load]"
        self.check(name, *ok_detail())

    def S(self, i):  # the drive's time of 1 kHz poll i from the first
        return i * self.dt

    def run(self):
        write_log(os.path.join(self.sess.a.out, "received.log"), self.sess.a.channel, self.link.frames)
        with open(os.path.join(self.sess.a.out, "commands.json"), "w") as f:
            json.dump({"speed_commands": self.sess.cmds, "events": self.sess.events}, f)
        self.pwm_period()
        self.e2e()
        self.split_polls()
        self.tracking()
        self.isr()
        self.burst_and_flood()
        self.comm_timeout()

    # --- the PWM period read over CAN against the other sources
    def pwm_period(self):
        refs = []
        if self.sess.a.period_us is not None:
            refs.append(("--period-us", self.sess.a.period_us * 1e-6))
        if self.simm is not None:
            refs.append(("the scenario's", self.simm["period_us"] * 1e-6))
        self.fig["pwm_period_us"] = round(self.period * 1e6, 4)
        name = f"PWM period read over CAN ({PWM_PARAM})"
        got = f"{1.0 / self.period:g} Hz = {self.period * 1e6:g} us"
        if not refs:
            self.na(name + " = --period-us", f"{got}; no --period-us or --scenario to compare it with")
            return
        self.check(name + " = " + " = ".join(n for n, _ in refs),
                   all(abs(p - self.period) <= 1e-6 * self.period for _, p in refs),
                   got + "; " + ", ".join(f"{n} {p * 1e6:g} us" for n, p in refs))

    # --- 2. E2E of every telemetry frame (the tool's monitor; a table CRC
    # checked against the tool's on the first frames)
    def e2e(self):
        mon = TelemetryMonitor()
        table = []
        for i in range(256):
            c = i
            for _ in range(8):
                c = ((c << 1) ^ 0x1D) & 0xFF if c & 0x80 else (c << 1) & 0xFF
            table.append(c)

        def crc(ident, data):
            c = 0xFF
            for b in (ident & 0xFF, ident >> 8 & 0xFF, *data[1:8]):
                c = table[c ^ b]
            return c ^ 0xFF

        names = {self.base + m: m for m in range(16, 25)}
        for i, (_, ident, data) in enumerate(self.link.frames):
            m = names.get(ident)
            if m is None:
                continue
            if i < 300 and crc(ident, data) != e2e_crc(ident, data):
                raise Fail("the harness's CRC table disagrees with pmsm_can.protocol.e2e_crc")
            ok = len(data) == 8 and crc(ident, data) == data[0]
            mon.update(m, (ok, data[1] & 0x0F if data else 0))
        fig = self.fig
        fig["telemetry_frames_checked"] = mon.received
        fig["telemetry_lost"], fig["telemetry_repeated"], fig["telemetry_corrupted"] = \
            mon.lost, mon.repeated, mon.corrupted
        fig["host_socket_kernel_drops"] = self.link.kernel_drops
        self.check("telemetry: no frame lost, repeated or corrupted (E2E counter + CRC-8)",
                   mon.lost == 0 and mon.repeated == 0 and mon.corrupted == 0 and self.link.kernel_drops == 0,
                   f"{mon.received} frames, lost {mon.lost}, repeated {mon.repeated}, corrupted "
                   f"{mon.corrupted}, host socket drops {self.link.kernel_drops}")

    # --- the polls: each Tlm_Status frame opens one (the node sends 16..24
    # in order); 1 kHz from the first Tlm_References frame, every ISR after
    # the last command
    def split_polls(self):
        polls = []  # dicts: t, status bytes, motion, refs, cost, errors, counters
        fast = False
        for t, ident, data in self.link.frames:
            m = ident - self.base
            if not STATUS <= m <= COUNTERS:
                continue
            if m == REFS and not fast:
                fast = True
                if polls:
                    polls = polls[-1:]  # the poll that carried this first References frame
            if m == STATUS:
                polls.append({"t": t, "st": data})
            elif polls:
                polls[-1][m] = data
        if not fast or len(polls) < 100:
            raise Fail(f"no 1 kHz telemetry ({len(polls)} status frames)")
        # the 1 kHz part: until the first status without Tlm_References, which
        # only the switch to a status every ISR sends (References stays at 1 kHz,
        # due with the status it was sent with; a status that carries it is
        # a 1 kHz one whatever the status rate)
        n_fast = next((i for i, p in enumerate(polls) if REFS not in p), len(polls))
        self.polls, self.fast_polls, self.every_isr = polls, polls[:n_fast], polls[n_fast:]
        span = n_fast * self.dt
        span_wall = self.fast_polls[-1]["t"] - self.fast_polls[0]["t"]
        fig = self.fig
        fig["status_frames_1kHz"] = n_fast
        fig["status_1kHz_sim_span_s"] = round(span, 4)
        fig["status_rate_host_Hz"] = round((n_fast - 1) / span_wall, 1) if span_wall > 0 else None
        self.check("status telemetry at >= 1 kHz for >= 10 s (the drive's time: its ISRs)",
                   span >= 10.0, f"{n_fast} Tlm_Status frames at 1 per {self.sess.dec_fast} ISRs = {span:.3f} s; "
                   f"on the host {fig['status_rate_host_Hz']} frames/s over {span_wall:.3f} s wall")

    # --- 1. tracking
    def command_age(self, r0):
        """The age of the command in force: for each ramp command, the poll at
        which Omega_ref showed it; a command k is in force until k+1 shows.
        Returns (max age + the telemetry's resolution, latencies)."""
        first_seen = {}
        for i, p in enumerate(self.fast_polls):
            v = oref(p)
            if v is not None:
                first_seen.setdefault(round(v * RPM, 3), i)
        applied = []
        for c_S, _, rpm in self.sess.cmds:
            if c_S >= r0 and c_S < T_NEW_SPEED and 0 < rpm < RAMP_RPM:
                i = first_seen.get(round(rpm * RPM, 3))
                if i is None:  # quantisation: one step either way
                    i = first_seen.get(round(rpm * RPM, 3) + 0.001, first_seen.get(round(rpm * RPM, 3) - 0.001))
                if i is not None and (not applied or self.S(i) > applied[-1][1]):
                    applied.append((c_S, self.S(i)))
        if len(applied) < 10:
            raise Fail(f"only {len(applied)} ramp commands seen in Omega_ref")
        ages = [applied[k + 1][1] - applied[k][0] for k in range(len(applied) - 1)]
        return max(ages) + self.dt, [a - c for c, a in applied]

    def max_err(self, ref, t0, t1):
        """Max |ref - speed| over the 1 kHz polls from t0 to t1 (profile time)."""
        return max(abs(ref - omega(p)) for i, p in enumerate(self.fast_polls)
                   if t0 <= self.S(i) < t1 and omega(p) is not None)

    def tracking(self):
        r0 = self.sess.ramp_start
        if r0 is None:
            raise Fail("the drive never reached RUN")
        simm, fig = self.simm, self.fig
        age_max, lat = self.command_age(r0)
        slope = RAMP_RPM / RAMP_S
        allowance = slope * age_max
        fig["cmd_latency_sim_ms"] = {"min": round(min(lat) * 1e3, 2), "max": round(max(lat) * 1e3, 2),
                                     "mean": round(sum(lat) / len(lat) * 1e3, 2)}
        fig["cmd_age_max_sim_ms"] = round(age_max * 1e3, 2)
        cmd_iv = [b[1] - a[1] for a, b in zip(self.sess.cmds, self.sess.cmds[1:]) if r0 <= a[0] < T_BURST]
        fig["cmd_interval_host_ms"] = {"max": round(max(cmd_iv) * 1e3, 2),
                                       "mean": round(sum(cmd_iv) / len(cmd_iv) * 1e3, 2)}
        e_ramp = max(abs(ramp(self.S(i) - r0) - omega(p)) for i, p in enumerate(self.fast_polls)
                     if 0 <= self.S(i) - r0 <= RAMP_S + 0.3 and omega(p) is not None)
        fig["ramp_max_err_rpm"] = {"hil": round(e_ramp, 2)}

        def ramp_bound():
            bound = simm["ramp_max_err_rpm"] + allowance
            fig["ramp_max_err_rpm"].update(pure_sim=round(simm["ramp_max_err_rpm"], 2),
                                           allowance=round(allowance, 2), bound=round(bound, 2))
            return e_ramp <= bound, (
                f"max |ref - speed| {e_ramp:.2f} rpm <= {simm['ramp_max_err_rpm']:.2f} (pure simulation) + "
                f"{slope:.0f} rpm/s x {age_max * 1e3:.2f} ms = {bound:.2f} rpm")

        self.against_sim("ramp 0 -> 500 rpm tracked within the pure simulation's error + slope x command age",
                         f"max |ref - speed| {e_ramp:.2f} rpm", ramp_bound)
        self.check("command age within two command periods (the allowance stays small)",
                   age_max <= 2 * T_CMD, f"{age_max * 1e3:.2f} ms")
        # the hold with the load step on and off
        e_load = self.max_err(RAMP_RPM, r0 + RAMP_S + 0.5, T_BURST)
        fig["load_max_err_rpm"] = {"hil": round(e_load, 2)}

        def load_bound():
            # allowance: the load meets the speed ripple at another phase over CAN
            # (its peak-to-peak, 2 x the steady fluctuation), and the dip depends on
            # the rotor angle at the step (cogging, sensor harmonics): 1.3 rpm over
            # 0..11 ms shifts of the step in pure simulation of this scenario
            # (measured natively), taken as LOAD_PHASE_RPM
            bound = simm["load_max_err_rpm"] + 2 * simm["fluctuation_rpm"] + LOAD_PHASE_RPM
            fig["load_max_err_rpm"].update(pure_sim=round(simm["load_max_err_rpm"], 2),
                                           allowance=round(2 * simm["fluctuation_rpm"] + LOAD_PHASE_RPM, 2),
                                           bound=round(bound, 2))
            return e_load <= bound and e_load >= 0.5 * simm["load_max_err_rpm"], (
                f"max |500 rpm - speed| {e_load:.2f} rpm <= {simm['load_max_err_rpm']:.2f} + "
                f"2 x {simm['fluctuation_rpm']:.2f} (its steady fluctuation: the load meets the "
                f"cogging ripple at another phase) + {LOAD_PHASE_RPM} (the step's angle) = "
                f"{bound:.2f} (and >= half of it: the load acted)")

        self.sim_only("1.5 N m load on/off at 500 rpm within the pure simulation's error + its ripple",
                      f"the load step is the simulator's (the scenario's, in its own time); max |500 rpm - speed| "
                      f"over the hold {e_load:.2f} rpm (reported only)", load_bound)

    # --- 3. ISR cost and overruns
    def isr(self):
        polls, rep, fig = self.polls, self.rep, self.fig
        costs = [p[COST] for p in polls if COST in p]
        cnts = [p[COUNTERS] for p in polls if COUNTERS in p]
        if not costs or not cnts:
            raise Fail(f"Tlm_IsrCost frames {len(costs)}, Tlm_Counters frames {len(cnts)}")
        cost_max = max(le(d, 4, 2) for d in costs) * 0.01
        cost_avg_max = max(le(d, 6, 2) for d in costs) * 0.01
        # over the session (a board counts from its reset)
        overruns = (le(cnts[-1], 2, 3) - le(cnts[0], 2, 3)) % (1 << 24)
        budget_us = self.period * 1e6
        fig["isr_cost_us"] = {"max": cost_max, "worst_10ms_mean": cost_avg_max, "budget": budget_us}
        if rep is not None:
            fig["isr_cost_us"].update(report_mean=round(rep["isr_cost"]["mean_s"] * 1e6, 3),
                                      report_max=round(rep["isr_cost"]["max_s"] * 1e6, 2))
        fig["isr_overruns"] = overruns
        fig["isr_overruns_since_start"] = le(cnts[-1], 2, 3)
        self.check("ISR cost max below the PWM period, no overrun",
                   cost_max < budget_us and overruns == 0,
                   f"Cost_max {cost_max:.2f} us < {budget_us:g} us, isr_overruns {overruns}")
        flagged = sum(1 for p in polls if le(p["st"], 3, 2) & ISR_OVERRUN_BIT)
        detail = f"isr_overrun latched in {flagged} of {len(polls)} Tlm_Status frames"
        ok = flagged == 0
        if rep is not None:
            ok = ok and not rep["faults"]["latched_bits"] & ISR_OVERRUN_BIT
            detail += f"; the report's latched {rep['faults']['latched']}"
        self.check("no isr_overrun fault", ok, detail)

    # --- 5. malformed burst and foreign load
    def burst_and_flood(self):
        sess, rep, fig = self.sess, self.rep, self.fig
        exp = {k: sess.expected.get(k, 0) for k in ("unknown_message", "wrong_dlc", "bad_value", "refused_state")}
        fig["malformed_sent"] = sess.burst.sent
        fig["malformed_expected_by_cause"] = {k: v for k, v in sess.expected.items() if v}
        fig["foreign_sent"] = sess.flood.sent
        fig["burst_wall_s"] = round(sess.events.get("burst_wall_s", float("nan")), 3)
        fw = sess.events.get("flood_wall_s", float("nan"))
        fig["foreign_rate_frames_s"] = round(sess.flood.sent / fw) if fw > 0 else None
        fig["malformed_rate_frames_s"] = round(sess.burst.sent / sess.events["burst_wall_s"]) \
            if sess.events.get("burst_wall_s") else None
        self.check("foreign frames for >= 2 s at a saturated 1 Mbit/s bus's rate (>= 9000 frames/s)",
                   sess.flood.sent >= int(FLOOD_S * BUS_FRAMES_S) and (fig["foreign_rate_frames_s"] or 0) >= 9000,
                   f"{sess.flood.sent} frames in {fw:.3f} s wall = {fig['foreign_rate_frames_s']} frames/s")

        def by_cause():
            rej = rep["can"]["node"]["rejected"]
            fig["rejected_report"] = rej
            exp_all = {k: sess.expected.get(k, 0) for k in rej}
            return sess.burst.sent >= 10000 and rej == exp_all, \
                f"sent {sess.burst.sent}, expected {exp_all}, counted {rej}"

        self.sim_only("every malformed frame counted by its cause (JSON report)",
                      "the totals by cause are the simulator's JSON report (Tlm_Errors mod 256 and one "
                      "Rsp_Error per frame stand for them)", by_cause)
        self.errors_and_replies(exp)
        self.sim_only("the drive's link lost nothing (kernel buffer, tx), no bus error",
                      "the link counters are the simulator's JSON report (Tlm_Errors' overrun and tx drop, "
                      "Tlm_Counters' bus errors stand for them)", self.link_report)
        self.sim_only("foreign frames never reach the node; its frames all counted",
                      "the node's frame totals are the simulator's JSON report (no state change and the "
                      "Tlm_Errors counts stand for them)", self.node_report)
        self.no_state_change()
        self.new_speed()

    def errors_and_replies(self, exp):
        errs = [p[ERRORS] for p in self.polls if ERRORS in p]
        cnts = [p[COUNTERS] for p in self.polls if COUNTERS in p]
        if not errs:
            raise Fail("no Tlm_Errors frame")
        # over the session, mod 256 (a board counts from its reset)
        delta = [(b - a) % 256 for a, b in zip(errs[0][2:8], errs[-1][2:8])]
        tlm_err = dict(zip(("unknown_message", "wrong_dlc", "bad_value", "refused_state"), delta))
        exp_mod = {k: v % 256 for k, v in exp.items()}
        bus_errors = (le(cnts[-1], 5, 3) - le(cnts[0], 5, 3)) % (1 << 24)
        self.fig["tlm_errors_session"] = dict(tlm_err, rx_overrun=delta[4], tx_drop=delta[5], bus_errors=bus_errors)
        self.check("Tlm_Errors counts = the expected ones mod 256, no overrun, no tx drop, no bus error "
                   "(Tlm_Counters)",
                   tlm_err == exp_mod and delta[4] == 0 and delta[5] == 0 and bus_errors == 0,
                   f"over the session: {self.fig['tlm_errors_session']}, expected {exp_mod}")
        rsp = sum(1 for _, ident, _ in self.link.frames if ident == self.base + RSP_ERROR)
        self.fig["rsp_error_received"] = rsp
        self.check("one Rsp_Error per malformed frame", rsp == self.sess.burst.sent, f"{rsp}")

    def link_report(self):
        link, node = self.rep["can"]["link"], self.rep["can"]["node"]
        return (link["rx_overflow_drops"] == 0 and link["tx_dropped"] == 0 and link["bus_errors"] == 0
                and node["tx_drops"] == 0), json.dumps(link)

    def node_report(self):
        node = self.rep["can"]["node"]
        rejected = sum(node["rejected"].values())
        return node["rx_frames"] == node["rx_accepted"] + rejected, (
            f"rx_frames {node['rx_frames']} = accepted {node['rx_accepted']} + rejected {rejected}"
            f" (foreign sent {self.sess.flood.sent})")

    def no_state_change(self):
        """State, mode, outputs, enabled, faults and controller as before the
        burst (RUN, speed, on, enabled, none), Omega_ref 500 rpm, until the new
        speed."""
        i0 = int(round(self.sess.events["burst_S"] / self.dt))
        seg = self.fast_polls[i0:int(T_NEW_SPEED / self.dt)]

        def state(p):
            st = p["st"]
            return st[1] >> 4, st[2] & 0xF, st[2] >> 4 & 1, st[2] >> 7, le(st, 3, 2), st[7]

        before = (STATE_RUN, 1, 1, 1, 0, self.fast_polls[i0 - 1]["st"][7])
        seen = {state(p) for p in seg}
        refs = [oref(p) for p in seg if oref(p) is not None]
        self.check("no state change through the burst and the flood (state, mode, outputs, enabled, faults, "
                   "controller, speed reference)",
                   seen == {before} and max(abs(r - RAMP_RPM) for r in refs) < 0.01,
                   f"{sorted(seen)}; Omega_ref {min(refs):.3f}..{max(refs):.3f} rpm over {len(seg)} polls")

    def new_speed(self):
        late_ref = [oref(p) for i, p in enumerate(self.fast_polls) if T_NEW_SPEED + 0.1 <= self.S(i) < T_LAST]
        self.check("a valid command after them gets through (Omega_ref = 300 rpm)",
                   max(abs(r - NEW_RPM) for r in late_ref) < 0.01,
                   f"Omega_ref {min(late_ref):.3f}..{max(late_ref):.3f} rpm over {len(late_ref)} polls")
        e_new = self.max_err(NEW_RPM, T_NEW_SPEED + 1.0, T_LAST)
        self.fig["new_speed_max_err_rpm"] = round(e_new, 2)
        over = f"over the last {(T_LAST - T_NEW_SPEED - 1.0):.1f} s"

        def bound():
            b = self.simm["fluctuation_rpm"] * 2 + 1.0
            return e_new <= b, (f"max |300 - speed| {e_new:.2f} rpm {over} <= {b:.2f} "
                                f"(twice the pure simulation's fluctuation + 1 rpm)")

        self.against_sim("the drive follows 300 rpm within twice the pure simulation's fluctuation + 1 rpm",
                         f"max |300 - speed| {e_new:.2f} rpm {over}", bound)

    # --- 4. command timeout: the status at every ISR around the last command
    def comm_timeout(self):
        every_isr, rep, fig = self.every_isr, self.rep, self.fig
        i_mark = next((i for i, p in enumerate(every_isr) if ESTIMATES in p), None)
        i_fault = next((i for i, p in enumerate(every_isr) if p["st"][1] >> 4 == STATE_FAULT), None)
        if i_mark is None or i_fault is None:
            raise Fail(f"last command seen: {i_mark is not None}, fault seen: {i_fault is not None}")
        pf = every_isr[i_fault]["st"]
        faults, first = le(pf, 3, 2), le(pf, 5, 2)
        outputs = {p["st"][2] >> 4 & 1 for p in every_isr[i_fault:]}
        # consecutive status frames (none lost: checked above) are consecutive ISRs
        d_isr = i_fault - i_mark
        drive_ms = d_isr * self.period * 1e3
        host_ms = (every_isr[i_fault]["t"] - self.sess.events["last_cmd_host_t"]) * 1e3
        # the drive's clock against the host's over those ISRs (a simulated
        # drive's pacing; a board's crystal)
        pace_ms = (every_isr[i_fault]["t"] - every_isr[i_mark]["t"]) * 1e3 - drive_ms
        latency_ms = host_ms - drive_ms - pace_ms
        fig["timeout_drive_isrs"] = d_isr
        fig["timeout_drive_ms"] = round(drive_ms, 2)
        fig["timeout_host_ms"] = round(host_ms, 2)
        fig["timeout_host_pacing_share_ms"] = round(pace_ms, 2)
        if rep is not None:
            fig["first_fault_sim_time_s"] = rep["faults"]["first_fault_sim_time_s"]
        # the node takes the last command in the poll after ISR k (its time stamp:
        # ISR k's), raises comm_lost in the first poll more than 100 ms later
        # (ISR k + 1001 at 10 kHz) and the next ISR latches the fault: its
        # telemetry, in the same poll, is the first with FAULT
        late = d_isr - 1 - CAN_TIMEOUT / self.period
        self.check("COMM_TIMEOUT detected within one period after 100 ms (drive's ISRs: raised at "
                   "k + 1001, latched by the next ISR)",
                   -1e-6 <= late <= 1 + 1e-6 and faults & COMM_TIMEOUT_BIT and first == COMM_TIMEOUT_BIT,
                   f"{d_isr} ISRs = {drive_ms:.1f} ms from the poll that took the last command "
                   f"to the first status with FAULT (detection {(d_isr - 1) * self.period * 1e3:.1f} ms); "
                   f"faults {faults:#06x}, first {first:#06x}")
        self.check("COMM_TIMEOUT seen on the host after the last command: host time = the drive's ISRs + its "
                   "clock's drift + at most 3 ms (send and receive latency)",
                   abs(latency_ms) <= 3.0,
                   f"{host_ms:.2f} ms = {drive_ms:.1f} ms of ISRs + {pace_ms:.2f} ms the drive's clock against "
                   f"the host's over them + {latency_ms:.2f} ms")

        def pacing():
            late_s = rep["realtime"]["max_late_s"] if rep["realtime"] else 0.0
            tol_ms = late_s * 1e3 + 2.0 + 1.0 + 2 * self.period * 1e3
            return abs(host_ms - CAN_TIMEOUT * 1e3) <= tol_ms, (
                f"{host_ms:.2f} ms (tolerance +-{tol_ms:.1f} ms: max lateness {late_s * 1e3:.2f} ms + "
                f"2 ms pacing lead + 1 ms host loop + 2 periods)")

        self.sim_only("COMM_TIMEOUT seen on the host 100 ms after the last command, within the pacing error",
                      f"the pacing figures are the simulator's JSON report (seen after {host_ms:.2f} ms; the "
                      f"check above bounds the host's view by the drive's ISRs)", pacing)
        self.check("PWM off after the fault (Outputs_on 0)", outputs == {0},
                   f"Outputs_on over {len(every_isr) - i_fault} frames after the fault: {sorted(outputs)}")
        last = self.polls[-1]["st"]
        self.check("final state fault, comm_timeout the first and only fault (the last Tlm_Status)",
                   last[1] >> 4 == STATE_FAULT and le(last, 3, 2) == COMM_TIMEOUT_BIT
                   and le(last, 5, 2) == COMM_TIMEOUT_BIT,
                   f"state {last[1] >> 4}, faults {faults_text(le(last, 3, 2))}, first {faults_text(le(last, 5, 2))}")
        self.sim_only("the drive's report: comm_timeout first, final state fault",
                      "the drive's fault record is the simulator's JSON report (the last Tlm_Status stands for it)",
                      lambda: (rep["faults"]["latched"][:1] == ["comm_timeout"]
                               and rep["faults"]["final_state"] == "fault", json.dumps(rep["faults"])))


def session_figures(sess, rep, fig):
    if rep is not None:
        fig["realtime"] = rep["realtime"]
        fig["pacing"] = "missed periods {missed_periods}, max late {max_late_s:.6f} s".format(**rep["realtime"])
        fig["hil_wall_s"] = round(rep["wall_time_s"], 2)
        fig["can_counts"] = rep["can"]
    fig["drive_start_state"] = sess.start_state
    fig["events"] = {k: round(v, 4) for k, v in sess.events.items() if k.endswith("_S") or k.endswith("_s")}
    fig["host_lag_growth_by_phase_ms"] = {k: round(v * 1e3, 2) for k, v in sess.lag.items()}
    fig["harness_cpu_s"] = round(time.process_time(), 2)


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--drive", choices=("sim", "external"), default="sim",
                    help="sim: start pmsm-sim --can --realtime here (default); external: CAN only, to the "
                    "drive that is --node on --channel (a board)")
    ap.add_argument("--pmsm-sim", help="the simulator: the drive with --drive sim, the pure simulation")
    ap.add_argument("--scenario", help="required with --drive sim; with --drive external: the tracking bounds "
                    "(they hold only if it models the board's motor and load)")
    ap.add_argument("--period-us", type=float,
                    help=f"the PWM period, checked against the one read over CAN ({PWM_PARAM})")
    ap.add_argument("--out", required=True)
    ap.add_argument("--channel", default="vcan0")
    ap.add_argument("--node", type=int, default=1)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    if a.drive == "sim" and not a.scenario:
        ap.error("--drive sim needs --scenario")
    if a.scenario and not a.pmsm_sim:
        ap.error("--scenario needs --pmsm-sim (its pure simulation)")
    return a


def report(checks, fig, out):
    with open(os.path.join(out, "hil_summary.json"), "w") as f:
        json.dump({"figures": fig, "checks": [{"name": n, "ok": None if ok is None else bool(ok), "detail": d}
                                              for n, ok, d in checks]}, f, indent=1)
    print(json.dumps(fig, indent=1))
    verdict = {True: "PASS", False: "FAIL", None: "N/A"}
    for n, ok, d in checks:
        print(f"{verdict[None if ok is None else bool(ok)]}: {n}: {d}")
    bad = sum(1 for _, ok, _ in checks if ok is not None and not ok)
    na = sum(1 for _, ok, _ in checks if ok is None)
    print(f"hil: {len(checks) - na - bad} of {len(checks) - na} checks passed"
          + (f", {na} not applicable (external drive)" if na else ""))
    return 1 if bad else 0


def main():
    a = parse_args()
    os.makedirs(a.out, exist_ok=True)
    checks, fig = [], {}
    t_start = time.monotonic()
    drive = ExternalDrive() if a.drive == "external" else SimDrive(a)
    try:
        simm = None
        if a.scenario:
            rep_sim, rows = pure_simulation(a, a.out)
            simm = sim_metrics(rows, rep_sim)
            fig["pure_sim"] = {k: (round(v, 3) if isinstance(v, float) else v) for k, v in simm.items()}
        try:
            link = Link(a.channel, a.node)
        except OSError as e:
            print(f"hil: cannot open {a.channel}: {e}", file=sys.stderr)
            return 2
        sess = Session(a, link, random.Random(a.seed), drive)  # its frames packed first: ~1 s in a VM
        drive.start()
        try:
            sess.run()
            rep = drive.finish()
        finally:
            drive.close(link)
        session_figures(sess, rep, fig)
        Analysis(sess, link, rep, simm, checks, fig).run()
    except Fail as e:
        checks.append(("the session ran", False, str(e)))
    fig["harness_wall_s"] = round(time.monotonic() - t_start, 2)
    return report(checks, fig, a.out)


if __name__ == "__main__":
    sys.exit(main())
