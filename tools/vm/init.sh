#!/bin/sh
# /init of the VM runner's initramfs (tools/vm/run.sh copies this file in;
# busybox applets only). Loads the CAN and 9p modules, creates vcan0, mounts
# the host's root read-only (9p tag hostroot) and the run directory writable
# (9p tag out) at its host path, runs the command of the run directory in a
# chroot of the host's root, writes its exit status there and powers off.
# The run directory (out/.vm/) holds outdir and guest.sh (inputs), stdout,
# stderr and status (outputs).
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
mount -t tmpfs shm /host/dev/shm 2>/dev/null
# the output directory at its host path (under /tmp it needs its mount point
# in the tmpfs)
mkdir -p "/host$out" 2>/dev/null
mount -o bind /out "/host$out" || fail "cannot mount the output share at $out"
# the command (out/.vm/guest.sh, written by run.sh: the caller's directory,
# environment and command)
chroot /host /bin/sh "$out/.vm/guest.sh" >"$run/stdout" 2>"$run/stderr"
echo $? >"$run/status.tmp" && mv "$run/status.tmp" "$run/status"
sync
poweroff -f
