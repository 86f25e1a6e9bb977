#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Builds the Debian 12 binary packages of nnstreamer-cpp from the Release build tree, with
# debhelper and dpkg-buildpackage (docs/packaging.md), then runs lintian on them.
#
# usage: scripts/package.sh [--no-build] [--no-lintian]
#   --no-build     do not run `cmake --build` first (the tree is known to be up to date)
#   --no-lintian   skip lintian
# env:   NNS_BUILD_DIR (build; configured with CMAKE_INSTALL_PREFIX=/usr, as scripts/setup.sh
#        does), NNS_JOBS (nproc), NNS_DEB_DIR (<build>/deb: where the .deb files go)
# The packages are split by packaging/packages.txt; the version is the project version of the
# top CMakeLists.txt. Exits non-zero when a step fails or lintian reports an error.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${NNS_BUILD_DIR:-$ROOT/build}
JOBS=${NNS_JOBS:-$(nproc 2>/dev/null || echo 2)}
OUT=${NNS_DEB_DIR:-$BUILD_DIR/deb}
do_build=1 do_lintian=1
for a in "$@"; do
  case $a in
    --no-build) do_build=0 ;;
    --no-lintian) do_lintian=0 ;;
    -h | --help)
      sed -n '3,12p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *)
      echo "package.sh: unknown option '$a' (see --help)" >&2
      exit 2
      ;;
  esac
done

say() { printf '[package] %s\n' "$*"; }
fail() {
  printf '[package] FAILED: %s\n' "$1" >&2
  if [[ -n ${2:-} && -f $2 ]]; then
    tail -n 30 "$2" | sed 's/^/    /' >&2
    printf '[package] full log: %s\n' "$2" >&2
  fi
  exit 1
}

for tool in dpkg-buildpackage dh dpkg-architecture cmake python3; do
  command -v $tool >/dev/null || fail "$tool is missing (Debian packages in scripts/deps/packaging.apt)"
done
cache=$BUILD_DIR/CMakeCache.txt
[[ -f $cache ]] || fail "no build tree in $BUILD_DIR (run scripts/setup.sh first)"
cache_var() { sed -n "s/^$1:[A-Z]*=//p" "$cache" | head -n 1; }
prefix=$(cache_var CMAKE_INSTALL_PREFIX)
[[ $prefix == /usr ]] || fail "$BUILD_DIR is configured with CMAKE_INSTALL_PREFIX=$prefix; \
packages need /usr (the plugin's compiled-in paths follow the prefix): \
cmake -DCMAKE_INSTALL_PREFIX=/usr $BUILD_DIR, then build again"
btype=$(cache_var CMAKE_BUILD_TYPE)
[[ $btype == Release ]] || say "warning: $BUILD_DIR is a $btype build, not Release"
[[ $(cache_var NNS_SANITIZE) != ON ]] || fail "$BUILD_DIR is a sanitizer build"
version=$(cache_var CMAKE_PROJECT_VERSION)
[[ -n $version ]] || fail "no CMAKE_PROJECT_VERSION in $cache"
multiarch=$(dpkg-architecture -qDEB_HOST_MULTIARCH)
pymm=$(cache_var NNS_PYTHON_VERSION_MM)
commit=$(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)

t0=$(date +%s)
if ((do_build)); then
  say "building $BUILD_DIR"
  mkdir -p "$OUT"
  cmake --build "$BUILD_DIR" -j"$JOBS" >"$BUILD_DIR/package-build.log" 2>&1 ||
    fail "cmake --build" "$BUILD_DIR/package-build.log"
fi

# dpkg-buildpackage writes the packages beside the source folder: $OUT/src -> $OUT/*.deb.
rm -rf "$OUT"
mkdir -p "$OUT/src"
cp -r "$ROOT/packaging/debian" "$OUT/src/debian"
stage=$OUT/stage
say "staging: DESTDIR=$stage cmake --install $BUILD_DIR"
DESTDIR=$stage cmake --install "$BUILD_DIR" >"$OUT/install.log" 2>&1 ||
  fail "cmake --install" "$OUT/install.log"
packages=$(python3 "$ROOT/packaging/gen-debian.py" --table "$ROOT/packaging/packages.txt" \
  --stage "$stage" --debian "$OUT/src/debian" --version "$version" --multiarch "$multiarch" \
  --python "$pymm" --maintainer "nnstreamer-cpp developers <nnstreamer-cpp@lists.invalid>" \
  --note "Built from commit $commit by scripts/package.sh.") ||
  fail "packaging/packages.txt does not match the installed files (see above)"
printf 'NNS_STAGE := %s\n' "$stage" >>"$OUT/src/debian/nns-vars.mk"
# symbols files for the libraries with versioned SONAMEs in libdir (ML API, nnstreamer-edge), so
# that packages built against them get per-symbol minimum versions; written from this build
# (removed symbols are caught by the abi.symbols test, docs/abi.md), checked by dh_makeshlibs.
for inst in "$OUT"/src/debian/*.install; do
  pkg=$(basename "$inst" .install)
  libs=$(grep -E "^usr/lib/$multiarch/lib[^/]*\.so\.[0-9]" "$inst" || true)
  [[ -n $libs ]] || continue
  args=()
  for l in $libs; do args+=(-e"$stage/$l"); done
  (cd "$OUT/src" && dpkg-gensymbols -q -p"$pkg" -v"$version" -P"$stage" "${args[@]}" \
    -O"debian/$pkg.symbols") || fail "dpkg-gensymbols for $pkg"
done
say "version $version; packages: $packages"

(cd "$OUT/src" && dpkg-buildpackage -b -nc -us -uc -d) >"$OUT/dpkg-buildpackage.log" 2>&1 ||
  fail "dpkg-buildpackage" "$OUT/dpkg-buildpackage.log"
# dpkg-shlibdeps warnings (e.g. a library linked but not used) are in the log.
grep -E 'dpkg-shlibdeps: (warning|error)' "$OUT/dpkg-buildpackage.log" | sort -u | sed 's/^/    /' || true
say "built $(ls "$OUT"/*.deb | wc -l) packages in ${OUT#"$ROOT"/}/ in $(($(date +%s) - t0)) s"

if ((do_lintian)); then
  command -v lintian >/dev/null || fail "lintian is missing (scripts/deps/packaging.apt)"
  changes=$(ls "$OUT"/*.changes)
  rc=0
  lintian --fail-on error --no-tag-display-limit "$changes" >"$OUT/lintian.log" 2>&1 || rc=$?
  errors=$(grep -c '^E: ' "$OUT/lintian.log" || true)
  warnings=$(grep -c '^W: ' "$OUT/lintian.log" || true)
  say "lintian: $errors errors, $warnings warnings (${OUT#"$ROOT"/}/lintian.log; the warnings are explained in docs/packaging.md)"
  grep '^E: ' "$OUT/lintian.log" | sed 's/^/    /' >&2 || true
  ((rc == 0)) || fail "lintian reported errors"
fi
