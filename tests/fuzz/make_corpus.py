"""Write the seed corpus of the CAN fuzz harnesses (tests/fuzz/corpus/):
a few valid frames of each command for fuzz_can_node, typical operations
for fuzz_can_params. Input layouts: README.md. Python 3 standard library
only; rerun after a protocol change: python3 tests/fuzz/make_corpus.py
"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
NODE = 3
STEP = 0x04 | 0x08 | (1 << 4)  # poll, ISR first, 100 us
POLL = 0x04                    # poll only
LATE = 0x04 | 0x08 | (15 << 4)  # 22.5 ms later: beyond every timeout


def crc16(name):
    crc = 0xFFFF
    for b in name.encode():
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) & 0xFFFF if crc & 0x8000 else (crc << 1) & 0xFFFF
    return crc


def frame(msg, data=b"", flags=STEP, node=NODE, ext=False, rtr=False, dlc=None):
    f = flags | (1 if ext else 0) | (2 if rtr else 0)
    d = bytes(data)
    n = len(d) if dlc is None else dlc
    return struct.pack("<IBB", node * 32 + msg, f, n) + d.ljust(8, b"\0")[:8]


def header(node=NODE, apply=True, fails=False, timeout_ms=5, rates=1):
    return bytes([node | (0x40 if apply else 0) | (0x80 if fails else 0),
                  ((timeout_ms - 1) & 15) | (rates << 4)])


f32 = lambda v: struct.pack("<f", v)
u16 = lambda v: struct.pack("<H", v)


def pwrite(name, ptype, value):
    if ptype == 0:
        v = f32(value)
    elif ptype == 1:
        v = struct.pack("<I", value)
    else:
        v = bytes([value])
    return frame(8, u16(crc16(name)) + bytes([ptype]) + v.ljust(4, b"\0"))


node_seeds = {
    "enable_speed": header() + frame(2, [1]) + frame(4, f32(100.0)) + frame(1, [1])
    + b"".join(frame(4, f32(100.0)) for _ in range(12)) + frame(1, [0]),
    "current_position": header(rates=3) + frame(2, [0]) + frame(3, f32(1.0) + f32(-2.0))
    + frame(1, [1]) + frame(3, f32(0.5) + f32(0.5)) + frame(2, [2]) + frame(5, f32(3.14))
    + frame(1, [0]),
    "timeout_clear": header(timeout_ms=2) + frame(1, [1]) + frame(4, f32(0.0), flags=LATE)
    + frame(4, f32(0.0), flags=LATE) + frame(1, [0]) + frame(6, b"") + frame(6, b"", flags=POLL),
    "param_read": header(node=0) + b"".join(frame(7, u16(crc16(n)), node=0) for n in (
        "position.kp_per_s", "controller", "estimator", "timing.delay_compensation",
        "motor.pole_pairs", "no.such")),
    "param_write": header() + pwrite("position.kp_per_s", 0, 60.0)
    + pwrite("timing.delay_compensation", 2, 0) + pwrite("timing.isr_overrun_limit", 1, 50)
    + pwrite("position.kp_per_s", 0, -1.0) + pwrite("position.kp_per_s", 1, 7)
    + frame(1, [1]) + pwrite("position.kp_per_s", 0, 70.0),
    "param_write_apply_fails": header(fails=True) + pwrite("position.kp_per_s", 0, 60.0),
    "controller": header(node=63) + b"".join(frame(9, [c], node=63) for c in (0, 1, 2, 3, 4)),
    "telemetry_rate": header(rates=0) + b"".join(
        frame(10, bytes([m]) + u16(1 + m % 3)) for m in range(16, 25))
    + b"".join(frame(4, f32(1.0)) for _ in range(8)) + frame(10, bytes([25]) + u16(1)),
    "rejects": header() + frame(0, b"", dlc=0) + frame(11, [1, 2]) + frame(1, [1, 1])
    + frame(1, [1], ext=True) + frame(1, [1], rtr=True) + frame(1, [1], node=4)
    + frame(16, [0] * 8) + frame(26, [1, 1, 1]) + frame(3, f32(float("nan")) + f32(0.0))
    + frame(2, [3]) + frame(4, f32(1e5)),
}

PARAMS = ["position.kp_per_s", "controller", "estimator", "timing.delay_compensation",
          "motor.pole_pairs", "limits.i_max_A", "timing.f_pwm_Hz"]


def op(code, sel=0, value=b"\0\0\0\0", extra=0):
    return bytes([code]) + u16(sel) + value.ljust(4, b"\0")[:4] + bytes([extra])


params_seeds = {
    "lookups": b"".join(op(0, crc16(n)) for n in PARAMS) + op(0, 0x1234),
    "set_validate": op(1 | (0 << 2), 5, f32(60.0)) + op(3) + op(1 | (1 << 2), 0, struct.pack("<I", 3))
    + op(3) + op(1 | (2 << 2), 40, b"\1") + op(3) + op(1 | (0 << 2), 7, f32(float("inf"))) + op(3),
    "names": op(2, extra=0x35) + b"position" + b"kp_per_s" + op(2, extra=0x20) + b"controller"[:7],
}


def write(sub, seeds):
    d = os.path.join(HERE, "corpus", sub)
    os.makedirs(d, exist_ok=True)
    for name, data in seeds.items():
        with open(os.path.join(d, name + ".bin"), "wb") as f:
            f.write(data)


if __name__ == "__main__":
    write("can_node", node_seeds)
    write("can_params", params_seeds)
