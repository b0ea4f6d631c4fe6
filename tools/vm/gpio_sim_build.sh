#!/usr/bin/env bash
# Builds the GPIO simulator (gpio-sim: simulated GPIO chips, created through
# configfs, their lines set through sysfs) as out-of-tree modules for a Debian
# kernel whose config does not have it (CONFIG_GPIO_SIM), for the VM runner
# (tools/vm/run.sh --gpio-sim; it calls this script once per kernel and keeps
# the result in its cache).
#
# usage: tools/vm/gpio_sim_build.sh KVER DEST
#   KVER  the kernel's release (e.g. 6.1.0-56-amd64; its linux-image-KVER
#         package must be known to apt-cache)
#   DEST  the directory to create: configfs.ko (from linux-image-KVER; the
#         simulator's configfs interface), irq_sim.ko (built: the interrupt
#         simulator, kernel/irq/irq_sim.c, when the kernel lacks
#         CONFIG_IRQ_SIM), gpio-sim.ko (built), modules.order (load order),
#         version (the package version and this script's hash)
#
# How: `apt-get download` (never installed) of linux-image-KVER (configfs.ko
# only), linux-headers-KVER with the packages it depends on
# (linux-headers-*-common, linux-kbuild-*) and linux-source-X.Y, all of the
# same package version; `dpkg -x` of the headers and kbuild packages into one
# temporary root (the headers' relative symlinks to kbuild then resolve; the
# Makefile's absolute include is pointed into that root), and from the
# source tarball only drivers/gpio/gpio-sim.c, drivers/gpio/gpiolib.h and
# kernel/irq/irq_sim.c. Then `make -C <headers> M=<dir> modules` with the
# compiler Debian built the kernel with (its headers say which). The
# modules are not signed: the kernel loads them (tainted) unless it has
# CONFIG_MODULE_SIG_FORCE, checked here.
#
# irq_sim.c as a module needs two changes, made here and checked: its
# handler calls irq_to_desc(), which the kernel does not export, through
# generic_handle_irq() instead (the same: the descriptor's handler, set to
# handle_simple_irq by irq_sim's own map callback), and a MODULE_LICENSE.
#
# Needs apt-get, apt-cache, dpkg, dpkg-deb, tar, xz, make, the compiler
# (gcc-N), strip and libelf (objtool); tools/setup.sh installs them.
# Downloads about 225 MB (linux-source is 140 MB of it); the temporary files
# are removed. Prints nothing on success; on failure the reason on stderr,
# exit status 1.
set -euo pipefail

me="tools/vm/gpio_sim_build.sh"
die() { echo "$me: $*" >&2; exit 1; }
[ $# = 2 ] || die "usage: $me KVER DEST"
kver=$1 dest=$2
self_id=$(sha256sum "${BASH_SOURCE[0]}" | cut -c1-16)

for t in apt-get apt-cache dpkg dpkg-deb tar xz make strip sha256sum; do
    command -v "$t" >/dev/null 2>&1 || die "$t is missing (tools/setup.sh installs it)"
done

# the package version of linux-image-KVER: the headers, kbuild and source
# packages must have the same one
ver=$(apt-cache show --no-all-versions "linux-image-$kver" 2>/dev/null | sed -n 's/^Version: //p' |
    head -n 1 || true)
[ -n "$ver" ] || die "apt-cache knows no linux-image-$kver (apt-get update?)"
deps_of() {
    { apt-cache show --no-all-versions "$1=$ver" 2>/dev/null || true; } | sed -n 's/^Depends: //p' |
        head -n 1 | tr ',' '\n' | sed 's/^ *//; s/ .*//'
}
hdr=linux-headers-$kver
common=$(deps_of "$hdr" | grep '^linux-headers-.*-common$' | head -n 1 || true)
kbuild=$(deps_of "$hdr" | grep '^linux-kbuild-' | head -n 1 || true)
[ -n "$common" ] && [ -n "$kbuild" ] ||
    die "cannot tell the packages $hdr=$ver depends on (linux-headers-*-common, linux-kbuild-*)"
upstream=${ver%%-*}                                   # 6.1.192
src=linux-source-$(echo "$upstream" | cut -d. -f1,2) # linux-source-6.1

parent=$(dirname "$dest")
mkdir -p "$parent" || die "cannot create $parent"
tmp=$(mktemp -d "$parent/.gpio-sim.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

pkgs=("linux-image-$kver=$ver" "$hdr=$ver" "$common=$ver" "$kbuild=$ver" "$src=$ver")
(cd "$tmp" && apt-get download "${pkgs[@]}" >"$tmp/apt.log" 2>&1) || {
    cat "$tmp/apt.log" >&2
    die "apt-get download ${pkgs[*]} failed"
}
deb() { ls "$tmp/$1"_*.deb 2>/dev/null | head -n 1; }

# the headers and kbuild in one root
root=$tmp/root
for p in "$hdr" "$common" "$kbuild"; do
    dpkg -x "$(deb "$p")" "$root" || die "dpkg -x of $p failed"
done
kdir=$root/usr/src/$hdr
[ -f "$kdir/.config" ] || die "$hdr has no .config"
sed -i "s|^include /usr/src/|include $root/usr/src/|" "$kdir/Makefile"
[ -f "$(sed -n 's/^include //p' "$kdir/Makefile")" ] ||
    die "the Makefile of $hdr does not include its common headers' Makefile as expected"
conf() { sed -n "s/^CONFIG_$1=//p" "$kdir/.config"; }
[ -z "$(conf GPIO_SIM)" ] ||
    die "linux-image-$kver has gpio-sim (CONFIG_GPIO_SIM=$(conf GPIO_SIM)): this is for kernels without"
[ "$(conf MODULE_SIG_FORCE)" != y ] ||
    die "linux-image-$kver only loads signed modules (CONFIG_MODULE_SIG_FORCE)"
[ "$(conf GPIOLIB)" = y ] && [ "$(conf GPIO_CDEV)" = y ] ||
    die "linux-image-$kver has no GPIO character device (CONFIG_GPIOLIB, CONFIG_GPIO_CDEV)"
cc=$(sed -n 's/^CC = .*)\(gcc-[0-9]*\)$/\1/p' "$kdir/.kernelvariables" 2>/dev/null || true)
if [ -n "$cc" ] && ! command -v "$cc" >/dev/null 2>&1; then
    die "$cc (the compiler of linux-image-$kver) is missing"
fi

# configfs from the image: a module, or built in
case "$(conf CONFIGFS_FS)" in
y) mods=() ;;
m)
    dpkg-deb --fsys-tarfile "$(deb "linux-image-$kver")" |
        tar -x -C "$tmp" --wildcards "*/lib/modules/$kver/kernel/fs/configfs/configfs.ko*" ||
        die "linux-image-$kver: cannot extract configfs.ko"
    f=$(find "$tmp" -path "*/lib/modules/$kver/kernel/fs/configfs/configfs.ko*" | head -n 1)
    case "$f" in
    *.ko) mv "$f" "$tmp/configfs.ko" ;;
    *.ko.xz) xz -dc "$f" >"$tmp/configfs.ko" ;;
    *.ko.zst) zstd -qdc "$f" >"$tmp/configfs.ko" ;;
    *) die "linux-image-$kver has no configfs module" ;;
    esac
    mods=(configfs)
    ;;
*) die "linux-image-$kver has no configfs (CONFIG_CONFIGFS_FS)" ;;
esac

# the sources: three files of the tarball
m=$tmp/m
mkdir -p "$m"
want=(drivers/gpio/gpio-sim.c drivers/gpio/gpiolib.h)
[ "$(conf IRQ_SIM)" = y ] || want+=(kernel/irq/irq_sim.c)
dpkg-deb --fsys-tarfile "$(deb "$src")" | tar -xO --wildcards "*/usr/src/$src.tar.xz" | xz -dc |
    tar -x -C "$tmp" --wildcards "${want[@]/#/*/}" ||
    die "$src=$ver: cannot extract ${want[*]} from usr/src/$src.tar.xz"
for f in "${want[@]}"; do
    cp "$tmp/$src/$f" "$m/" || die "$src has no $f"
done
if [ -f "$m/irq_sim.c" ]; then
    sed -i 's/handle_simple_irq(irq_to_desc(irqnum));/generic_handle_irq(irqnum);/' "$m/irq_sim.c"
    grep -q 'generic_handle_irq(irqnum);' "$m/irq_sim.c" && ! grep -q 'irq_to_desc' "$m/irq_sim.c" ||
        die "$src: kernel/irq/irq_sim.c is not as expected (its handler's irq_to_desc call)"
    printf '\n%s\n%s\n' 'MODULE_DESCRIPTION("Interrupt simulator (kernel/irq/irq_sim.c, out of tree)");' \
        'MODULE_LICENSE("GPL");' >>"$m/irq_sim.c"
    mods+=(irq_sim)
fi
mods+=(gpio-sim)
echo "obj-m := $(printf '%s.o ' "${mods[@]}" | sed 's/configfs\.o //')" >"$m/Kbuild"
make -C "$kdir" M="$m" modules >"$tmp/make.log" 2>&1 || {
    tail -n 40 "$tmp/make.log" >&2
    die "make -C $hdr M=... modules failed (log above)"
}
mkdir -p "$tmp/out"
for n in "${mods[@]}"; do
    f=$m/$n.ko
    [ "$n" = configfs ] && f=$tmp/configfs.ko
    [ -f "$f" ] || die "no $n.ko after the build"
    if [ "$n" = configfs ]; then
        cp "$f" "$tmp/out/$n.ko" # as shipped (signed)
    else
        strip --strip-debug -o "$tmp/out/$n.ko" "$f" || die "strip of $n.ko failed"
    fi
    echo "$n" >>"$tmp/out/modules.order"
done
echo "$ver $self_id" >"$tmp/out/version"
rm -rf "$dest"
mv "$tmp/out" "$dest"
