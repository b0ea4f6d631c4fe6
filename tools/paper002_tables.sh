#!/bin/sh
# Paper 002 bench: runs every host_sim/scenarios/paper002_case{N}_{controller}.json
# that exists (N = 1..4) and prints, per case, the paper's Table I / Table II
# numbers of its four controllers (host_sim/scenarios/reference/paper002_tables.json)
# beside the measured ones of each controller file, with the amplitudes of
# the speed error's disturbance lines (33.3, 66.7, 200, 266.7 Hz at 500 rpm;
# tools/plot_spectrum.py) and writes the spectra as PNGs.
#
# usage: tools/paper002_tables.sh BUILD_DIR [OUT_DIR]
#   BUILD_DIR  a configured and built tree (BUILD_DIR/host_sim/cli/pmsm-sim)
#   OUT_DIR    where the JSON reports, CSV traces and spectrum PNGs go
#              (default: a new temporary directory, printed)
# Python: PMSM_SIM_PYTHON, else the project's .venv (tools/setup.sh).
set -eu
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
    echo "usage: $0 BUILD_DIR [OUT_DIR]" >&2
    exit 2
fi
root=$(cd "$(dirname "$0")/.." && pwd)
sim="$1/host_sim/cli/pmsm-sim"
[ -x "$sim" ] || { echo "$0: no pmsm-sim at $sim (build first)" >&2; exit 2; }
py="${PMSM_SIM_PYTHON:-$root/.venv/bin/python}"
[ -x "$py" ] || { echo "$0: no Python at $py (tools/setup.sh, or set PMSM_SIM_PYTHON)" >&2; exit 2; }
if [ $# -eq 2 ]; then
    out="$2"
    mkdir -p "$out"
else
    out=$(mktemp -d "${TMPDIR:-/tmp}/paper002.XXXXXX")
fi
echo "outputs in $out"
found=0
for n in 1 2 3 4; do
    for f in "$root"/host_sim/scenarios/paper002_case"$n"_*.json; do
        [ -e "$f" ] || continue
        name=$(basename "$f" .json)
        "$sim" run "$f" --json "$out/$name.json" --csv "$out/$name.csv" --quiet
        found=1
    done
done
[ "$found" -eq 1 ] || { echo "$0: no paper002_case*.json scenario" >&2; exit 1; }
exec "$py" "$root/tools/paper002_tables.py" \
    "$root/host_sim/scenarios/reference/paper002_tables.json" "$out"
