#!/usr/bin/env bash
# The whole test suite from zero: set-up, the Cortex-M4F build (with its size
# report) and the Cortex-M3 build with their QEMU tests, the STM32F405 port
# (its size report and QEMU smoke test), the host build under ASan+UBSan
# with its tests, then the optimised host build with its tests.
set -euo pipefail
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$repo"
tools/setup.sh
cmake --workflow --preset m4f
cmake --workflow --preset m3
cmake --workflow --preset stm32f405
cmake --workflow --preset host-asan
cmake --workflow --preset host
