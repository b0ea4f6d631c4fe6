"""The tool's protocol layer against independent expectations: the CRC
check values of their catalogues, the DBC's identifiers and ranges, the
E2E monitor's arithmetic, the unit parser."""
import math

import pytest

from pmsm_can import units
from pmsm_can.protocol import (Protocol, ProtocolError, TelemetryMonitor, crc8_sae_j1850,
                               crc16_ccitt_false, e2e_crc, param_id)


def test_crc_check_values():
    # catalogue check values of CRC-8/SAE-J1850 and CRC-16/CCITT-FALSE
    assert crc8_sae_j1850(b"123456789") ^ 0xFF == 0x4B
    assert crc16_ccitt_false(b"123456789") == 0x29B1
    assert param_id("123456789") == 0x29B1


def test_identifiers_carry_the_node():
    p = Protocol(5)
    assert p.frame_id("Cmd_Speed") == 5 * 32 + 4
    assert p.number_of(5 * 32 + 16) == 16
    assert p.number_of(4 * 32 + 16) is None


def test_commands_checked_against_the_dbc():
    p = Protocol(0)
    fid, data = p.encode("Cmd_Speed", {"Omega_ref": 12.5})
    assert fid == 4 and len(data) == 4
    with pytest.raises(ProtocolError):
        p.encode("Cmd_Speed", {"Omega_ref": math.nan})
    with pytest.raises(ProtocolError):
        p.encode("Cmd_Speed", {"Omega_ref": 1e6})  # beyond the DBC's range


def test_telemetry_e2e_decode():
    p = Protocol(1)
    m = p.db.get_message_by_name("Tlm_Motion")
    raw = bytearray(m.encode({"Crc": 0, "Counter": 7, "Omega_m": 1.5, "Theta_m": -2.0}))
    fid = p.frame_id("Tlm_Motion")
    raw[0] = e2e_crc(fid, raw)
    name, sig, e2e = p.decode(fid, bytes(raw))
    assert name == "Tlm_Motion" and e2e == (True, 7)
    assert sig["Omega_m"] == pytest.approx(1.5) and sig["Theta_m"] == pytest.approx(-2.0)
    raw[4] ^= 1
    assert p.decode(fid, bytes(raw))[2] == (False, 7)


def test_monitor_counts_loss_repetition_corruption():
    mon = TelemetryMonitor()
    seq = [0, 1, 2, 4, 4, 5, 14, 0]  # a loss of 1 (3), a repeat (4), a loss of 8 (6..13)
    verdicts = [mon.update("Tlm_Motion", (True, c)) for c in seq]
    assert verdicts == ["ok", "ok", "ok", "lost", "repeated", "ok", "lost", "ok"]
    assert (mon.lost, mon.repeated) == (1 + 8, 1)
    assert mon.update("Tlm_Motion", (False, 1)) == "corrupted" and mon.corrupted == 1
    # the corrupted frame took counter 1: 2 next is in sequence, not a loss
    assert mon.update("Tlm_Motion", (True, 2)) == "ok" and mon.lost == 9


def test_units():
    assert units.speed_rad_s("60rpm") == pytest.approx(2 * math.pi)
    assert units.speed_rad_s("3.5") == 3.5
    assert units.angle_rad("180deg") == pytest.approx(math.pi)
    assert units.current_A("250mA") == pytest.approx(0.25)
    for bad in ("fast", "1 furlong", "nan", "inf rpm"):
        with pytest.raises(ProtocolError):
            units.speed_rad_s(bad)
