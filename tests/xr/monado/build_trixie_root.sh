#!/bin/sh
# SPDX-License-Identifier: MIT
## @brief Builds (or reuses) a Debian trixie root with the Monado OpenXR runtime for headless tests.
##
## Usage: build_trixie_root.sh [--refresh] [DIR]
##   DIR        where the root goes (default: $TELESPHERE_MONADO_ROOT, else <cache>/monado-trixie)
##   --refresh  ignore an existing tree and cached tarball; build from the archive again
## Environment:
##   TELESPHERE_MONADO_CACHE   cache folder outside the repo (default /var/cache/telesphere)
##   TELESPHERE_DEBIAN_MIRROR  Debian mirror (default http://deb.debian.org/debian)
##
## Order: DIR already holds a root for this package set → nothing to do; a cached tarball for the
## package set exists → unpack it (seconds, no root needed); else debootstrap + apt-get install
## (needs root, about 85 s and 160 MB of downloads) and save the tarball (zstd, about 260 MB).
## The cache key is a hash of suite, architecture and package list; the package versions that went
## into a tree are written to DIR/telesphere-monado-versions.txt. See
## tests/xr/monado/README.md and xr/README.md ("OpenXR session").
set -eu

SUITE=trixie
ARCH=amd64
PACKAGES="monado-service libopenxr1-monado libopenxr-loader1 mesa-vulkan-drivers libegl-mesa0 libgl1-mesa-dri libglx-mesa0"
# Bump when the way the tree is made changes (invalidates cached tarballs).
RECIPE=1

say() { printf 'build_trixie_root: %s\n' "$*" >&2; }
die() { say "error: $*"; exit 1; }

REFRESH=0
DIR=
while [ $# -gt 0 ]; do
  case "$1" in
    --refresh) REFRESH=1 ;;
    -h|--help) sed -n 's/^## \{0,1\}//p' "$0"; exit 0 ;;
    -*) die "unknown option '$1' (see --help)" ;;
    *) [ -z "$DIR" ] || die "more than one DIR given"; DIR=$1 ;;
  esac
  shift
done

CACHE=${TELESPHERE_MONADO_CACHE:-/var/cache/telesphere}
MIRROR=${TELESPHERE_DEBIAN_MIRROR:-http://deb.debian.org/debian}
[ -n "$DIR" ] || DIR=${TELESPHERE_MONADO_ROOT:-$CACHE/monado-trixie}
case "$DIR" in /*) ;; *) DIR=$(pwd)/$DIR ;; esac

KEY=$(printf '%s\n' "$RECIPE" "$SUITE" "$ARCH" $PACKAGES | sha256sum | cut -c1-16)
TARBALL=$CACHE/monado-$SUITE-$KEY.tar.zst
STAMP=$DIR/telesphere-monado-key
VERSIONS=telesphere-monado-versions.txt

root_complete() {
  [ -f "$STAMP" ] && [ "$(cat "$STAMP")" = "$KEY" ] &&
    [ -x "$DIR/usr/bin/monado-service" ] && [ -e "$DIR/lib64/ld-linux-x86-64.so.2" ] &&
    [ -e "$DIR/usr/lib/x86_64-linux-gnu/libopenxr_monado.so" ]
}

if [ "$REFRESH" = 0 ] && root_complete; then
  say "root for package set $KEY already at $DIR: nothing to do"
  printf '%s\n' "$DIR"
  exit 0
fi

command -v zstd >/dev/null 2>&1 || die "zstd not found (apt-get install zstd)"

# Partial trees are built beside DIR and moved into place at the end, so DIR is always complete.
WORK=$DIR.partial.$$
cleanup() {
  # Unmount whatever debootstrap or we left mounted in the partial tree before deleting it.
  if [ -d "$WORK" ]; then
    for m in $(awk -v w="$WORK/" 'index($2, w) == 1 { print $2 }' /proc/mounts | sort -r); do
      umount "$m" 2>/dev/null || umount -l "$m" 2>/dev/null || true
    done
  fi
  rm -rf --one-file-system "$WORK" "$WORK.debootstrap.log" "$WORK.apt.log" "$TARBALL.partial.$$" 2>/dev/null || true
}
trap cleanup EXIT
trap 'exit 130' INT TERM

install_tree() {
  if [ -e "$DIR" ]; then
    say "replacing the old tree at $DIR"
    rm -rf "$DIR"
  fi
  mv "$WORK" "$DIR"
}

mkdir -p "$(dirname "$DIR")"

if [ "$REFRESH" = 0 ] && [ -f "$TARBALL" ]; then
  say "unpacking cached $TARBALL into $DIR"
  mkdir -p "$WORK"
  tar -C "$WORK" -I zstd -xf "$TARBALL" || die "could not unpack $TARBALL (delete it to rebuild)"
  printf '%s\n' "$KEY" > "$WORK/telesphere-monado-key"
  install_tree
  root_complete || die "the tree unpacked from $TARBALL is incomplete (delete the tarball to rebuild)"
  say "done: $DIR"
  printf '%s\n' "$DIR"
  exit 0
fi

[ "$(id -u)" = 0 ] || die "no cached tarball at $TARBALL and building one needs root (debootstrap, chroot): run with sudo, or set TELESPHERE_MONADO_CACHE to a folder holding monado-$SUITE-$KEY.tar.zst"
command -v debootstrap >/dev/null 2>&1 || die "debootstrap not found (apt-get install debootstrap)"

say "building the $SUITE root for package set $KEY in $WORK (about 85 s and 160 MB from $MIRROR)"
mkdir -p "$WORK"
say "step 1/4: debootstrap --variant=minbase $SUITE"
debootstrap --variant=minbase --arch="$ARCH" "$SUITE" "$WORK" "$MIRROR" > "$WORK.debootstrap.log" 2>&1 || {
  tail -n 20 "$WORK.debootstrap.log" >&2; rm -f "$WORK.debootstrap.log"; die "debootstrap failed (log above)"; }
rm -f "$WORK.debootstrap.log"

say "step 2/4: apt-get install $PACKAGES"
mount -t proc proc "$WORK/proc" || die "could not mount /proc in the chroot"
chroot "$WORK" /usr/bin/env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin DEBIAN_FRONTEND=noninteractive sh -c \
  "apt-get -q update && apt-get -q install -y --no-install-recommends $PACKAGES && apt-get clean &&
   dpkg-query -W -f '\${Package} \${Version}\n' > /$VERSIONS" > "$WORK.apt.log" 2>&1 || {
  tail -n 30 "$WORK.apt.log" >&2; rm -f "$WORK.apt.log"; die "apt-get in the chroot failed (log above)"; }
rm -f "$WORK.apt.log"
umount "$WORK/proc" || umount -l "$WORK/proc"
rm -rf "$WORK/var/lib/apt/lists/"* "$WORK/var/cache/apt/"*
say "monado: $(grep '^monado-service ' "$WORK/$VERSIONS" || echo '?')"

say "step 3/4: caching the tree as $TARBALL"
if mkdir -p "$CACHE" 2>/dev/null && [ -w "$CACHE" ]; then
  tar -C "$WORK" --one-file-system --exclude='./proc/*' --exclude='./dev/*' \
      -I 'zstd -T0 -3' -cf "$TARBALL.partial.$$" . || die "could not write $TARBALL"
  mv "$TARBALL.partial.$$" "$TARBALL"
else
  say "warning: cache folder $CACHE is not writable; not caching"
fi

say "step 4/4: installing the tree at $DIR"
printf '%s\n' "$KEY" > "$WORK/telesphere-monado-key"
install_tree
root_complete || die "the built tree at $DIR is incomplete"
say "done: $DIR"
printf '%s\n' "$DIR"
