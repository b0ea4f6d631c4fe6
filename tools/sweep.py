#!/usr/bin/env python3
"""Parameter sweeps of pmsm-sim: a sweep description (docs/sweeps.md) expands
into one pmsm-sim job per point; the jobs run elsewhere (GNU parallel on one
machine, tools/sweep.sh; or a Slurm job array); their JSON metrics are
collected into one table and heat maps.

usage: sweep.py expand SWEEP.json OUT_DIR [--pmsm-sim PATH]
           writes OUT_DIR/jobs.txt (line N runs point N) and OUT_DIR/points.csv
       sweep.py collect SWEEP.json OUT_DIR [--no-plot]
           reads OUT_DIR/point_NNNN.{json,rc,log} (and OUT_DIR/joblog.tsv, GNU
           parallel's, for a point without its .rc), writes OUT_DIR/results.csv
           and OUT_DIR/heatmap.png and prints the table
Exit status: 0 done (a point whose run failed is a row of the table, not an
error of the sweep); 1 a metric path absent from a run's JSON (the table is
still written); 2 bad command line, sweep description or OUT_DIR.
Standard library, plus matplotlib for the heat maps: run it with the
project's venv (tools/setup.sh): .venv/bin/python.
"""
import argparse
import csv
import itertools
import json
import math
import os
import re
import shlex
import sys

FORMAT_VERSION = 1
PROG = "sweep"


class SweepError(Exception):
    """An error of the sweep description (exit status 2)."""


class UsageError(SweepError):
    """An error of the command line or of OUT_DIR (exit status 2)."""


def fail(where, expected, found):
    raise SweepError(f"{where + ': ' if where else ''}expected {expected}, found {found}")


# --- the sweep description -------------------------------------------------


def no_duplicate_keys(pairs):
    seen = {}
    for k, v in pairs:
        if k in seen:
            raise SweepError(f"repeated key {k!r}")
        seen[k] = v
    return seen


def check_keys(obj, where, required, optional):
    if not isinstance(obj, dict):
        fail(where, "an object", json.dumps(obj))
    for k in obj:
        if k not in required and k not in optional:
            allowed = ", ".join(f'"{a}"' for a in (*required, *optional))
            fail(f"{where}.{k}" if where else k, f"one of {allowed} (unknown key)", json.dumps(k))
    for k in required:
        if k not in obj:
            fail(f"{where}.{k}" if where else k, "this key (required)", "nothing")


NAME_RE = re.compile(r"^[A-Za-z0-9_]+$")
# A key path of --set: dotted keys with [i] indexes (host_sim/scenarios/README.md).
KEY_PART = r"[A-Za-z_][A-Za-z0-9_]*(\[[0-9]+\])*"
KEY_PATH_RE = re.compile(rf"^{KEY_PART}(\.{KEY_PART})*$")


def check_name(value, where):
    if not isinstance(value, str) or not NAME_RE.match(value):
        fail(where, "a name of letters, digits and _", json.dumps(value))


def check_set_list(value, where):
    if not isinstance(value, list):
        fail(where, 'an array of "KEY.PATH=VALUE" strings', json.dumps(value))
    for i, s in enumerate(value):
        if not isinstance(s, str) or "=" not in s or not KEY_PATH_RE.match(s.split("=", 1)[0]):
            fail(f"{where}[{i}]", '"KEY.PATH=VALUE"', json.dumps(s))
    return list(value)


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def linspace(spec, where):
    if (not isinstance(spec, list) or len(spec) != 3 or not all(is_number(x) for x in spec)
            or not isinstance(spec[2], int) or spec[2] < 2):
        fail(where, "[start, stop, n] with n >= 2 an integer", json.dumps(spec))
    a, b, n = spec
    # 12 significant digits: 0.1 steps stay 0.3, not 0.30000000000000004.
    return [float(f"{a + (b - a) * i / (n - 1):.12g}") for i in range(n)]


def load_axis(ax, where):
    check_keys(ax, where, ("name", "keys", "values"), ("nominal", "label"))
    check_name(ax["name"], f"{where}.name")
    keys = ax["keys"] if isinstance(ax["keys"], list) else [ax["keys"]]
    if not keys:
        fail(f"{where}.keys", "a key path or a non-empty array of key paths", "[]")
    for i, k in enumerate(keys):
        if not isinstance(k, str) or not KEY_PATH_RE.match(k):
            fail(f"{where}.keys" + (f"[{i}]" if isinstance(ax["keys"], list) else ""),
                 "a key path of --set (e.g. disturbances.mismatch.R)", json.dumps(k))
    vals = ax["values"]
    if isinstance(vals, dict):
        check_keys(vals, f"{where}.values", ("linspace",), ())
        vals = linspace(vals["linspace"], f"{where}.values.linspace")
    if not isinstance(vals, list) or not vals:
        fail(f"{where}.values", 'a non-empty array or {"linspace": [start, stop, n]}',
             json.dumps(vals))
    points = []  # (label, [value per key])
    for i, v in enumerate(vals):
        w = f"{where}.values[{i}]"
        if isinstance(v, dict):
            check_keys(v, w, ("label", "set"), ())
            if not isinstance(v["set"], list) or len(v["set"]) != len(keys):
                fail(f"{w}.set", f"an array of {len(keys)} values, one per key",
                     json.dumps(v["set"]))
            if not isinstance(v["label"], (int, float, str)) or isinstance(v["label"], bool):
                fail(f"{w}.label", "a number or a string", json.dumps(v["label"]))
            points.append((v["label"], list(v["set"])))
        else:
            points.append((v, [v] * len(keys)))
    labels = [p[0] for p in points]
    if len(set(map(json.dumps, labels))) != len(labels):
        fail(f"{where}.values", "distinct values (labels)", json.dumps(labels))
    nominal = ax.get("nominal", labels[0])
    if nominal not in labels:
        fail(f"{where}.nominal", f"one of the axis values {json.dumps(labels)}",
             json.dumps(nominal))
    label = ax.get("label", ax["name"])
    if not isinstance(label, str):
        fail(f"{where}.label", "a string", json.dumps(label))
    return {"name": ax["name"], "label": label, "keys": keys, "points": points,
            "nominal": labels.index(nominal)}


def load_sweep(path):
    try:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f, object_pairs_hook=no_duplicate_keys,
                            parse_constant=lambda c: fail("", "finite numbers", c))
    except OSError as e:
        raise SweepError(f"cannot read: {e.strerror}")
    except json.JSONDecodeError as e:
        raise SweepError(f"{e.lineno}:{e.colno}: malformed JSON: {e.msg}")
    check_keys(doc, "", ("sweep_format_version", "bases", "axes", "metrics"),
               ("name", "description", "set", "stable"))
    if doc["sweep_format_version"] != FORMAT_VERSION:
        fail("sweep_format_version", str(FORMAT_VERSION), json.dumps(doc["sweep_format_version"]))
    here = os.path.dirname(os.path.abspath(path))
    sweep = {"name": doc.get("name", os.path.splitext(os.path.basename(path))[0]),
             "set": check_set_list(doc.get("set", []), "set")}
    if not isinstance(doc["bases"], list) or not doc["bases"]:
        fail("bases", "a non-empty array", json.dumps(doc["bases"]))
    sweep["bases"] = []
    for i, b in enumerate(doc["bases"]):
        w = f"bases[{i}]"
        check_keys(b, w, ("name", "scenario"), ("set",))
        check_name(b["name"], f"{w}.name")
        if not isinstance(b["scenario"], str) or not b["scenario"]:
            fail(f"{w}.scenario", "a scenario file (relative to the sweep file)",
                 json.dumps(b["scenario"]))
        scen = os.path.normpath(os.path.join(here, b["scenario"]))
        if not os.path.isfile(scen):
            fail(f"{w}.scenario", "an existing scenario file", scen)
        sweep["bases"].append({"name": b["name"], "scenario": scen,
                               "set": check_set_list(b.get("set", []), f"{w}.set")})
    if not isinstance(doc["axes"], list) or not doc["axes"]:
        fail("axes", "a non-empty array of axes", json.dumps(doc["axes"]))
    sweep["axes"] = [load_axis(a, f"axes[{i}]") for i, a in enumerate(doc["axes"])]
    if not isinstance(doc["metrics"], list) or not doc["metrics"]:
        fail("metrics", "a non-empty array", json.dumps(doc["metrics"]))
    sweep["metrics"] = []
    for i, m in enumerate(doc["metrics"]):
        w = f"metrics[{i}]"
        check_keys(m, w, ("name", "path"), ("plot", "scale"))
        check_name(m["name"], f"{w}.name")
        if not isinstance(m["path"], str) or not KEY_PATH_RE.match(m["path"]):
            fail(f"{w}.path", "a JSON path such as windows.at_120rpm.rms_error_rpm",
                 json.dumps(m["path"]))
        if not isinstance(m.get("plot", True), bool):
            fail(f"{w}.plot", "true or false", json.dumps(m["plot"]))
        if m.get("scale", "linear") not in ("linear", "log"):
            fail(f"{w}.scale", '"linear" or "log"', json.dumps(m["scale"]))
        sweep["metrics"].append({"name": m["name"], "path": parse_path(m["path"]),
                                 "path_text": m["path"], "plot": m.get("plot", True),
                                 "scale": m.get("scale", "linear")})
    names = [b["name"] for b in sweep["bases"]]
    if len(set(names)) != len(names):
        fail("bases", "distinct names", json.dumps(names))
    cols = [a["name"] for a in sweep["axes"]] + [m["name"] for m in sweep["metrics"]]
    clash = sorted({c for c in cols if cols.count(c) > 1 or c in FIXED_COLUMNS})
    if clash:
        fail("axes, metrics", f"names distinct from each other and from {', '.join(FIXED_COLUMNS)}",
             ", ".join(clash))
    sweep["stable"] = load_stable(doc.get("stable"), sweep["metrics"])
    return sweep


def load_stable(st, metrics):
    if st is None:
        return None
    check_keys(st, "stable", (), ("no_fault", "max", "min"))
    out = {"no_fault": st.get("no_fault", False), "max": {}, "min": {}}
    if not isinstance(out["no_fault"], bool):
        fail("stable.no_fault", "true or false", json.dumps(out["no_fault"]))
    names = [m["name"] for m in metrics]
    for kind in ("max", "min"):
        bounds = st.get(kind, {})
        if not isinstance(bounds, dict):
            fail(f"stable.{kind}", "an object {metric name: bound}", json.dumps(bounds))
        for k, v in bounds.items():
            if k not in names:
                fail(f"stable.{kind}.{k}", f"a metric name ({', '.join(names)})", json.dumps(k))
            if not is_number(v):
                fail(f"stable.{kind}.{k}", "a finite number", json.dumps(v))
            out[kind][k] = v
    return out


def parse_path(text):
    """'windows.at_120rpm.rms_error_rpm', 'load_steps[2].max_dip_rpm' -> keys."""
    out = []
    for part in text.split("."):
        m = re.match(r"^([^\[]+)((\[[0-9]+\])*)$", part)
        out.append(m.group(1))
        out.extend(int(i) for i in re.findall(r"\[([0-9]+)\]", m.group(2)))
    return out


FIXED_COLUMNS = ("point", "base", "exit_code", "status", "reason")


# --- expand ----------------------------------------------------------------


def expand_points(sweep):
    """Every point: (index from 1, base, [axis value index per axis])."""
    grid = list(itertools.product(*(range(len(a["points"])) for a in sweep["axes"])))
    points = []
    for base in sweep["bases"]:
        for combo in grid:
            points.append((len(points) + 1, base, list(combo)))
    return points


def point_stem(index, n):
    return f"point_{index:0{max(4, len(str(n)))}d}"


def label_text(v):
    return v if isinstance(v, str) else json.dumps(v)


def points_rows(sweep, points):
    rows = [["point", "base"] + [a["name"] for a in sweep["axes"]]]
    for idx, base, combo in points:
        rows.append([str(idx), base["name"]] +
                    [label_text(a["points"][c][0]) for a, c in zip(sweep["axes"], combo)])
    return rows


def csv_text(rows):
    class Buf:
        def __init__(self):
            self.parts = []

        def write(self, s):
            self.parts.append(s)
    buf = Buf()
    csv.writer(buf, lineterminator="\n").writerows(rows)
    return "".join(buf.parts)


def job_line(sweep, point, n, out_dir, pmsm_sim):
    idx, base, combo = point
    sets = list(sweep["set"]) + list(base["set"])
    for a, c in zip(sweep["axes"], combo):
        for key, value in zip(a["keys"], a["points"][c][1]):
            sets.append(f"{key}={json.dumps(value)}")
    stem = os.path.join(out_dir, point_stem(idx, n))
    q = shlex.quote
    cmd = [q(pmsm_sim), "run", q(base["scenario"])]
    for s in sets:
        cmd += ["--set", q(s)]
    cmd += ["--quiet", "--json", q(stem + ".json")]
    # The exit status is kept beside the metrics, so that the table does not
    # depend on what ran the line (GNU parallel, a Slurm array task, a shell).
    return (" ".join(cmd) + f" 2>{q(stem + '.log')}; s=$?; echo $s >{q(stem + '.rc')}; exit $s")


def cmd_expand(args):
    sweep = load_sweep(args.sweep)
    out_dir = os.path.abspath(args.out_dir)
    os.makedirs(out_dir, exist_ok=True)
    pmsm_sim = os.path.abspath(args.pmsm_sim)
    if not os.access(pmsm_sim, os.X_OK):
        raise UsageError(f"--pmsm-sim: expected an executable pmsm-sim, found {pmsm_sim}")
    points = expand_points(sweep)
    # The outputs of an earlier expansion would be mistaken for this one's.
    for f in os.listdir(out_dir):
        if re.match(r"^point_[0-9]+\.(json|rc|log)$", f) or f in (
                "joblog.tsv", "results.csv", "heatmap.png"):
            os.remove(os.path.join(out_dir, f))
    n = len(points)
    with open(os.path.join(out_dir, "jobs.txt"), "w", encoding="utf-8") as f:
        for p in points:
            f.write(job_line(sweep, p, n, out_dir, pmsm_sim) + "\n")
    with open(os.path.join(out_dir, "points.csv"), "w", encoding="utf-8") as f:
        f.write(csv_text(points_rows(sweep, points)))
    shape = " x ".join(str(len(a["points"])) for a in sweep["axes"])
    print(f"{PROG}: {sweep['name']}: {n} points ({len(sweep['bases'])} base scenario(s) x "
          f"{shape}): {os.path.join(out_dir, 'jobs.txt')}")
    return 0


# --- collect ---------------------------------------------------------------


def read_joblog(path):
    """GNU parallel's --joblog: Seq -> exit value (or 128 + signal)."""
    codes = {}
    try:
        with open(path, encoding="utf-8") as f:
            for row in csv.DictReader(f, delimiter="\t"):
                try:
                    seq, code, sig = int(row["Seq"]), int(row["Exitval"]), int(row["Signal"])
                except (KeyError, TypeError, ValueError):
                    continue
                codes[seq] = 128 + sig if sig else code
    except OSError:
        pass
    return codes


def get_path(doc, path):
    cur = doc
    for k in path:
        if isinstance(k, int):
            if not isinstance(cur, list) or k >= len(cur):
                raise KeyError(k)
        elif not isinstance(cur, dict) or k not in cur:
            raise KeyError(k)
        cur = cur[k]
    return cur


def cell_text(v):
    """A metric's value in the CSV: numbers exact (repr), lists joined by +."""
    if v is None:
        return "n/a"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, list):
        return "+".join(cell_text(x) for x in v) if v else "none"
    if isinstance(v, dict):
        return json.dumps(v, sort_keys=True)
    return str(v)


def first_error_line(log_path):
    try:
        with open(log_path, encoding="utf-8", errors="replace") as f:
            lines = [ln.strip() for ln in f if ln.strip()]
    except OSError:
        return ""
    errs = [ln for ln in lines if "error" in ln]
    return (errs or lines or [""])[0][:200]


def classify(sweep, values, faults):
    st = sweep["stable"]
    if st is None:
        return "ok", []
    reasons = []
    if st["no_fault"] and faults:
        reasons.append("fault " + "+".join(faults))
    for kind, op, bad in (("max", ">", lambda x, b: x > b), ("min", "<", lambda x, b: x < b)):
        for name, bound in st[kind].items():
            v = values.get(name)
            if not is_number(v):
                reasons.append(f"{name} unavailable")
            elif bad(v, bound):
                reasons.append(f"{name} {op} {bound:g}")
    return ("unstable" if reasons else "stable"), reasons


def collect_rows(sweep, out_dir):
    points = expand_points(sweep)
    n = len(points)
    expected = csv_text(points_rows(sweep, points))
    try:
        with open(os.path.join(out_dir, "points.csv"), encoding="utf-8") as f:
            found = f.read()
    except OSError:
        raise UsageError(f"{out_dir}: no points.csv: run `sweep.py expand` first")
    if found != expected:
        raise UsageError(f"{out_dir}/points.csv: expected the points of the sweep description, "
                         "found other points (the description changed since `expand`: expand "
                         "and run again)")
    joblog = read_joblog(os.path.join(out_dir, "joblog.tsv"))
    rows, missing = [], []
    for idx, base, combo in points:
        stem = os.path.join(out_dir, point_stem(idx, n))
        row = {"point": idx, "base": base["name"], "combo": combo,
               "axes": [a["points"][c][0] for a, c in zip(sweep["axes"], combo)],
               "values": {}, "faults": []}
        try:
            with open(stem + ".rc", encoding="utf-8") as f:
                code = int(f.read().strip())
        except (OSError, ValueError):
            code = joblog.get(idx)
        row["exit_code"] = code
        reasons = []
        if code is None:
            row["status"], reasons = "not run", ["no exit status: the job did not run"]
        elif code != 0:
            row["status"] = "failed"
            reasons = [first_error_line(stem + ".log") or f"exit {code}"]
        else:
            try:
                with open(stem + ".json", encoding="utf-8") as f:
                    doc = json.load(f)
            except (OSError, json.JSONDecodeError) as e:
                doc = None
                row["status"], reasons = "failed", [f"exit 0 but no metrics JSON ({e})"]
            if doc is not None:
                for m in sweep["metrics"]:
                    try:
                        row["values"][m["name"]] = get_path(doc, m["path"])
                    except KeyError:
                        row["values"][m["name"]] = "missing"
                        missing.append(f"{os.path.basename(stem)}.json: {m['path_text']}")
                row["faults"] = list(doc.get("faults", {}).get("latched", []))
                row["status"], reasons = classify(sweep, row["values"], row["faults"])
        row["reason"] = "; ".join(reasons)
        rows.append(row)
    return rows, missing


def table_rows(sweep, rows, exact):
    head = list(FIXED_COLUMNS[:2]) + [a["name"] for a in sweep["axes"]] + \
        ["exit_code", "status"] + [m["name"] for m in sweep["metrics"]] + ["reason"]
    out = [head]
    for r in rows:
        cells = [str(r["point"]), r["base"]] + [label_text(v) for v in r["axes"]]
        cells += ["" if r["exit_code"] is None else str(r["exit_code"]), r["status"]]
        for m in sweep["metrics"]:
            if m["name"] not in r["values"]:
                cells.append("")
                continue
            v = r["values"][m["name"]]
            cells.append(f"{v:.4g}" if not exact and is_number(v) else cell_text(v))
        cells.append(r["reason"])
        out.append(cells)
    return out


def print_table(rows):
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    for r in rows:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip())


def plot_heatmaps(sweep, rows, path):
    try:
        import matplotlib
    except ImportError:
        raise UsageError(f"no matplotlib in {sys.executable}: run with the project's "
                         ".venv/bin/python (tools/setup.sh), or collect --no-plot")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # noqa: E402  (backend first)
    from matplotlib.colors import LogNorm, Normalize  # noqa: E402

    axes = sweep["axes"]
    metrics = [m for m in sweep["metrics"] if m["plot"]
               and any(is_number(r["values"].get(m["name"])) for r in rows)]
    if not metrics:
        return False
    # Two axes or more: one map per pair (x the earlier axis, y the later),
    # the other axes at their nominal values; one axis: a single row.
    pairs = list(itertools.combinations(range(len(axes)), 2)) or [(0, None)]
    panels = [(b, m) for b in sweep["bases"] for m in metrics]
    # One colour scale per metric, shared by every base and pair: the maps
    # of two controllers compare by colour.
    norms = {}
    for m in metrics:
        finite = [float(v) for r in rows for v in [r["values"].get(m["name"])]
                  if is_number(v) and not (m["scale"] == "log" and v <= 0)]
        if finite:
            lo, hi = min(finite), max(finite)
            norms[m["name"]] = LogNorm(lo, hi if hi > lo else lo * 10) if m["scale"] == "log" \
                else Normalize(lo, hi if hi > lo else lo + 1)
    # A map is wider than 4.6 in when its x axis has more than 8 values
    # (0.55 in per cell: the annotations stay readable).
    width = max(4.6, 0.55 * max(len(axes[ix]["points"]) for ix, _ in pairs) + 1.5)
    fig, grid = plt.subplots(len(panels), len(pairs), squeeze=False,
                             figsize=(width * len(pairs), 3.6 * len(panels)))
    for pi, (base, m) in enumerate(panels):
        for pj, (ix, iy) in enumerate(pairs):
            ax = grid[pi][pj]
            nx = len(axes[ix]["points"])
            ny = 1 if iy is None else len(axes[iy]["points"])
            val = [[math.nan] * nx for _ in range(ny)]
            note = [[""] * nx for _ in range(ny)]
            for r in rows:
                if r["base"] != base["name"]:
                    continue
                if any(k not in (ix, iy) and c != axes[k]["nominal"]
                       for k, c in enumerate(r["combo"])):
                    continue
                x, y = r["combo"][ix], (0 if iy is None else r["combo"][iy])
                v = r["values"].get(m["name"])
                if is_number(v) and not (m["scale"] == "log" and v <= 0):
                    val[y][x] = float(v)
                    note[y][x] = f"{v:.3g}"
                elif r["status"] in ("stable", "unstable", "ok"):
                    note[y][x] = "n/a" if v is None else cell_text(v)
                if r["status"] == "failed":
                    note[y][x] = f"exit {r['exit_code']}"
                elif r["status"] == "not run":
                    note[y][x] = "not run"
                elif r["status"] == "unstable":
                    note[y][x] += "\n" + ("+".join(r["faults"]) if r["faults"] else "unstable")
            norm = norms.get(m["name"])
            cmap = plt.get_cmap("viridis").copy()
            cmap.set_bad("0.85")
            img = ax.imshow(val, origin="lower", aspect="auto", cmap=cmap, norm=norm)
            for y in range(ny):
                for x in range(nx):
                    bright = norm is not None and math.isfinite(val[y][x]) and \
                        norm(val[y][x]) > 0.6
                    ax.text(x, y, note[y][x], ha="center", va="center", fontsize=7,
                            color="black" if bright or not math.isfinite(val[y][x]) else "white")
            ax.set_xticks(range(nx), [label_text(p[0]) for p in axes[ix]["points"]],
                          rotation=90 if nx > 8 else 0)
            ax.set_xlabel(axes[ix]["label"])
            if iy is None:
                ax.set_yticks([])
            else:
                ax.set_yticks(range(ny), [label_text(p[0]) for p in axes[iy]["points"]])
                ax.set_ylabel(axes[iy]["label"])
            fixed = [f"{a['name']}={label_text(a['points'][a['nominal']][0])}"
                     for k, a in enumerate(axes) if k not in (ix, iy)]
            title = f"{base['name']}: {m['name']}"
            if fixed:
                title += f" ({', '.join(fixed)})"
            ax.set_title(title, fontsize=9)
            if norm is not None:
                fig.colorbar(img, ax=ax, shrink=0.85)
    fig.suptitle(sweep["name"])
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def cmd_collect(args):
    sweep = load_sweep(args.sweep)
    out_dir = os.path.abspath(args.out_dir)
    rows, missing = collect_rows(sweep, out_dir)
    csv_path = os.path.join(out_dir, "results.csv")
    with open(csv_path, "w", encoding="utf-8") as f:
        f.write(csv_text(table_rows(sweep, rows, exact=True)))
    print_table(table_rows(sweep, rows, exact=False))
    counts = {}
    for r in rows:
        counts[r["status"]] = counts.get(r["status"], 0) + 1
    summary = ", ".join(f"{v} {k}" for k, v in counts.items())
    print(f"{PROG}: {sweep['name']}: {len(rows)} points: {summary}; table {csv_path}")
    if not args.no_plot:
        png = os.path.join(out_dir, "heatmap.png")
        if plot_heatmaps(sweep, rows, png):
            print(f"{PROG}: heat maps {png}")
        else:
            print(f"{PROG}: no numeric metric to plot")
    for m in missing:
        print(f"{PROG}: error: {m}: no such key in the run's JSON metrics", file=sys.stderr)
    return 1 if missing else 0


def main(argv):
    p = argparse.ArgumentParser(prog="sweep.py", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    e = sub.add_parser("expand", help="write OUT_DIR/jobs.txt and OUT_DIR/points.csv")
    e.add_argument("sweep")
    e.add_argument("out_dir")
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    e.add_argument("--pmsm-sim", default=os.path.join(repo, "build/host/host_sim/cli/pmsm-sim"),
                   help="the pmsm-sim the jobs run (default: build/host's)")
    c = sub.add_parser("collect", help="write OUT_DIR/results.csv and OUT_DIR/heatmap.png")
    c.add_argument("sweep")
    c.add_argument("out_dir")
    c.add_argument("--no-plot", action="store_true", help="no heat maps (no matplotlib needed)")
    args = p.parse_args(argv)
    try:
        return cmd_expand(args) if args.command == "expand" else cmd_collect(args)
    except SweepError as err:
        where = "" if isinstance(err, UsageError) else args.sweep
        print(f"{PROG}: error: {where + ': ' if where else ''}{err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
