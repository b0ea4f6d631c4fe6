#!/bin/sh
# /init of the VM runner's initramfs (tools/vm/run.sh copies this file in;
# busybox applets only). Loads the CAN and 9p modules, creates vcan0, mounts
# the host's root read-only (9p tag hostroot) and the run directory writable
# (9p tag out) at its host path, runs the command of the run directory in a
# chroot of the host's root, writes its exit status there and powers off.
# The run directory (out/.vm/) holds outdir and guest.sh (inputs), stdout,
# stderr and status (outputs); with run.sh --gpio-sim also gpio_sim (input:
# the number of lines of a simulated GPIO chip to make) and gpio_sim.env
# (output: the chip's variables, read by guest.sh).
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
fail() {
    echo "pmsm-vm init: $*" >&2
    poweroff -f
}
for m in $(cat /modules.order); do
    insmod "/modules/$m.ko" || fail "insmod $m failed"
done
ip link add dev vcan0 type vcan || fail "cannot create vcan0"
ip link set up vcan0 || fail "cannot bring vcan0 up"
ip link set up lo
# vcan delivers through the per-CPU backlog (1000 frames by default): room
# for bursts of a bus at full load while a CPU is busy
echo 100000 >/proc/sys/net/core/netdev_max_backlog
mkdir -p /out /host
mount -t 9p -o trans=virtio,version=9p2000.L,msize=262144 out /out || fail "9p mount of the output share failed"
mount -t 9p -o trans=virtio,version=9p2000.L,ro,msize=262144 hostroot /host || fail "9p mount of the host root failed"
run=/out/.vm
out=$(cat "$run/outdir")
mount -t proc proc /host/proc
mount -t sysfs sys /host/sys
mount -t devtmpfs dev /host/dev
# a writable /tmp unless the checkout or the caller's directory is there
# (run.sh decides; then TMPDIR is /dev/shm)
[ "$(cat "$run/tmpfs_tmp")" = 1 ] && mount -t tmpfs tmp /host/tmp
mount -t tmpfs run /host/run 2>/dev/null
mkdir -p /host/dev/shm # devtmpfs has no shm directory
mount -t tmpfs shm /host/dev/shm 2>/dev/null
# the output directory at its host path (under /tmp it needs its mount point
# in the tmpfs)
mkdir -p "/host$out" 2>/dev/null
mount -o bind /out "/host$out" || fail "cannot mount the output share at $out"
# run.sh --gpio-sim: one simulated GPIO chip (gpio-sim through configfs,
# Documentation/admin-guide/gpio/gpio-sim.rst of the kernel's source)
if [ -f "$run/gpio_sim" ]; then
    g=/sys/kernel/config/gpio-sim/pmsm
    mount -t configfs configfs /sys/kernel/config || fail "gpio-sim: cannot mount configfs"
    mkdir "$g" "$g/bank0" || fail "gpio-sim: no gpio-sim in configfs (module not loaded?)"
    cat "$run/gpio_sim" >"$g/bank0/num_lines" || fail "gpio-sim: cannot set the number of lines"
    echo 1 >"$g/live" || fail "gpio-sim: the simulated chip does not come up"
    chip=$(cat "$g/bank0/chip_name")
    sysdir=/sys/devices/platform/$(cat "$g/dev_name")/$chip
    [ -c "/host/dev/$chip" ] && [ -d "$sysdir/sim_gpio0" ] ||
        fail "gpio-sim: no /dev/$chip or $sysdir"
    mount -t configfs configfs /host/sys/kernel/config
    {
        echo "export PMSM_GPIO_SIM_CHIP=/dev/$chip"
        echo "export PMSM_GPIO_SIM_SYSFS=$sysdir"
        echo "export PMSM_GPIO_SIM_LINES=$(cat "$g/bank0/num_lines")"
    } >"$run/gpio_sim.env"
fi
# the command (out/.vm/guest.sh, written by run.sh: the caller's directory,
# environment and command)
chroot /host /bin/sh "$out/.vm/guest.sh" >"$run/stdout" 2>"$run/stderr"
echo $? >"$run/status.tmp" && mv "$run/status.tmp" "$run/status"
sync
poweroff -f
