#!/bin/sh
# SPDX-License-Identifier: LGPL-2.1-only
# Builds NNStreamer-style extensions the way a user does: install the tree into a fresh prefix,
# then compile with nothing but that prefix (pkg-config nnstreamer / nnstreamer-single) and a
# plain C compiler. Output: <out>/ext/lib<name>.so custom filters and <out>/ext/caps_main.
#   build_ext.sh <build dir> <source dir of the .c files> <out dir> [no-program]
# "no-program" skips caps_main (sanitizer trees: an uninstrumented program cannot load ASan
# libraries).
set -eu
build=$1 src=$2 out=$3 program=${4:-yes}
prefix=$out/prefix
rm -rf "$out"
mkdir -p "$out/ext"
cmake --install "$build" --prefix "$prefix" >"$out/install.log" 2>&1 ||
  { echo "cmake --install failed:"; tail -20 "$out/install.log"; exit 1; }
pc=$(find "$prefix" -name nnstreamer.pc -path '*/pkgconfig/*' | head -n 1)
[ -n "$pc" ] || { echo "no nnstreamer.pc installed under $prefix"; exit 1; }
PKG_CONFIG_PATH=$(dirname "$pc")${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}
export PKG_CONFIG_PATH
pkg-config --exists nnstreamer-internal || { echo "no nnstreamer-internal.pc installed"; exit 1; }
cflags=$(pkg-config --cflags nnstreamer)
libdir=$(pkg-config --variable=libdir nnstreamer-single)
cc=${CC:-cc}
for f in ext_passthrough ext_passthrough_variable ext_scaler ext_rnn; do
  # shellcheck disable=SC2046,SC2086
  $cc -std=c11 -Wall -Wextra -Werror -fPIC -shared $cflags -o "$out/ext/lib$f.so" "$src/$f.c" \
    $(pkg-config --libs nnstreamer-single) -Wl,-rpath,"$libdir"
  readelf -d "$out/ext/lib$f.so" | grep -q 'NEEDED.*\[libnnstreamer-single.so\]' ||
    { echo "lib$f.so does not list libnnstreamer-single.so in NEEDED"; exit 1; }
done
[ "$program" = no-program ] && { echo "extensions built in $out/ext"; exit 0; }
# A program using the GStreamer-side API links the plugin through libdir/libnnstreamer.so.
# shellcheck disable=SC2046,SC2086
$cc -std=c11 -Wall -Wextra -Werror $cflags -o "$out/ext/caps_main" "$src/caps_main.c" \
  $(pkg-config --libs nnstreamer) -Wl,-rpath,"$libdir"
echo "extensions built in $out/ext against $prefix"
