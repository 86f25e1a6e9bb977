#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# ctest package_install (label package; docs/packaging.md): builds the Debian packages from the
# Release tree (scripts/package.sh: debhelper, lintian without errors), installs them with
# `apt-get install ./*.deb` into a minimal Debian 12 root made by debootstrap (dependencies from
# the Debian mirror this machine's apt uses), runs checks.sh inside it with an empty
# environment (gst-inspect, one pipeline per back end on real models, a custom filter built
# with pkg-config, a C program on the ML API, import nnstreamer), then removes the packages and
# checks that only the conffile /etc/nnstreamer.ini is left, and purges.
# Nothing is installed on this machine: everything happens in <build>/package-test/root.
#
# usage: install_test.sh <source dir> <build dir> <shared dir (../shared)>
# Cached under <build>/package-test/: root/ (the Debian root, made once; the packages'
# dependencies stay installed in it between runs) and archives/ (downloaded .deb files).
# NNS_PACKAGE_ROOT_REBUILD=1 makes the root again; NNS_PACKAGE_REUSE_DEBS=1 installs the packages
# already in <build>/deb instead of building them. Skips (exit 77) when not root, when
# debootstrap is missing or the mirror cannot be reached, or without ../shared/models.
set -euo pipefail
SRC=$1 BUILD=$2 SHARED=$3
WORK=$BUILD/package-test
ROOTFS=$WORK/root
ARCHIVES=$WORK/archives
MODELS=$SHARED/models/upstream
T0=$(date +%s)
lap=$T0
say() { printf '[package-test] %s\n' "$*"; }
phase() {
  local now
  now=$(date +%s)
  say "$1 took $((now - lap)) s"
  lap=$now
}
skip() {
  say "SKIPPED: $*"
  exit 77
}

[[ $(id -u) == 0 ]] || skip "needs root (debootstrap, chroot and mounts for the test root)"
for t in debootstrap chroot unshare mount; do
  command -v $t >/dev/null || skip "$t is missing (scripts/deps/packaging.apt)"
done
for f in models/pytorch_lenet5.pt data/9.raw models/mobilenet_v2_quant.onnx data/orange.png \
  data/orange.raw models/mobilenet_v2_1.0_224_quant.tflite labels/labels.txt \
  models/lenet_iter_9000.caffemodel; do
  [[ -r $MODELS/$f ]] || skip "$MODELS/$f is missing (../shared/models)"
done
[[ -r $BUILD/data/imagenet_labels_1000.txt ]] || skip "$BUILD/data/imagenet_labels_1000.txt is missing"
# A tree configured before scripts/setup.sh chose the prefix /usr cannot be packaged: skipped
# on a developer machine (with the fix), a failure in CI (a fresh tree always has /usr).
prefix=$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$BUILD/CMakeCache.txt")
if [[ $prefix != /usr ]]; then
  why="$BUILD is configured with CMAKE_INSTALL_PREFIX=$prefix; packages need /usr: cmake -DCMAKE_INSTALL_PREFIX=/usr $BUILD, then build again"
  [[ ${CI:-} == true ]] && { say "FAILED: $why"; exit 1; }
  skip "$why"
fi

# In a private mount namespace, the mounts of the root vanish with the process on every exit
# path; the EXIT trap unmounts them too.
if [[ -z ${NNS_PACKAGE_TEST_NS:-} ]]; then
  NNS_PACKAGE_TEST_NS=1 exec unshare --mount --propagation private -- bash "$0" "$@"
fi

# 1. The packages (lintian runs inside: no errors allowed).
DEBS=$BUILD/deb
if [[ ${NNS_PACKAGE_REUSE_DEBS:-0} == 1 && -n $(ls "$DEBS"/*.deb 2>/dev/null) ]]; then
  say "reusing the packages in $DEBS (NNS_PACKAGE_REUSE_DEBS=1)"
else
  bash "$SRC/scripts/package.sh" --no-build
fi
phase "packages"

# 2. The Debian 12 root, made once (debootstrap --variant=minbase).
mirror=$(sed -n 's/^URIs: *\(http[^ ]*\/debian\)\/\{0,1\} *$/\1/p' /etc/apt/sources.list.d/*.sources \
  2>/dev/null | head -n 1)
[[ -n $mirror ]] || mirror=$(sed -n 's/^deb \(\[[^]]*\] \)\{0,1\}\(http[^ ]*\/debian\)\/\{0,1\} bookworm .*/\2/p' \
  /etc/apt/sources.list 2>/dev/null | head -n 1)
[[ -n $mirror ]] || mirror=http://deb.debian.org/debian
security=$(sed -n 's/^URIs: *\(http[^ ]*\/debian-security\)\/\{0,1\} *$/\1/p' \
  /etc/apt/sources.list.d/*.sources 2>/dev/null | head -n 1)
[[ ${NNS_PACKAGE_ROOT_REBUILD:-0} == 0 ]] || rm -rf "$ROOTFS"
mkdir -p "$ARCHIVES/partial"
if [[ ! -f $ROOTFS/.nns-root-ready ]]; then
  rm -rf "$ROOTFS" "$ROOTFS.tmp"
  say "debootstrap --variant=minbase bookworm from $mirror"
  debootstrap --variant=minbase --cache-dir="$ARCHIVES" bookworm "$ROOTFS.tmp" "$mirror" \
    >"$WORK/debootstrap.log" 2>&1 || {
    tail -n 5 "$WORK/debootstrap.log"
    rm -rf "$ROOTFS.tmp"
    skip "debootstrap could not make the Debian 12 root from $mirror ($WORK/debootstrap.log)"
  }
  mv "$ROOTFS.tmp" "$ROOTFS"
  cat >"$ROOTFS/etc/apt/sources.list" <<EOF
deb $mirror bookworm main
deb $mirror bookworm-updates main
EOF
  # The security archive too, when this machine uses one: its libraries may be newer than
  # bookworm's, and the packages' dependencies are computed from this machine's.
  [[ -z $security ]] || echo "deb $security bookworm-security main" >>"$ROOTFS/etc/apt/sources.list"
  # apt in the root keeps no .deb of its own: the archives folder is bind-mounted (cache).
  echo 'Binary::apt::APT::Keep-Downloaded-Packages "true";' >"$ROOTFS/etc/apt/apt.conf.d/90nns-keep"
  touch "$ROOTFS/.nns-root-ready"
  phase "debootstrap"
fi

mounts=()
cleanup() {
  local i
  for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do umount -l "${mounts[i]}" 2>/dev/null || true; done
}
trap cleanup EXIT
bind() {
  mkdir -p "$2"
  mount --bind "$1" "$2"
  mounts+=("$2")
}
mount -t proc proc "$ROOTFS/proc" && mounts+=("$ROOTFS/proc")
bind /dev "$ROOTFS/dev"
bind "$ARCHIVES" "$ROOTFS/var/cache/apt/archives"
cp /etc/resolv.conf "$ROOTFS/etc/resolv.conf" 2>/dev/null || true
in_root() { env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 chroot "$ROOTFS" "$@"; }
apt_root() { in_root env DEBIAN_FRONTEND=noninteractive apt-get -q -o Dpkg::Use-Pty=0 "$@"; }

# 3. Install the packages (and what the checks use: gst-launch, pngdec, a C compiler).
# apt-get update once a day, or when the root's sources changed.
stamp=$WORK/apt-updated
# update_index: apt-get update in the root; when it fails (the mirror or the network) the test
# skips naming the mirror.
update_index() {
  apt_root update >"$WORK/apt-update.log" 2>&1 || {
    tail -n 5 "$WORK/apt-update.log"
    skip "apt-get update failed in the test root ($mirror)"
  }
  touch "$stamp"
}
if [[ ! -f $stamp || $ROOTFS/etc/apt/sources.list -nt $stamp ||
  -n $(find "$stamp" -mmin +1440 2>/dev/null) ]]; then
  update_index
fi
rm -rf "$ROOTFS/tmp/nns-debs" "$ROOTFS/tmp/nns-models" "$ROOTFS/tmp/nns-check"
mkdir -p "$ROOTFS/tmp/nns-debs" "$ROOTFS/tmp/nns-models" "$ROOTFS/tmp/nns-check"
cp "$DEBS"/*.deb "$ROOTFS/tmp/nns-debs/"
for f in models/pytorch_lenet5.pt data/9.raw models/mobilenet_v2_quant.onnx data/orange.png \
  data/orange.raw models/mobilenet_v2_1.0_224_quant.tflite labels/labels.txt; do
  cp "$MODELS/$f" "$ROOTFS/tmp/nns-models/"
done
cp "$BUILD/data/imagenet_labels_1000.txt" "$ROOTFS/tmp/nns-models/"
cp "$MODELS/models/lenet_iter_9000.caffemodel" "$SRC/tests/data/lenet_deploy.prototxt" "$ROOTFS/tmp/nns-models/"
cp "$SRC"/tests/package/{checks.sh,invert_filter.c,ml_api_check.c,invert.lua,invert.py} "$ROOTFS/tmp/nns-check/"
ours=$(cd "$DEBS" && for d in *.deb; do dpkg-deb -f "$d" Package; done | tr '\n' ' ')
# A previous run that stopped half-way may have left them installed.
in_root dpkg --purge $ours >/dev/null 2>&1 || true
debs=()
for d in "$DEBS"/*.deb; do debs+=("/tmp/nns-debs/${d##*/}"); done
install_all() {
  apt_root install -y --no-install-recommends "${debs[@]}" gstreamer1.0-tools \
    gstreamer1.0-plugins-good gcc libc6-dev pkgconf >"$WORK/apt-install.log" 2>&1
}
# A download that failed (the mirror or the network, or an index older than the archive).
download_failed() {
  grep -qE 'Failed to fetch|Temporary failure resolving|Could not connect|Connection failed|Unable to fetch|Hash Sum mismatch' \
    "$WORK/apt-install.log"
}
# A failed download is retried once after apt-get update; when it fails again the test skips
# naming the mirror. Anything else (a dependency that cannot be met, a maintainer script
# failing) is a fault of our packages and fails the test.
installed=0
install_all && installed=1
if ((!installed)) && download_failed; then
  say "apt-get install could not download from $mirror; apt-get update and one more try"
  update_index
  install_all && installed=1
  if ((!installed)) && download_failed; then
    tail -n 30 "$WORK/apt-install.log"
    skip "apt-get install could not download Debian's packages from $mirror twice ($WORK/apt-install.log)"
  fi
fi
if ((!installed)); then
  tail -n 30 "$WORK/apt-install.log"
  say "FAILED: apt-get install ./*.deb in the test root ($WORK/apt-install.log)"
  exit 1
fi
say "installed: $ours"
phase "apt-get install"

# 4. The checks, with an empty environment.
rc=0
env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root chroot "$ROOTFS" /bin/bash /tmp/nns-check/checks.sh || rc=$?
phase "checks"

# 5. apt-get remove: nothing of ours is left but the conffile; then purge removes that too.
in_root sh -c "dpkg-query -L $ours" | sort -u >"$WORK/files.txt"
apt_root remove -y $ours >"$WORK/apt-remove.log" 2>&1 || {
  tail -n 20 "$WORK/apt-remove.log"
  say "FAILED: apt-get remove"
  exit 1
}
left=()
while read -r f; do
  [[ -n $f && $f == /* ]] || continue
  p=$ROOTFS$f
  if [[ -L $p || -f $p ]]; then
    [[ $f == /etc/nnstreamer.ini ]] || left+=("$f")
  elif [[ -d $p && $f == *nnstreamer* ]]; then
    left+=("$f/")
  fi
done <"$WORK/files.txt"
if ((${#left[@]})); then
  say "FAILED: apt-get remove left files of ours behind: ${left[*]}"
  rc=1
else
  [[ -f $ROOTFS/etc/nnstreamer.ini ]] || { say "FAILED: apt-get remove deleted the conffile /etc/nnstreamer.ini"; rc=1; }
  say "check remove: ok (only the conffile /etc/nnstreamer.ini is left)"
fi
# apt-get purge skips packages already removed (only their conffiles left): dpkg --purge.
in_root dpkg --purge $ours >>"$WORK/apt-remove.log" 2>&1 || true
if [[ -e $ROOTFS/etc/nnstreamer.ini ]]; then
  say "FAILED: apt-get purge left /etc/nnstreamer.ini"
  rc=1
else
  say "check purge: ok"
fi
phase "remove + purge"
say "total $(($(date +%s) - T0)) s"
exit $rc
