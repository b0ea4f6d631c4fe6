#!/bin/sh
# Runs tools/bench_gem.py with gym-electric-motor pinned by
# tools/requirements-bench-gem.txt, installed into a venv under the build
# directory on first use. Usage (from the repository root):
#   tools/bench_gem.sh BUILD_DIR [bench_gem.py options]
set -eu
build=${1:?usage: tools/bench_gem.sh BUILD_DIR [options]}
shift
venv="$build/gem-venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
    "$venv/bin/pip" install -q -r tools/requirements-bench-gem.txt
fi
exec "$venv/bin/python" tools/bench_gem.py "$build/host_sim/cli/pmsm-sim" "$@"
