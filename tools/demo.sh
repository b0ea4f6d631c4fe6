#!/usr/bin/env bash
# Main job: set up, build the simulator (optimised host build), run the paper
# 001 benchmark scenario closed loop with the baseline FOC, print the metrics
# table and write JSON metrics, a CSV trace and a PNG plot to out/.
# Extra arguments go to `pmsm-sim run` (e.g. --set duration_s=3).
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"
tools/setup.sh
cmake --preset host >/dev/null
cmake --build --preset host --target pmsm-sim >/dev/null
mkdir -p out
scenario=host_sim/scenarios/paper001_benchmark_foc.json
build/host/host_sim/cli/pmsm-sim run "$scenario" \
  --json out/paper001_foc.json --csv out/paper001_foc.csv \
  --plot out/paper001_foc.png "$@"
echo "plot: out/paper001_foc.png  metrics: out/paper001_foc.json  trace: out/paper001_foc.csv"
