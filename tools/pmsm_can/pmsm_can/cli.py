"""pmsm-can: watch and command a drive over CAN.

  pmsm-can [--interface socketcan] [--channel vcan0] [--node 0] COMMAND ...
    status [--once]            live status view (curses), or one snapshot
    enable [--hold S]          enable and keep the link alive (Ctrl-C stops)
    disable | clear            disable / acknowledge faults
    speed 50rpm [--hold S]     speed mode + setpoint, streamed (feeds the
    current 0 1.5A [--hold S]  drive's command timeout), then disable
    position 90deg [--hold S]
    controller cdobc           select the controller (drive stopped)
    rate Tlm_Motion 10         one Tlm_Motion frame every 10 fast ISRs (0 off)
    param get NAME | param set NAME VALUE
    log FILE [--duration S]    every frame to FILE (.log candump, .blf, .asc,
                               .csv: python-can's writers), with the E2E report
    plot Tlm_Motion.Omega_m .. [--duration S] [--out PNG]
    replay FILE [--plot SIG ..] [--out PNG]
The drive stops (COMM_TIMEOUT fault) when commands stop while it is enabled:
the streaming commands resend their setpoint every --period s (0.02).
"""
import argparse
import sys
import time

import can

from . import units
from .client import DriveClient, DriveError
from .protocol import Protocol, ProtocolError, TelemetryMonitor, faults_text

STATES = {0: "IDLE", 1: "CALIBRATING", 2: "RUN", 3: "FAULT", 4: "ALIGN"}


def open_bus(args):
    kwargs = {"interface": args.interface, "channel": args.channel}
    if args.interface == "socketcan":
        kwargs["receive_own_messages"] = False
    return can.Bus(**kwargs)


def stream(client, args, send):
    """Call send() every period until --hold s have passed (or Ctrl-C),
    printing the status once a second; then disable."""
    end = time.monotonic() + args.hold if args.hold > 0 else float("inf")
    next_print = 0.0
    try:
        while time.monotonic() < end:
            send()
            t_next = time.monotonic() + args.period
            while time.monotonic() < t_next:
                client.poll(max(0.0, t_next - time.monotonic()))
            if time.monotonic() >= next_print:
                print(status_line(client), flush=True)
                next_print = time.monotonic() + 1.0
    except KeyboardInterrupt:
        pass
    finally:
        client.enable(False)
    return 0


def status_line(client):
    st = client.latest.get("Tlm_Status")
    mo = client.latest.get("Tlm_Motion")
    parts = []
    if st:
        s = st[1]
        parts.append(f"{STATES.get(int(s['State']), s['State'])} faults {faults_text(int(s['Faults_latched']))}")
    if mo:
        parts.append(f"omega {mo[1]['Omega_m']:.3f} rad/s ({mo[1]['Omega_m'] * 60 / 6.283185307:.1f} rpm)")
    parts.append(client.monitor.summary())
    return "; ".join(parts)


def cmd_status(client, args):
    if args.once:
        client.wait_for("Tlm_Status", timeout=args.timeout)
        print(status_line(client))
        return 0
    import curses

    def view(scr):
        scr.nodelay(True)
        while scr.getch() not in (ord("q"), 27):
            deadline = time.monotonic() + 0.2
            while time.monotonic() < deadline:
                client.poll(0.02)
            scr.erase()
            scr.addstr(0, 0, f"node {client.proto.node_id}  (q quits)")
            row = 2
            for name in sorted(client.latest):
                t, sig = client.latest[name]
                text = "  ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}"
                                 for k, v in sig.items() if k not in ("Crc", "Counter"))
                scr.addstr(row, 0, f"{name:15s} {text}"[: curses.COLS - 1])
                row += 1
            scr.addstr(row + 1, 0, client.monitor.summary()[: curses.COLS - 1])
            scr.refresh()
    curses.wrapper(view)
    return 0


def cmd_log(client, args):
    end = time.monotonic() + args.duration
    with can.Logger(args.file) as logger:
        while time.monotonic() < end:
            msg = client.bus.recv(0.05)
            if msg is not None:
                logger.on_message_received(msg)
                client.handle(msg)
    print(f"{args.file}: {client.monitor.summary()}")
    return 0


def signal_series(frames, names):
    """{Message.Signal: (t list, y list)} from (timestamp, message, signals)."""
    out = {n: ([], []) for n in names}
    for t, name, sig in frames:
        for n in names:
            m, s = n.split(".", 1)
            if m == name and s in sig:
                out[n][0].append(t)
                out[n][1].append(float(sig[s]))
    return out


def plot_series(series, out=None, title=""):
    import matplotlib
    if out:
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(len(series), 1, sharex=True, squeeze=False,
                             figsize=(8, 2.4 * len(series)))
    for ax, (name, (t, y)) in zip(axes[:, 0], series.items()):
        t0 = t[0] if t else 0.0
        ax.plot([x - t0 for x in t], y, lw=0.9)
        ax.set_ylabel(name, fontsize=8)
        ax.grid(True, alpha=0.3)
    axes[-1, 0].set_xlabel("time (s)")
    fig.suptitle(title)
    fig.tight_layout()
    if out:
        fig.savefig(out, dpi=110)
        print(f"wrote {out}")
    else:
        plt.show()


def check_signals(proto, names):
    for n in names:
        if "." not in n:
            raise ProtocolError(f"signal: expected Message.Signal, found {n!r}")
        m, s = n.split(".", 1)
        if s not in [x.name for x in proto.db.get_message_by_name(m).signals]:
            raise ProtocolError(f"{m} has no signal {s!r}")


def cmd_plot(client, args):
    """Live plot (a window refreshed every 0.2 s for --duration s), or,
    with --out, the same series saved as a PNG at the end."""
    check_signals(client.proto, args.signals)
    frames = []
    live = None
    if not args.out:
        import matplotlib.pyplot as plt
        plt.ion()
        fig, axes = plt.subplots(len(args.signals), 1, sharex=True, squeeze=False)
        lines = [ax.plot([], [], lw=0.9)[0] for ax in axes[:, 0]]
        for ax, name in zip(axes[:, 0], args.signals):
            ax.set_ylabel(name, fontsize=8)
            ax.grid(True, alpha=0.3)
        live = (plt, fig, axes, lines)
    t0 = time.monotonic()
    end = t0 + args.duration
    next_draw = t0
    while time.monotonic() < end:
        got = client.poll(0.02)
        if got and got[2] != "corrupted":
            frames.append((time.monotonic() - t0, got[0], got[1]))
        if live and time.monotonic() >= next_draw:
            plt, fig, axes, lines = live
            series = signal_series(frames, args.signals)
            for ax, line, name in zip(axes[:, 0], lines, args.signals):
                line.set_data(*series[name])
                ax.relim()
                ax.autoscale_view()
            fig.suptitle(client.monitor.summary(), fontsize=8)
            plt.pause(0.01)
            next_draw = time.monotonic() + 0.2
    if args.out:
        plot_series(signal_series(frames, args.signals), args.out, client.monitor.summary())
    return 0


def replay(path, proto):
    """Decoded frames of a log and the E2E report."""
    monitor = TelemetryMonitor()
    frames = []
    for msg in can.LogReader(path):
        if msg.is_error_frame or msg.is_remote_frame:
            continue
        decoded = proto.decode(msg.arbitration_id, msg.data)
        if decoded is None:
            continue
        name, sig, e2e = decoded
        if monitor.update(name, e2e) != "corrupted":
            frames.append((msg.timestamp, name, sig))
    return frames, monitor


def cmd_replay(args):
    proto = Protocol(args.node)
    frames, monitor = replay(args.file, proto)
    counts = {}
    for _, name, _ in frames:
        counts[name] = counts.get(name, 0) + 1
    for name in sorted(counts):
        print(f"{name:15s} {counts[name]}")
    print(monitor.summary())
    if args.plot:
        check_signals(proto, args.plot)
        plot_series(signal_series(frames, args.plot), args.out, args.file)
    return 0


def build_parser():
    ap = argparse.ArgumentParser(prog="pmsm-can", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--interface", default="socketcan", help="python-can interface (socketcan, virtual, ...)")
    ap.add_argument("--channel", default="vcan0", help="CAN channel (vcan0, can0)")
    ap.add_argument("--node", type=int, default=0, help="drive node id 0..63")
    ap.add_argument("--timeout", type=float, default=1.0, help="answer timeout (s)")
    sub = ap.add_subparsers(dest="command", required=True)
    p = sub.add_parser("status")
    p.add_argument("--once", action="store_true")
    for name in ("enable", "speed", "current", "position"):
        p = sub.add_parser(name)
        if name == "speed":
            p.add_argument("value", help="50rpm, 5.2rad/s, 1rps")
        elif name == "position":
            p.add_argument("value", help="1.5rad, 90deg, 2rev")
        elif name == "current":
            p.add_argument("i_d", help="d-axis current (A)")
            p.add_argument("i_q", help="q-axis current (A)")
        p.add_argument("--hold", type=float, default=0.0, help="seconds (0: until Ctrl-C)")
        p.add_argument("--period", type=float, default=0.02, help="resend period (s)")
    sub.add_parser("disable")
    sub.add_parser("clear")
    p = sub.add_parser("controller")
    p.add_argument("name")
    p = sub.add_parser("rate")
    p.add_argument("message", help="Tlm_Status .. Tlm_Counters")
    p.add_argument("decimation", type=int)
    p = sub.add_parser("param")
    p.add_argument("action", choices=["get", "set"])
    p.add_argument("name")
    p.add_argument("value", nargs="?")
    p = sub.add_parser("log")
    p.add_argument("file")
    p.add_argument("--duration", type=float, default=10.0)
    p = sub.add_parser("plot")
    p.add_argument("signals", nargs="+", help="Message.Signal, e.g. Tlm_Motion.Omega_m")
    p.add_argument("--duration", type=float, default=5.0)
    p.add_argument("--out", help="save a PNG instead of showing a window")
    p = sub.add_parser("replay")
    p.add_argument("file")
    p.add_argument("--plot", nargs="*", default=[])
    p.add_argument("--out")
    return ap


def run(args, bus=None):
    """Execute parsed args; bus: an open python-can bus (tests), else one
    is opened from --interface/--channel."""
    if args.command == "replay":
        return cmd_replay(args)
    own = bus is None
    bus = bus or open_bus(args)
    try:
        client = DriveClient(bus, args.node)
        c = args.command
        if c == "status":
            return cmd_status(client, args)
        if c == "enable":
            return stream(client, args, lambda: client.enable(True))
        if c == "disable":
            client.enable(False)
            return 0
        if c == "clear":
            client.clear_faults()
            return 0
        if c == "speed":
            w = units.speed_rad_s(args.value)
            return stream(client, args, lambda: (client.mode("speed"), client.speed(w), client.enable(True)))
        if c == "current":
            i_d, i_q = units.current_A(args.i_d), units.current_A(args.i_q)
            return stream(client, args, lambda: (client.mode("current"), client.current(i_d, i_q),
                                                 client.enable(True)))
        if c == "position":
            th = units.angle_rad(args.value)
            return stream(client, args, lambda: (client.mode("position"), client.position(th),
                                                 client.enable(True)))
        if c == "controller":
            client.controller(args.name)
            print(f"controller = {client.param_get('controller', args.timeout)[1]}")
            return 0
        if c == "rate":
            client.telemetry_rate(args.message, args.decimation)
            return 0
        if c == "param":
            if args.action == "get":
                t, v = client.param_get(args.name, args.timeout)
            else:
                if args.value is None:
                    raise ProtocolError("param set: expected a value")
                t, v = client.param_set(args.name, args.value, args.timeout)
            print(f"{args.name} = {v} ({t})")
            return 0
        if c == "log":
            return cmd_log(client, args)
        if c == "plot":
            return cmd_plot(client, args)
        raise ProtocolError(f"unknown command {c}")
    finally:
        if own:
            bus.shutdown()


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        return run(args)
    except (ProtocolError, DriveError, can.CanError, OSError, ValueError) as e:
        print(f"pmsm-can: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
