"""Quantities with units on the command line: '50rpm', '5.2rad/s', '90deg'."""
import math
import re

from .protocol import ProtocolError

_NUM = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"
SPEED = {"": 1.0, "rad/s": 1.0, "rpm": 2 * math.pi / 60, "rps": 2 * math.pi, "deg/s": math.pi / 180}
ANGLE = {"": 1.0, "rad": 1.0, "deg": math.pi / 180, "rev": 2 * math.pi}
CURRENT = {"": 1.0, "a": 1.0, "ma": 1e-3}


def parse(text, units, what):
    m = re.fullmatch(_NUM + r"\s*([A-Za-z/]*)", text.strip())
    unit = m.group(2).lower() if m else None
    if not m or unit not in {u.lower() for u in units}:
        raise ProtocolError(f"{what}: expected a number with a unit among "
                            f"{', '.join(u or '(none: SI)' for u in units)}, found {text!r}")
    value = float(m.group(1)) * {u.lower(): f for u, f in units.items()}[unit]
    if not math.isfinite(value):
        raise ProtocolError(f"{what}: expected a finite value, found {text!r}")
    return value


def speed_rad_s(text):
    return parse(text, SPEED, "speed")


def angle_rad(text):
    return parse(text, ANGLE, "position")


def current_A(text):
    return parse(text, CURRENT, "current")
