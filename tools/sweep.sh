#!/usr/bin/env bash
# A parameter sweep of pmsm-sim in one command (docs/sweeps.md): expands the
# sweep description into one job per point (OUT_DIR/jobs.txt), runs the jobs
# with GNU parallel on this machine, and collects their JSON metrics into
# OUT_DIR/results.csv (printed as a table) and OUT_DIR/heatmap.png.
#
# usage: tools/sweep.sh SWEEP.json OUT_DIR [BUILD_DIR]
#   BUILD_DIR       the build whose pmsm-sim runs the points (default build/host)
# Environment:
#   PARALLEL_JOBS   jobs at a time (default: nproc)
#   PMSM_SIM_PYTHON the Python of tools/sweep.py (default: the project's .venv)
#
# Exit status: 0 when every point was run and collected, also when some
# points' runs failed (they are rows of the table, with their exit code); 1
# when a metric path is absent from a run's JSON; 2 on a usage error, a bad
# sweep description or a missing tool.
set -euo pipefail

usage="usage: tools/sweep.sh SWEEP.json OUT_DIR [BUILD_DIR]"
[[ $# -ge 2 && $# -le 3 ]] || { echo "$usage" >&2; exit 2; }
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
sweep_file=$1
out_dir=$2
build=${3:-$repo/build/host}
sim="$build/host_sim/cli/pmsm-sim"
python=${PMSM_SIM_PYTHON:-$repo/.venv/bin/python}
jobs=${PARALLEL_JOBS:-$(nproc)}

if ! command -v parallel >/dev/null; then
  echo "sweep: GNU parallel not found: install Debian package parallel: tools/setup.sh does" >&2
  exit 2
fi
die() { echo "sweep: $*" >&2; exit 2; }
[[ -x $sim ]] || die "no pmsm-sim at $sim (build it: cmake --workflow --preset host)"
command -v "$python" >/dev/null || die "no Python at $python (run tools/setup.sh)"
[[ $jobs =~ ^[1-9][0-9]*$ ]] || die "PARALLEL_JOBS: expected a positive integer, found '$jobs'"

"$python" "$repo/tools/sweep.py" expand "$sweep_file" "$out_dir" --pmsm-sim "$sim"
n=$(wc -l <"$out_dir/jobs.txt")
echo "sweep: running $n jobs, $jobs at a time (GNU parallel; log $out_dir/joblog.tsv)"
start=$(date +%s.%N)
# --will-cite: upstream GNU parallel otherwise asks for a citation once per
# user (Debian's package does not); --halt never: every point runs, failed
# ones are reported by collect. Exit status = number of failed jobs: not an
# error of the sweep.
status=0
parallel --will-cite --joblog "$out_dir/joblog.tsv" --halt never -j "$jobs" \
  <"$out_dir/jobs.txt" || status=$?
end=$(date +%s.%N)
echo "sweep: $n jobs in $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.1f", b - a }') s" \
  "wall time ($status failed)"
"$python" "$repo/tools/sweep.py" collect "$sweep_file" "$out_dir"
