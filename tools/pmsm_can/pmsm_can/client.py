"""A drive on a python-can bus: commands, parameter access, telemetry with
loss/corruption accounting (protocol.py)."""
import math
import time

import can

from .protocol import (PARAM_STATUS, PARAM_TYPES, REJECT_CAUSES, TLM_FIRST, TLM_LAST, Protocol,
                       ProtocolError, TelemetryMonitor, param_id)

MODES = {"current": 0, "speed": 1, "position": 2}
CONTROLLERS = {"foc_pi": 0, "idapbc": 1, "eeo": 2, "cdobc": 3}


class DriveError(Exception):
    """The drive refused a request or did not answer."""


class DriveClient:
    def __init__(self, bus, node_id=0, protocol=None):
        self.bus = bus
        self.proto = protocol or Protocol(node_id)
        self.monitor = TelemetryMonitor()
        self.latest = {}      # message name -> (time, signals)
        self.rejections = []  # decoded Rsp_Error frames
        self.replies = []     # decoded Rsp_Param frames not yet consumed

    # ---- sending ----------------------------------------------------------
    def send(self, name, signals=None):
        frame_id, data = self.proto.encode(name, signals)
        self.bus.send(can.Message(arbitration_id=frame_id, data=data, is_extended_id=False))

    def enable(self, on=True):
        self.send("Cmd_Enable", {"Enable": 1 if on else 0})

    def mode(self, name):
        if name not in MODES:
            raise ProtocolError(f"mode: expected one of {', '.join(MODES)}, found {name!r}")
        self.send("Cmd_Mode", {"Mode": MODES[name]})

    def speed(self, omega_rad_s):
        self.send("Cmd_Speed", {"Omega_ref": float(omega_rad_s)})

    def current(self, i_d_A, i_q_A):
        self.send("Cmd_Current", {"I_d_ref": float(i_d_A), "I_q_ref": float(i_q_A)})

    def position(self, theta_rad):
        self.send("Cmd_Position", {"Theta_ref": float(theta_rad)})

    def clear_faults(self):
        self.send("Cmd_ClearFaults")

    def controller(self, name):
        if name not in CONTROLLERS:
            raise ProtocolError(f"controller: expected one of {', '.join(CONTROLLERS)}, found {name!r}")
        self.send("Cmd_Controller", {"Controller": CONTROLLERS[name]})

    def telemetry_rate(self, message, decimation):
        number = self._telemetry_number(message)
        self.send("Cmd_TelemetryRate", {"Telemetry_msg": number, "Decimation": int(decimation)})

    def _telemetry_number(self, message):
        if isinstance(message, int):
            number = message
        else:
            m = self.proto.db.get_message_by_name(message)
            number = m.frame_id
        if not TLM_FIRST <= number <= TLM_LAST:
            raise ProtocolError(f"telemetry message: expected {TLM_FIRST}..{TLM_LAST}, found {message!r}")
        return number

    # ---- receiving --------------------------------------------------------
    def poll(self, timeout=0.0):
        """Take one frame (or None after timeout s); returns (name, signals,
        verdict) for a frame of this node, verdict from the E2E monitor
        ('ok', 'lost', 'repeated', 'corrupted')."""
        msg = self.bus.recv(timeout)
        if msg is None:
            return None
        return self.handle(msg)

    def handle(self, msg):
        if msg.is_extended_id or msg.is_error_frame or msg.is_remote_frame:
            return None
        decoded = self.proto.decode(msg.arbitration_id, msg.data)
        if decoded is None:
            return None
        name, signals, e2e = decoded
        verdict = self.monitor.update(name, e2e)
        if verdict != "corrupted":
            self.latest[name] = (msg.timestamp, signals)
        if name == "Rsp_Error":
            self.rejections.append(signals)
        elif name == "Rsp_Param":
            self.replies.append(signals)
        return name, signals, verdict

    def wait_for(self, name, timeout=1.0, predicate=None):
        """Poll until a frame `name` (matching predicate) arrives."""
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            got = self.poll(max(0.0, min(0.05, end - time.monotonic())))
            if got and got[0] == name and (predicate is None or predicate(got[1])):
                return got[1]
        raise DriveError(f"no {name} from node {self.proto.node_id} within {timeout:g} s")

    # ---- parameters -------------------------------------------------------
    def _param_reply(self, pid, timeout):
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            for i, r in enumerate(self.replies):
                if int(r["Param_id"]) == pid:
                    return self.replies.pop(i)
            for i, r in enumerate(self.rejections):
                if int(r["Rejected_cmd"]) in (7, 8, 9):
                    rej = self.rejections.pop(i)
                    raise DriveError("request rejected: "
                                     + REJECT_CAUSES.get(int(rej["Cause"]), str(rej["Cause"])))
            self.poll(0.02)
        raise DriveError(f"no answer to parameter {pid:#06x} within {timeout:g} s")

    @staticmethod
    def _value(reply):
        t = int(reply["Param_type"])
        return {0: ("f32", reply.get("Value_f32")), 1: ("u32", reply.get("Value_u32")),
                2: ("bool", reply.get("Value_bool"))}[t]

    def param_get(self, name, timeout=1.0):
        pid = param_id(name)
        self.send("Cmd_ParamRead", {"Param_id": pid})
        reply = self._param_reply(pid, timeout)
        status = int(reply["Status"])
        if status != 0:
            raise DriveError(f"{name}: {PARAM_STATUS.get(status, status)}")
        return self._value(reply)

    def param_set(self, name, value, timeout=1.0):
        """Write with the parameter's own type (read first); returns the
        value now in force."""
        ptype, _ = self.param_get(name, timeout)
        pid = param_id(name)
        if ptype == "f32":
            v = float(value)
            if not math.isfinite(v):
                raise ProtocolError(f"{name}: expected a finite number, found {value!r}")
            signals = {"Value_f32": v}
        elif ptype == "u32":
            v = int(value)
            signals = {"Value_u32": v}
        else:
            v = value if isinstance(value, bool) else str(value).lower() in ("1", "true", "on", "yes")
            signals = {"Value_bool": int(v)}
        signals.update({"Param_id": pid, "Param_type": PARAM_TYPES[ptype]})
        self.send("Cmd_ParamWrite", signals)
        reply = self._param_reply(pid, timeout)
        status = int(reply["Status"])
        if status != 0:
            raise DriveError(f"{name} = {value}: {PARAM_STATUS.get(status, status)}")
        return self._value(reply)
