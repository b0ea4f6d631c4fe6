"""The drive's CAN protocol, read from its single source of truth
(tools/dbc/pmsm_drive.dbc): identifiers, command encoding, telemetry
decoding with the E2E check, parameter ids.

Identifier = node_id * 32 + message number (11-bit, node_id 0..63); the
DBC lists node 0's identifiers. Telemetry frames (messages 16..24) carry
byte 0 = CRC-8/SAE-J1850 (polynomial 0x1D, initial 0xFF, final XOR 0xFF)
over the data ID (the 11-bit identifier, low byte then high byte) and
bytes 1..7, and a counter 0..14 in the low nibble of byte 1.
"""
import math
import os

import cantools

NODE_ID_MAX = 63
MESSAGE_BITS = 5
TLM_FIRST, TLM_LAST = 16, 24
COUNTER_MODULO = 15

DBC_PATH = os.environ.get(
    "PMSM_CAN_DBC",
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "dbc", "pmsm_drive.dbc"),
)

PARAM_TYPES = {"f32": 0, "u32": 1, "bool": 2}
PARAM_STATUS = {0: "ok", 1: "unknown_id", 2: "refused_running", 3: "invalid_value", 4: "wrong_type"}
REJECT_CAUSES = {1: "unknown_message", 2: "wrong_dlc", 3: "bad_value", 4: "refused_state",
                 5: "unknown_param", 6: "wrong_param_type"}
FAULT_NAMES = ["overcurrent", "dc_overvoltage", "dc_undervoltage", "nonfinite", "isr_overrun",
               "external", "calibration", "encoder", "estimate", "overspeed", "stall", "i2t",
               "current_sensor", "loss_of_lock", "current_limit", "comm_timeout"]


class ProtocolError(Exception):
    """A frame or a request the protocol cannot express."""


def crc8_sae_j1850(data, crc=0xFF):
    """CRC-8/SAE-J1850 without the final XOR: feed bytes, then ^ 0xFF."""
    for b in data:
        crc ^= b
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1D) & 0xFF if crc & 0x80 else (crc << 1) & 0xFF
    return crc


def e2e_crc(frame_id, data):
    """The E2E CRC of a telemetry frame: data ID then bytes 1..7."""
    head = bytes([frame_id & 0xFF, (frame_id >> 8) & 0xFF])
    return crc8_sae_j1850(head + bytes(data[1:8])) ^ 0xFF


def crc16_ccitt_false(data):
    crc = 0xFFFF
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def param_id(name):
    """Parameter id of a configuration key ("cdobc.obs_pole_rad_s")."""
    if not name or any(c.isspace() for c in name):
        raise ProtocolError(f"parameter name: expected block.field or field, found {name!r}")
    return crc16_ccitt_false(name.encode("ascii"))


class Protocol:
    """Encoding and decoding for one node."""

    def __init__(self, node_id=0, dbc_path=DBC_PATH):
        if not isinstance(node_id, int) or not 0 <= node_id <= NODE_ID_MAX:
            raise ProtocolError(f"node id: expected 0..{NODE_ID_MAX}, found {node_id!r}")
        self.node_id = node_id
        self.db = cantools.database.load_file(dbc_path)
        self._by_number = {m.frame_id: m for m in self.db.messages}

    def frame_id(self, message_name):
        m = self.db.get_message_by_name(message_name)
        return (self.node_id << MESSAGE_BITS) | m.frame_id

    def number_of(self, frame_id):
        """Message number of a frame of this node, None for another node."""
        if frame_id >> MESSAGE_BITS != self.node_id:
            return None
        return frame_id & ((1 << MESSAGE_BITS) - 1)

    def message(self, number):
        return self._by_number.get(number)

    def encode(self, message_name, signals=None):
        """(identifier, payload) of a command, values checked against the
        DBC (finite, within each signal's range)."""
        m = self.db.get_message_by_name(message_name)
        signals = dict(signals or {})
        for s in m.signals:
            if s.name not in signals:
                continue
            v = signals[s.name]
            if isinstance(v, float) and not math.isfinite(v):
                raise ProtocolError(f"{message_name}.{s.name}: expected a finite value, found {v}")
            if s.minimum is not None and s.maximum is not None and not s.minimum <= v <= s.maximum:
                raise ProtocolError(f"{message_name}.{s.name}: expected "
                                    f"[{s.minimum:g}, {s.maximum:g}] {s.unit or ''}, found {v}")
        data = m.encode(signals, strict=False) if m.signals else b""
        return self.frame_id(message_name), bytes(data)

    def decode(self, frame_id, data):
        """(message name, signals dict, e2e) for a frame of this node;
        e2e is None for frames without protection, else (crc_ok, counter).
        None for another node's frame or an unknown message."""
        number = self.number_of(frame_id)
        m = self.message(number) if number is not None else None
        if m is None or len(data) != m.length:
            return None
        signals = m.decode(bytes(data), decode_choices=False, scaling=True)
        e2e = None
        if TLM_FIRST <= number <= TLM_LAST:
            e2e = (e2e_crc(frame_id, data) == data[0], data[1] & 0x0F)
        return m.name, signals, e2e


class TelemetryMonitor:
    """Loss, repetition and corruption of telemetry from the E2E fields:
    per message, the counter must advance by 1 (mod 15); a jump of k
    counts k - 1 lost frames, no advance a repeated frame; a CRC mismatch
    a corrupted frame, whose counter is not trusted: it is assumed to have
    taken one step, so the next gap counts it as corrupted, not lost."""

    def __init__(self):
        self.last = {}
        self.unread = {}  # message -> corrupted frames since its last good one
        self.received = 0
        self.lost = 0
        self.repeated = 0
        self.corrupted = 0

    def update(self, name, e2e):
        if e2e is None:
            return "ok"
        crc_ok, counter = e2e
        self.received += 1
        if not crc_ok:
            self.corrupted += 1
            self.unread[name] = self.unread.get(name, 0) + 1
            return "corrupted"
        prev = self.last.get(name)
        self.last[name] = counter
        skipped = self.unread.pop(name, 0)
        if prev is None:
            return "ok"
        step = (counter - prev - skipped) % COUNTER_MODULO
        if step == 0:
            self.repeated += 1
            return "repeated"
        if step > 1:
            self.lost += step - 1
            return "lost"
        return "ok"

    def summary(self):
        return (f"telemetry: {self.received} frames, {self.lost} lost, "
                f"{self.repeated} repeated, {self.corrupted} corrupted")


def faults_text(bits):
    names = [n for i, n in enumerate(FAULT_NAMES) if bits >> i & 1]
    return "+".join(names) if names else "none"
