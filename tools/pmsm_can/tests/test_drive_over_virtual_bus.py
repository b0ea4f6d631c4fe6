"""The telemetry tool against the real firmware and simulator: the engine
(host_sim/pyengine, libpmsm_engine.so: scenario loader, plant, firmware
with its CAN node) loaded through ctypes and stepped by a bridge thread
that moves frames between it and a python-can virtual bus, paced to wall
time; the tool (pmsm_can) talks to the other end of that bus.

Environment (set by ctest): PMSM_ENGINE_LIB, PMSM_SCENARIOS_DIR."""
import ctypes
import math
import os
import threading
import time

import can
import pytest

from pmsm_can import cli
from pmsm_can.client import DriveClient
from pmsm_can.protocol import Protocol, param_id

LIB = os.environ.get("PMSM_ENGINE_LIB")
SCENARIOS = os.environ.get("PMSM_SCENARIOS_DIR")
pytestmark = pytest.mark.skipif(not LIB or not SCENARIOS,
                                reason="PMSM_ENGINE_LIB / PMSM_SCENARIOS_DIR not set (run through ctest)")

STEPS_PER_TICK = 10  # 1 ms of the 10 kHz drive per bridge iteration


class Engine:
    def __init__(self, scenario, node_id=0, timeout_s=0.1):
        lib = ctypes.CDLL(LIB)
        lib.pe_open.restype = ctypes.c_void_p
        lib.pe_open.argtypes = [ctypes.c_char_p, ctypes.POINTER(ctypes.c_char_p), ctypes.c_int,
                                ctypes.c_uint32, ctypes.c_double, ctypes.c_char_p, ctypes.c_int]
        lib.pe_step.argtypes = [ctypes.c_void_p, ctypes.c_int]
        lib.pe_time_s.restype = ctypes.c_double
        lib.pe_time_s.argtypes = [ctypes.c_void_p]
        lib.pe_speed_rad_s.restype = ctypes.c_double
        lib.pe_speed_rad_s.argtypes = [ctypes.c_void_p]
        lib.pe_deliver.argtypes = [ctypes.c_void_p, ctypes.c_uint32, ctypes.c_uint32,
                                   ctypes.c_char_p, ctypes.c_int]
        lib.pe_collect.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_uint32),
                                   ctypes.POINTER(ctypes.c_uint32), ctypes.c_char_p,
                                   ctypes.POINTER(ctypes.c_int)]
        lib.pe_close.argtypes = [ctypes.c_void_p]
        self.lib = lib
        err = ctypes.create_string_buffer(1024)
        path = os.path.join(SCENARIOS, scenario).encode()
        self.h = lib.pe_open(path, None, 0, node_id, timeout_s, err, len(err))
        if not self.h:
            raise RuntimeError(err.value.decode())

    def step(self, n):
        rc = self.lib.pe_step(self.h, n)
        if rc != 0:
            raise RuntimeError(f"engine step failed: {rc}")

    def time_s(self):
        return self.lib.pe_time_s(self.h)

    def speed(self):
        return self.lib.pe_speed_rad_s(self.h)

    def deliver(self, msg):
        flags = (1 if msg.is_extended_id else 0) | (2 if msg.is_remote_frame else 0)
        return self.lib.pe_deliver(self.h, msg.arbitration_id, msg.dlc, bytes(msg.data).ljust(8, b"\0"),
                                   flags)

    def collect(self):
        fid, dlc, flags = ctypes.c_uint32(), ctypes.c_uint32(), ctypes.c_int()
        buf = ctypes.create_string_buffer(8)
        if not self.lib.pe_collect(self.h, ctypes.byref(fid), ctypes.byref(dlc), buf, ctypes.byref(flags)):
            return None
        return can.Message(arbitration_id=fid.value, data=buf.raw[: dlc.value],
                           is_extended_id=bool(flags.value & 1), is_remote_frame=bool(flags.value & 2))

    def close(self):
        self.lib.pe_close(self.h)


class Bridge(threading.Thread):
    """Engine <-> virtual bus, paced: the simulated time never runs ahead of
    wall time. tamper: frame id -> list of actions for the next frames of
    that id ('drop' or 'corrupt')."""

    def __init__(self, engine, channel):
        super().__init__(daemon=True)
        self.engine = engine
        self.bus = can.Bus(interface="virtual", channel=channel, receive_own_messages=False)
        self.stop_flag = threading.Event()
        self.tamper = {}
        self.lock = threading.Lock()
        self.error = None

    def run(self):
        try:
            t0 = time.monotonic()
            sim0 = self.engine.time_s()
            while not self.stop_flag.is_set():
                while (msg := self.bus.recv(0)) is not None:
                    self.engine.deliver(msg)
                self.engine.step(STEPS_PER_TICK)
                while (out := self.engine.collect()) is not None:
                    with self.lock:
                        actions = self.tamper.get(out.arbitration_id)
                        action = actions.pop(0) if actions else None
                    if action == "drop":
                        continue
                    if action == "corrupt":
                        data = bytearray(out.data)
                        data[5] ^= 0x10
                        out.data = data
                    self.bus.send(out)
                ahead = (self.engine.time_s() - sim0) - (time.monotonic() - t0)
                if ahead > 0:
                    time.sleep(ahead)
        except Exception as e:  # reported by the test
            self.error = e

    def stop(self):
        self.stop_flag.set()
        self.join(5)
        self.bus.shutdown()


@pytest.fixture
def drive():
    engine = Engine("paper002_case1_foc.json")
    bridge = Bridge(engine, "pmsm-test")
    bridge.start()
    bus = can.Bus(interface="virtual", channel="pmsm-test", receive_own_messages=False)
    client = DriveClient(bus, 0)
    yield engine, bridge, client, bus
    bridge.stop()
    bus.shutdown()
    engine.close()
    assert bridge.error is None, bridge.error


def keep(client, seconds, send):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        send()
        t_next = time.monotonic() + 0.02
        while time.monotonic() < t_next:
            client.poll(0.005)


def test_parameter_enable_speed_and_timeout(drive):
    engine, bridge, client, _ = drive
    client.telemetry_rate("Tlm_Motion", 100)  # every 10 ms
    st = client.wait_for("Tlm_Status", 2.0)
    assert int(st["State"]) == 0  # IDLE
    # parameter write while stopped, through the firmware's validation
    assert client.param_set("foc_pi.speed_bandwidth_rad_s", 150.0) == ("f32", 150.0)
    assert client.param_get("foc_pi.speed_bandwidth_rad_s") == ("f32", 150.0)
    with pytest.raises(Exception):
        client.param_set("foc_pi.speed_bandwidth_rad_s", -5.0)  # invalid: rejected
    # speed command, streamed (feeds the 0.1 s command timeout); 0.6 s in
    # (wall time, so a loaded machine that sends less often still sends
    # it with time left for the answer), a parameter write, which the
    # running drive refuses (status 2)
    target = 20.0
    pid = param_id("foc_pi.speed_bandwidth_rad_s")
    t_write = time.monotonic() + 0.6
    sent = {"write": False}

    def send():
        client.mode("speed")
        client.speed(target)
        client.enable(True)
        if not sent["write"] and time.monotonic() >= t_write:
            client.send("Cmd_ParamWrite", {"Param_id": pid, "Param_type": 0, "Value_f32": 120.0})
            sent["write"] = True

    keep(client, 1.0, send)
    st = client.latest["Tlm_Status"][1]  # the last one received while streaming
    assert int(st["State"]) == 2, st  # RUN
    omega = client.latest["Tlm_Motion"][1]["Omega_m"]
    assert abs(omega - target) < 0.05 * target, omega
    assert abs(engine.speed() - target) < 0.05 * target
    refused = [r for r in client.replies if int(r["Param_id"]) == pid]
    assert refused and int(refused[-1]["Status"]) == 2, refused
    # silence: the command timeout latches COMM_TIMEOUT (bit 15)
    time.sleep(0.4)
    st = client.wait_for("Tlm_Status", 1.0, lambda s: int(s["State"]) == 3)
    assert int(st["Faults_latched"]) & (1 << 15)
    assert client.monitor.lost == 0 and client.monitor.corrupted == 0


@pytest.mark.parametrize("ext", [".log", ".blf", ".asc", ".csv"])
def test_log_formats_read_back(drive, tmp_path, ext):
    _, _, client, bus = drive
    client.telemetry_rate("Tlm_Motion", 50)
    path = str(tmp_path / ("telemetry" + ext))
    args = cli.build_parser().parse_args(["--interface", "virtual", "--channel", "pmsm-test",
                                          "log", path, "--duration", "0.5"])
    assert cli.run(args, bus=bus) == 0
    frames, monitor = cli.replay(path, Protocol(0))
    names = [n for _, n, _ in frames]
    assert names.count("Tlm_Motion") >= 20, names[:10]
    assert "Tlm_Status" in names
    assert monitor.lost == 0 and monitor.corrupted == 0, monitor.summary()
    # values read back as sent: the motor is at rest
    assert all(abs(s["Omega_m"]) < 1.0 for _, n, s in frames if n == "Tlm_Motion")


def test_dropped_and_corrupted_frames_detected(drive):
    _, bridge, client, _ = drive
    proto = Protocol(0)
    client.telemetry_rate("Tlm_Motion", 50)
    client.wait_for("Tlm_Motion", 1.0)
    client.wait_for("Tlm_Motion", 1.0)
    with bridge.lock:
        bridge.tamper[proto.frame_id("Tlm_Motion")] = ["drop", None, None, "corrupt"]
    end = time.monotonic() + 0.5
    while time.monotonic() < end:
        client.poll(0.02)
    assert client.monitor.lost == 1, client.monitor.summary()
    assert client.monitor.corrupted == 1, client.monitor.summary()
    assert client.monitor.repeated == 0


def test_cli_commands_and_replay_plot(drive, tmp_path, capsys):
    """The console commands a user types, on the same bus: status, rate,
    param get/set, log, and replay with a plot written to a PNG."""
    _, _, _, bus = drive
    parser = cli.build_parser()

    def run(*argv):
        return cli.run(parser.parse_args(["--interface", "virtual", "--channel", "pmsm-test", *argv]),
                       bus=bus)

    assert run("status", "--once") == 0
    assert "IDLE" in capsys.readouterr().out
    assert run("param", "set", "foc_pi.speed_bandwidth_rad_s", "140") == 0
    assert run("param", "get", "foc_pi.speed_bandwidth_rad_s") == 0
    assert "foc_pi.speed_bandwidth_rad_s = 140.0 (f32)" in capsys.readouterr().out
    assert run("rate", "Tlm_Currents", "20") == 0
    log = str(tmp_path / "run.blf")
    assert run("log", log, "--duration", "0.3") == 0
    png = str(tmp_path / "v_dc.png")
    assert cli.main(["replay", log, "--plot", "Tlm_Currents.V_dc", "--out", png]) == 0
    out = capsys.readouterr().out
    assert "Tlm_Currents" in out and "0 lost" in out
    assert os.path.getsize(png) > 1000
    frames, _ = cli.replay(log, Protocol(0))
    v_dc = [s["V_dc"] for _, n, s in frames if n == "Tlm_Currents"]
    assert len(v_dc) >= 10 and all(abs(v - 300.0) < 1.0 for v in v_dc)  # the scenario's bus
