#!/usr/bin/env bash
# Main job (until the simulator lands): build the firmware for the host and the
# Cortex-M4F and print the M4F size report.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"
tools/setup.sh
cmake --preset host >/dev/null
cmake --build --preset host
cmake --preset m4f >/dev/null
cmake --build --preset m4f
