#!/usr/bin/env bash
# Run a command where SocketCAN works: natively when this kernel can give a
# vcan0 (it exists and is up, or `ip link add dev vcan0 type vcan` works),
# else inside a small QEMU VM (TCG) with a Debian kernel that has CAN, the
# host's root shared read-only, the output directory writable at its own
# path, and vcan0 up. Prints the command's stdout and stderr and exits with
# its status.
#
# usage: tools/vm/run.sh [options] [--] COMMAND
#   COMMAND        one string, run as `sh -c COMMAND` in the current directory
#                  with the current environment (exported variables; in the VM
#                  also PMSM_VM=1)
#   --out DIR      the directory the command may write (created; default: a
#                  temporary one, removed afterwards); in the VM the rest of the
#                  host's file system is read-only (plus a tmpfs /tmp)
#   --timeout S    limit for the whole run, VM boot included (default 300)
#   --vm | --native  force the VM / the host (default: the host when it can)
#   --smp N, --mem MB  the VM's vCPUs (default 2) and memory (default 1024)
#   --icount SHIFT the VM's clocks count instructions (QEMU -icount, one
#                  guest instruction = 2^SHIFT ns, idle time in real time):
#                  the host's scheduling no longer shows in the guest's time.
#                  One vCPU (QEMU 7.2 does not bring up a second one under
#                  -icount; the Linux boot stops in SMP bring-up)
#   --gpio-sim     a simulated GPIO chip in the VM (implies --vm): the kernel's
#                  gpio-sim module, built once into the cache
#                  (tools/vm/gpio_sim_build.sh), with one chip of 8 lines made
#                  through configfs; the command gets PMSM_GPIO_SIM_CHIP (its
#                  /dev/gpiochipN), PMSM_GPIO_SIM_SYSFS (its sysfs directory:
#                  sim_gpioK/pull sets line K's level unless the line is an
#                  output, sim_gpioK/value reads it) and PMSM_GPIO_SIM_LINES;
#                  configfs is mounted at /sys/kernel/config
#   --prepare      only build the cache (kernel + initramfs) and stop
#   --verbose      say which path runs, the cache, and the VM's boot time
#
# Cache: $PMSM_VM_CACHE, else ${XDG_CACHE_HOME:-$HOME/.cache}/pmsm-drive-vm
# (without a home: ${TMPDIR:-/tmp}/pmsm-drive-vm-<uid>):
# the kernel of the version the mirror's linux-image-amd64 metapackage
# depends on (apt-cache; `apt-get download` + `dpkg -x`, never installed),
# only its vmlinuz and the modules the VM needs kept, and the busybox
# initramfs built from tools/vm/init.sh. Needs qemu-system-x86_64,
# busybox (static), cpio, gzip, depmod/modprobe (kmod), apt-get and dpkg
# (tools/setup.sh installs them). With --gpio-sim also the modules of
# tools/vm/gpio_sim_build.sh (downloaded and built once, about 30 s) and an
# initramfs with them.
#
# Exit status: the command's; 124 when the time limit ends the run; 125 when
# the VM cannot be prepared or ends without the command's status.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
me="tools/vm/run.sh"

out= timeout_s=300 force= icount= smp=2 smp_set=0 mem=1024 prepare_only=0 verbose=0 gpio_sim=0
while [ $# -gt 0 ]; do
    case "$1" in
    --out) out=$2; shift 2 ;;
    --timeout) timeout_s=$2; shift 2 ;;
    --vm) force=vm; shift ;;
    --native) force=native; shift ;;
    --smp) smp=$2; smp_set=1; shift 2 ;;
    --icount) icount=$2; shift 2 ;;
    --mem) mem=$2; shift 2 ;;
    --prepare) prepare_only=1; shift ;;
    --gpio-sim) gpio_sim=8; shift ;;
    --verbose) verbose=1; shift ;;
    -h | --help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --) shift; break ;;
    -*) echo "$me: unknown option $1 (--help)" >&2; exit 2 ;;
    *) break ;;
    esac
done
if [ $prepare_only = 0 ] && [ $# -ne 1 ]; then
    echo "$me: expected one COMMAND string (--help)" >&2
    exit 2
fi
cmd=${1-}
case "$timeout_s" in '' | *[!0-9]*) echo "$me: --timeout takes whole seconds" >&2; exit 2 ;; esac
case "$icount" in '' | [0-9]) ;; *) echo "$me: --icount takes a shift 0..9" >&2; exit 2 ;; esac
if [ -n "$icount" ]; then
    [ "$smp_set" = 0 ] || [ "$smp" = 1 ] || { echo "$me: --icount runs one vCPU (--smp 1)" >&2; exit 2; }
    smp=1
fi
if [ $gpio_sim != 0 ]; then
    [ "$force" != native ] || { echo "$me: --gpio-sim runs in the VM (not with --native)" >&2; exit 2; }
    force=vm
fi

die() { echo "$me: $*" >&2; exit 125; }
say() { [ $verbose = 0 ] || echo "$me: $*" >&2; }
need() {
    local t
    for t in "$@"; do
        command -v "$t" >/dev/null 2>&1 ||
            [ -x "/usr/sbin/$t" ] || [ -x "/sbin/$t" ] ||
            die "$t is missing (tools/setup.sh installs the VM runner's packages: qemu-system-x86 busybox-static cpio kmod)"
    done
}
export PATH="$PATH:/usr/sbin:/sbin"

# ---- the native path ---------------------------------------------------
native_ok() {
    if ip link show vcan0 >/dev/null 2>&1; then
        ip -d link show vcan0 2>/dev/null | grep -q ' vcan ' &&
            ip link show vcan0 | grep -q '[<,]UP[,>]'
        return
    fi
    ip link add dev vcan0 type vcan >/dev/null 2>&1 && ip link set up vcan0
}
if [ "$force" != vm ] && [ $prepare_only = 0 ]; then
    if [ "$force" = native ] || native_ok; then
        say "this kernel has vcan0: running natively"
        if [ -n "$out" ]; then mkdir -p "$out"; fi
        set +e
        timeout --kill-after=10 "$timeout_s" sh -c "$cmd"
        rc=$?
        [ $rc = 124 ] && echo "$me: the run took over $timeout_s s (--timeout)" >&2
        exit $rc
    fi
fi

# ---- the cache: kernel and initramfs -----------------------------------
need qemu-system-x86_64 busybox cpio gzip depmod modprobe apt-cache apt-get dpkg timeout
if [[ -n ${PMSM_VM_CACHE:-} ]]; then
  cache=$PMSM_VM_CACHE
elif [[ -n ${XDG_CACHE_HOME:-} || -n ${HOME:-} ]]; then
  cache=${XDG_CACHE_HOME:-$HOME/.cache}/pmsm-drive-vm
else
  cache=${TMPDIR:-/tmp}/pmsm-drive-vm-$(id -u)  # no home: a per-user temporary cache
fi
mkdir -p "$cache" || die "cannot create the cache $cache"
say "cache $cache"

kver=$(apt-cache depends linux-image-amd64 2>/dev/null |
    sed -n 's/^ *Depends: linux-image-\([0-9].*-amd64\)$/\1/p' | head -n 1 || true)
if [ -z "$kver" ]; then
    # no package lists: the newest kernel already in the cache
    kver=$(ls -d "$cache"/kernel-*/ 2>/dev/null | sed 's|.*/kernel-\(.*\)/$|\1|' | sort -V | tail -n 1)
    [ -n "$kver" ] || die "apt-cache knows no linux-image-amd64 (apt-get update?) and the cache $cache has no kernel"
fi
kdir=$cache/kernel-$kver
# the modules the VM needs, in load order (modprobe --show-depends)
wanted="can can_raw vcan 9p 9pnet_virtio virtio_pci"
if [ ! -f "$kdir/vmlinuz" ]; then
    say "preparing kernel $kver"
    tmp=$(mktemp -d "$cache/.kernel.XXXXXX")
    trap 'rm -rf "$tmp"' EXIT
    (cd "$tmp" && apt-get download "linux-image-$kver" >"$tmp/apt.log" 2>&1) ||
        { cat "$tmp/apt.log" >&2; die "apt-get download linux-image-$kver failed"; }
    dpkg -x "$tmp"/linux-image-"$kver"_*.deb "$tmp/x" || die "dpkg -x of linux-image-$kver failed"
    mdir=$(ls -d "$tmp"/x/{usr/,}lib/modules/"$kver" 2>/dev/null | head -n 1 || true)
    [ -n "$mdir" ] || die "linux-image-$kver has no modules directory"
    root=${mdir%/lib/modules/$kver}
    depmod -b "$root" "$kver" || die "depmod on linux-image-$kver failed"
    mkdir -p "$tmp/k/modules"
    : >"$tmp/k/modules.order"
    # shellcheck disable=SC2086
    modprobe -d "$root" -S "$kver" --show-depends -a $wanted >"$tmp/deps" ||
        die "modprobe --show-depends $wanted failed for $kver"
    while read -r verb path _; do
        [ "$verb" = insmod ] || continue
        name=$(basename "$path")
        case "$name" in
        *.ko) cp "$path" "$tmp/k/modules/$name" ;;
        *.ko.xz) xz -dc "$path" >"$tmp/k/modules/${name%.xz}" ;;
        *.ko.zst) zstd -qdc "$path" >"$tmp/k/modules/${name%.zst}" ;;
        *) die "unexpected module file $name" ;;
        esac
        name=${name%.ko*}
        grep -qx "$name" "$tmp/k/modules.order" || echo "$name" >>"$tmp/k/modules.order"
    done <"$tmp/deps"
    cp "$tmp/x/boot/vmlinuz-$kver" "$tmp/k/vmlinuz" || die "linux-image-$kver has no vmlinuz"
    rm -rf "$kdir"
    mv "$tmp/k" "$kdir"
    rm -rf "$tmp"
    trap - EXIT
fi

# --gpio-sim: the simulator's modules (built once per kernel and builder)
# and an initramfs of its own with them
moddirs=("$kdir")
variant=
if [ $gpio_sim != 0 ]; then
    gdir=$kdir/gpio-sim
    builder_id=$(sha256sum "$here/gpio_sim_build.sh" | cut -c1-16)
    if [ "$(cut -d' ' -f2 "$gdir/version" 2>/dev/null)" != "$builder_id" ]; then
        say "building the gpio-sim modules for $kver"
        "$here/gpio_sim_build.sh" "$kver" "$gdir" || die "cannot build gpio-sim for $kver (above)"
    fi
    moddirs+=("$gdir")
    variant=gpiosim-
fi

busybox=$(command -v busybox)
bb_id=$(ls -lL "$busybox" | awk '{print $5}')
order=()
for d in "${moddirs[@]}"; do order+=("$d/modules.order"); done
initrd_id=$( (cat "$here/init.sh" "${order[@]}"; echo "$bb_id"; [ -z "$variant" ] || cat "$gdir/version") |
    sha256sum | cut -c1-16)
initrd=$cache/initrd-$variant$kver-$initrd_id.cpio.gz
if [ ! -f "$initrd" ]; then
    say "building the initramfs"
    ldd "$busybox" >/dev/null 2>&1 && die "$busybox is not static (install busybox-static)"
    tmp=$(mktemp -d "$cache/.initrd.XXXXXX")
    trap 'rm -rf "$tmp"' EXIT
    mkdir -p "$tmp/r/bin" "$tmp/r/proc" "$tmp/r/sys" "$tmp/r/dev" "$tmp/r/modules"
    cp "$busybox" "$tmp/r/bin/busybox"
    for a in sh mount insmod ip mkdir cat chroot mv sync poweroff echo ls; do
        ln -s busybox "$tmp/r/bin/$a"
    done
    cp "$here/init.sh" "$tmp/r/init"
    chmod 755 "$tmp/r/init"
    cp "$kdir"/modules/*.ko "$tmp/r/modules/"
    [ -z "$variant" ] || cp "$gdir"/*.ko "$tmp/r/modules/"
    cat "${order[@]}" >"$tmp/r/modules.order"
    (cd "$tmp/r" && find . | LC_ALL=C sort | cpio -o -H newc --quiet | gzip -1) >"$tmp/initrd" ||
        die "cpio of the initramfs failed"
    rm -f "$cache"/initrd-"$variant$kver"-*.cpio.gz
    mv "$tmp/initrd" "$initrd"
    rm -rf "$tmp"
    trap - EXIT
fi
[ $prepare_only = 1 ] && { say "kernel $kver, $initrd"; exit 0; }

# ---- the run directory ----------------------------------------------------
if [ -n "$out" ]; then
    mkdir -p "$out" || die "cannot create $out"
    out=$(cd "$out" && pwd -P)
    keep=1
else
    out=$(mktemp -d "${TMPDIR:-/tmp}/pmsm-vm.XXXXXX")
    out=$(cd "$out" && pwd -P)
    keep=0
fi
run=$out/.vm
rm -rf "$run"
mkdir -p "$run"
cleanup() {
    [ -z "${qemu_pid-}" ] || kill "$qemu_pid" 2>/dev/null || true
    if [ $keep = 0 ]; then rm -rf "$out"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM HUP
printf '%s\n' "$out" >"$run/outdir"
[ $gpio_sim = 0 ] || echo "$gpio_sim" >"$run/gpio_sim"
pwd=$(pwd -P)
# a tmpfs over /tmp hides the host's /tmp: not when the checkout or the
# caller's directory is there
case "$repo/ $pwd/" in
/tmp/* | */\ /tmp/*) echo 0 >"$run/tmpfs_tmp" ;;
*) echo 1 >"$run/tmpfs_tmp" ;;
esac
q() { printf "'%s'" "$(printf '%s' "$1" | sed "s/'/'\\\\''/g")"; }
{
    echo 'cat /proc/uptime >"$(dirname "$0")/uptime"'
    while IFS= read -r -d '' kv; do
        name=${kv%%=*}
        case "$name" in
        PWD | OLDPWD | SHLVL | _ | *[!A-Za-z0-9_]* | [0-9]*) continue ;;
        esac
        printf 'export %s=%s\n' "$name" "$(q "${kv#*=}")"
    done < <(env -0)
    [ "$(cat "$run/tmpfs_tmp")" = 1 ] || echo 'export TMPDIR=/dev/shm'
    echo 'export PMSM_VM=1'
    [ $gpio_sim = 0 ] || echo '. "$(dirname "$0")/gpio_sim.env" || exit 125'
    printf 'cd %s || exit 125\n' "$(q "$pwd")"
    printf 'exec /bin/sh -c %s\n' "$(q "$cmd")"
} >"$run/guest.sh"

# ---- the VM -----------------------------------------------------------------
esc() { printf '%s' "${1//,/,,}"; }
say "booting kernel $kver (TCG${icount:+, icount shift $icount}, $smp vCPUs, $mem MB)"
if [ -n "$icount" ]; then
    accel=(-accel tcg,thread=single -icount "shift=$icount,sleep=on,align=off")
else
    accel=(-accel tcg,thread=multi)
fi
t0=$(date +%s.%N)
set +e
timeout --kill-after=10 "$timeout_s" qemu-system-x86_64 \
    "${accel[@]}" -smp "$smp" -m "$mem" -nodefaults -no-reboot \
    -display none -monitor none -serial "file:$run/console.log" \
    -kernel "$kdir/vmlinuz" -initrd "$initrd" \
    -append "console=ttyS0 quiet loglevel=3 panic=-1" \
    -virtfs "local,path=/,mount_tag=hostroot,security_model=none,readonly=on,multidevs=remap" \
    -virtfs "local,path=$(esc "$out"),mount_tag=out,security_model=none,multidevs=remap" \
    >"$run/qemu.log" 2>&1 &
qemu_pid=$!
wait $qemu_pid
qrc=$?
qemu_pid=
set -e
t1=$(date +%s.%N)
if [ -f "$run/status" ]; then
    cat "$run/stdout"
    cat "$run/stderr" >&2
    rc=$(cat "$run/status")
    if [ $verbose = 1 ]; then
        up=$(cut -d' ' -f1 "$run/uptime" 2>/dev/null || echo '?')
        say "command status $rc; VM $(echo "$t1 - $t0" | bc) s wall, command started at guest uptime $up s"
    fi
    exit "$rc"
fi
[ -f "$run/stdout" ] && cat "$run/stdout"
[ -f "$run/stderr" ] && cat "$run/stderr" >&2
if [ $qrc = 124 ] || [ $qrc = 137 ]; then
    echo "$me: the VM run took over $timeout_s s (--timeout); console:" >&2
    tail -n 30 "$run/console.log" >&2
    exit 124
fi
echo "$me: the VM ended (qemu status $qrc) without the command's status; qemu said:" >&2
cat "$run/qemu.log" >&2
echo "$me: console (last 30 lines):" >&2
tail -n 30 "$run/console.log" >&2
exit 125
