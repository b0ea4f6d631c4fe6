#!/usr/bin/env bash
# Installs everything the project needs on a Debian 12 machine:
#  - Debian packages (compilers, cmocka, cJSON, QEMU, GNU parallel, clang
#    for the libFuzzer harness, can-utils, what tools/vm/gpio_sim_build.sh
#    builds a kernel module with, ...)
#  - a Python virtual environment in .venv/ with the PyPI packages of tools/
# Idempotent: prints nothing and changes nothing when all is present.
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

debian_packages=(
  cmake ninja-build gcc pkg-config clang-format
  gcc-arm-none-eabi libnewlib-arm-none-eabi binutils-arm-none-eabi
  libcmocka-dev libcjson-dev
  qemu-system-arm
  python3-venv
  parallel
  clang libclang-rt-14-dev
  can-utils
  qemu-system-x86 busybox-static cpio kmod
  make libelf1 xz-utils
)
# From bookworm-backports (the v2 API of libgpiod: 2.1.3; bookworm has 1.6).
backports_packages=(libgpiod-dev gpiod)

missing=()
for p in "${debian_packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]})); then
  if [[ $(id -u) -eq 0 ]]; then
    sudo=()
  elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
    sudo=(sudo -n)
  else
    echo "setup: missing Debian packages: ${missing[*]}" >&2
    echo "setup: run this script as root (or with passwordless sudo) to install them" >&2
    exit 1
  fi
  echo "setup: installing ${missing[*]}"
  "${sudo[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# libgpiod v2 from bookworm-backports (the same mirror, another suite)
gpiod_v2() { pkg-config --atleast-version=2 libgpiod 2>/dev/null; }
if ! gpiod_v2; then
  if [[ $(id -u) -eq 0 ]]; then
    sudo=()
  elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
    sudo=(sudo -n)
  else
    echo "setup: libgpiod v2 (bookworm-backports) missing; run this script as root" >&2
    exit 1
  fi
  list=/etc/apt/sources.list.d/bookworm-backports.sources
  if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    echo "setup: adding the bookworm-backports suite ($list)"
    printf 'Types: deb\nURIs: http://deb.debian.org/debian\nSuites: bookworm-backports\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' |
      "${sudo[@]}" tee "$list" >/dev/null
  fi
  echo "setup: installing ${backports_packages[*]} from bookworm-backports"
  "${sudo[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends \
    -t bookworm-backports "${backports_packages[@]}" >/dev/null
fi

# Python tools (plots, CAN telemetry) live in a virtual environment.
venv="$repo/.venv"
requirements="$repo/tools/requirements.txt"
stamp="$venv/.requirements.installed"
if [[ ! -x "$venv/bin/python" ]]; then
  echo "setup: creating Python virtual environment in .venv"
  python3 -m venv "$venv"
fi
if [[ ! -f "$stamp" ]] || ! cmp -s "$requirements" "$stamp"; then
  echo "setup: installing Python packages from tools/requirements.txt"
  "$venv/bin/pip" install --quiet --disable-pip-version-check -r "$requirements"
  cp "$requirements" "$stamp"
fi
# The CAN telemetry tool (tools/pmsm_can, console command pmsm-can), from
# the source tree (editable: it reads tools/dbc/pmsm_drive.dbc in place).
if [[ ! -x "$venv/bin/pmsm-can" ]]; then
  echo "setup: installing the pmsm-can tool (tools/pmsm_can)"
  "$venv/bin/pip" install --quiet --disable-pip-version-check --no-deps --no-build-isolation \
    -e "$repo/tools/pmsm_can"
fi
