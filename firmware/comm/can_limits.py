"""Generate pmsm_can_limits.h: the [min|max] range of every signal of the
CAN database, for the firmware's telemetry saturation (firmware/comm).

cantools' generated codec (firmware/can_codec) checks ranges
(..._is_in_range) but publishes no limits, and its encoders cast without
saturating; the node saturates telemetry values into the DBC range before
encoding, with the limits written here from the same database at build
time, so they cannot drift from it.

For each signal of each message, with the codec's names:
  PMSM_CAN_<MESSAGE>_<SIGNAL>_MIN, _MAX          physical range (float)
  PMSM_CAN_<MESSAGE>_<SIGNAL>_RAW_MIN, _RAW_MAX  raw range (integer
                                                 signals only)

usage: python can_limits.py <database.dbc> <output.h>
"""
import math
import sys

import cantools
from cantools.database.can.c_source import camel_to_snake_case


def c_float(x):
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"non-finite limit {x}")
    text = repr(x)
    if "e" not in text and "." not in text:
        text += ".0"
    return f"({text}f)"


def c_int(x, signed):
    return f"({int(x)})" if signed else f"({int(x)}u)"


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    db = cantools.database.load_file(argv[1])
    lines = [
        "/* Generated from the CAN database by firmware/comm/can_limits.py:",
        " * do not edit. Every signal's [min|max] range, with the names of",
        " * the generated codec (pmsm_can.h). */",
        "#ifndef PMSM_CAN_LIMITS_H",
        "#define PMSM_CAN_LIMITS_H",
        "",
    ]
    for msg in db.messages:
        mname = camel_to_snake_case(msg.name).upper()
        for sig in msg.signals:
            if sig.minimum is None or sig.maximum is None:
                raise ValueError(f"{msg.name}.{sig.name}: no [min|max] in the DBC")
            name = f"PMSM_CAN_{mname}_{camel_to_snake_case(sig.name).upper()}"
            lines.append(f"#define {name}_MIN {c_float(sig.minimum)}")
            lines.append(f"#define {name}_MAX {c_float(sig.maximum)}")
            if not sig.is_float:
                raw_min = round((sig.minimum - sig.offset) / sig.scale)
                raw_max = round((sig.maximum - sig.offset) / sig.scale)
                lines.append(f"#define {name}_RAW_MIN {c_int(raw_min, sig.is_signed)}")
                lines.append(f"#define {name}_RAW_MAX {c_int(raw_max, sig.is_signed)}")
    lines += ["", "#endif /* PMSM_CAN_LIMITS_H */", ""]
    with open(argv[2], "w", encoding="ascii") as f:
        f.write("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
