#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# One command from a fresh Debian 12 machine to a built tree and a demo run:
#   1. Debian packages listed in scripts/deps/*.apt (skips what is installed already),
#   2. npm packages listed in scripts/deps/*.npm, unpacked into third_party/npm/<name>/,
#   3. cmake configure + build into build/ (Release),
#   4. examples/demo/run_demo.sh.
# Re-running is fast: every step skips work that is already done.
#
# usage: scripts/setup.sh [--no-apt] [--no-npm] [--no-build] [--no-demo]
# env:   NNS_BUILD_DIR (build), NNS_BUILD_TYPE (Release), NNS_JOBS (nproc),
#        NNS_INSTALL_PREFIX (/usr, first configure only; scripts/package.sh needs /usr),
#        NNS_APT_LOCK (/tmp/nns-apt.lock, used with flock when flock exists),
#        NNS_NPM_KEEP_TARBALLS=1 keeps downloaded npm tarballs in third_party/npm/.tarballs/.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BUILD_DIR=${NNS_BUILD_DIR:-$ROOT/build}
BUILD_TYPE=${NNS_BUILD_TYPE:-Release}
JOBS=${NNS_JOBS:-$(nproc 2>/dev/null || echo 2)}
LOG_DIR=$BUILD_DIR/setup-logs
APT_LOCK=${NNS_APT_LOCK:-/tmp/nns-apt.lock}
NPM_DIR=$ROOT/third_party/npm

do_apt=1 do_npm=1 do_build=1 do_demo=1
for arg in "$@"; do
  case $arg in
    --no-apt) do_apt=0 ;;
    --no-npm) do_npm=0 ;;
    --no-build) do_build=0 do_demo=0 ;;
    --no-demo) do_demo=0 ;;
    -h | --help)
      sed -n '3,14p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
      exit 0
      ;;
    *)
      echo "setup.sh: unknown option '$arg' (see --help)" >&2
      exit 2
      ;;
  esac
done

mkdir -p "$LOG_DIR"
t_start=$(date +%s)
step_start=$t_start

say() { printf '[setup] %s\n' "$*"; }
# fail <step> <what went wrong> [log file]: prints the reason and the log's tail, exits 1.
fail() {
  printf '[setup] FAILED in step "%s": %s\n' "$1" "$2" >&2
  if [[ -n ${3:-} && -s $3 ]]; then
    printf '[setup] last lines of %s:\n' "$3" >&2
    tail -n 40 "$3" | sed 's/^/    /' >&2
  fi
  exit 1
}
step() {
  step_start=$(date +%s)
  say "== $*"
}
step_done() { say "   done in $(($(date +%s) - step_start)) s"; }

# Reads a deps list: drops comments and blank lines, trims spaces.
read_list() { sed -e 's/#.*//' -e 's/^[[:space:]]*//' -e 's/[[:space:]]*$//' "$@" | grep -v '^$' || true; }

# Runs a command as root: directly when root, else through sudo (non-interactive in CI).
as_root() {
  if [[ $(id -u) -eq 0 ]]; then
    "$@"
  elif command -v sudo >/dev/null; then
    if [[ -n ${CI:-} ]]; then sudo -n "$@"; else sudo "$@"; fi
  else
    echo "need root for: $* (run as root or install sudo)" >&2
    return 1
  fi
}
# apt-get with the development lock (shared with other engineers) when flock is available, and
# waiting for dpkg's own lock instead of failing when another apt runs.
apt_get() {
  local cmd=(env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=900 "$@")
  if command -v flock >/dev/null && touch "$APT_LOCK" 2>/dev/null; then
    as_root flock -w 1800 "$APT_LOCK" "${cmd[@]}"
  else
    as_root "${cmd[@]}"
  fi
}
# Names of the lists (among $2...) that mention package $1.
lists_with() {
  local p=$1 f out=()
  shift
  for f in "$@"; do read_list "$f" | grep -qxF -- "$p" && out+=("scripts/deps/${f##*/}"); done
  echo "${out[*]:-npm lists}"
}
is_installed() { [[ $(dpkg-query -W -f='${db:Status-Abbrev}' "$1" 2>/dev/null) == ii* ]]; }

# ---------------------------------------------------------------------------------------------
# 1. Debian packages
apt_packages() {
  step "Debian packages (scripts/deps/*.apt)"
  shopt -s nullglob
  local lists=("$ROOT"/scripts/deps/*.apt)
  shopt -u nullglob
  ((${#lists[@]})) || {
    say "   no scripts/deps/*.apt lists"
    return
  }
  local wanted missing=()
  mapfile -t wanted < <(read_list "${lists[@]}" | sort -u)
  # npm lists need npm; Debian's npm package provides it when the machine has none.
  if ((do_npm)) && [[ -n $(npm_lines) ]] && ! command -v npm >/dev/null; then wanted+=(npm); fi
  local p
  for p in "${wanted[@]}"; do is_installed "$p" || missing+=("$p"); done
  if ((${#missing[@]} == 0)); then
    say "   all ${#wanted[@]} packages already installed"
    step_done
    return
  fi
  say "   installing ${#missing[@]} of ${#wanted[@]} packages: ${missing[*]}"
  local log=$LOG_DIR/apt.log
  : >"$log"
  apt_get update -qq >>"$log" 2>&1 ||
    fail "apt-get update" "could not refresh the package lists (network? sources.list?)" "$log"
  if ! apt_get install -y -qq --no-install-recommends "${missing[@]}" >>"$log" 2>&1; then
    # Find out which package is the problem: try them one by one.
    say "   batch install failed; retrying package by package to find the culprit"
    for p in "${missing[@]}"; do
      is_installed "$p" && continue
      local plog=$LOG_DIR/apt-$p.log
      if ! apt_get install -y -qq --no-install-recommends "$p" >"$plog" 2>&1; then
        local why
        why=$(grep -E '^(E:|dpkg: error)' "$plog" | head -n 3 | tr '\n' ' ')
        fail "apt-get install" \
          "package '$p' (from $(lists_with "$p" "${lists[@]}")) failed: ${why:-see the log}" "$plog"
      fi
    done
  fi
  for p in "${missing[@]}"; do
    is_installed "$p" || say "   warning: '$p' is still not listed as installed by dpkg" \
      "(a virtual package? list the real package name so re-runs can skip it)"
  done
  step_done
}

# ---------------------------------------------------------------------------------------------
# 2. npm packages: lines "name@version [sha512-...] [paths to extract...]".
#    The tarball is fetched with `npm pack` (which checks the registry's integrity), its sha512 is
#    compared with the pinned one when the line has one, and it is unpacked (whole, or only the
#    listed paths, relative to the package root) into third_party/npm/<name>/. A stamp file there
#    records the line and the tarball's integrity, so an unchanged line is skipped on re-runs.
npm_lines() {
  shopt -s nullglob
  local lists=("$ROOT"/scripts/deps/*.npm)
  shopt -u nullglob
  ((${#lists[@]})) && read_list "${lists[@]}"
  return 0
}

npm_fetch_one() {
  local line=$1
  local spec integrity="" paths=() tok
  read -r -a toks <<<"$line"
  spec=${toks[0]}
  for tok in "${toks[@]:1}"; do
    if [[ $tok == sha512-* ]]; then integrity=$tok; else paths+=("$tok"); fi
  done
  local name=${spec%@*} version=${spec##*@}
  [[ -n $name && -n $version && $name != "$spec" ]] ||
    fail "npm" "bad line '$line': expected 'name@version [sha512-...] [paths...]'"
  local dest=$NPM_DIR/$name stamp="$NPM_DIR/$name/.nns-stamp"
  local want_stamp="line: $line"
  if [[ -f $stamp ]] && [[ $(head -n 1 "$stamp") == "$want_stamp" ]]; then
    say "   $spec: up to date"
    return
  fi
  local log=$LOG_DIR/npm-${name//\//_}.log tmp
  tmp=$(mktemp -d "$NPM_DIR/.fetch.XXXXXX")
  say "   $spec: fetching"
  if ! (cd "$tmp" && npm pack --json --loglevel=error "$spec" >pack.json 2>"$log"); then
    rm -rf "$tmp"
    fail "npm" "npm pack $spec failed (package or version missing, or no network)" "$log"
  fi
  local tgz got
  tgz=$(node -e 'const j=require(process.argv[1]);process.stdout.write(j[0].filename)' \
    "$tmp/pack.json") || fail "npm" "cannot read npm pack output for $spec" "$log"
  tgz=$tmp/$tgz
  got=$(node -e 'const c=require("crypto"),fs=require("fs");
    process.stdout.write("sha512-"+c.createHash("sha512").update(fs.readFileSync(process.argv[1])).digest("base64"))' "$tgz")
  local reg
  reg=$(node -e 'const j=require(process.argv[1]);process.stdout.write(j[0].integrity||"")' \
    "$tmp/pack.json")
  if [[ -n $reg && $reg != "$got" ]]; then
    rm -rf "$tmp"
    fail "npm" "$spec: tarball sha512 $got differs from the registry's $reg"
  fi
  if [[ -n $integrity && $integrity != "$got" ]]; then
    rm -rf "$tmp"
    fail "npm" "$spec: tarball sha512 $got differs from the pinned $integrity (scripts/deps/*.npm)"
  fi
  rm -rf "$dest"
  mkdir -p "$dest"
  local members=()
  for tok in "${paths[@]}"; do members+=("package/${tok#/}"); done
  if ! tar -xzf "$tgz" -C "$dest" --strip-components=1 --no-same-owner \
    ${members:+--wildcards} "${members[@]}" >>"$log" 2>&1; then
    rm -rf "$tmp" "$dest"
    fail "npm" "$spec: unpacking failed (is every listed path in the package?)" "$log"
  fi
  if [[ -n ${NNS_NPM_KEEP_TARBALLS:-} ]]; then
    mkdir -p "$NPM_DIR/.tarballs" && mv "$tgz" "$NPM_DIR/.tarballs/"
  fi
  rm -rf "$tmp"
  printf '%s\nintegrity: %s\nfetched: %s\n' "$want_stamp" "$got" "$(date -u +%FT%TZ)" >"$stamp"
  say "   $spec: unpacked into third_party/npm/$name ($(du -sh "$dest" | cut -f1))"
}

npm_packages() {
  step "npm packages (scripts/deps/*.npm)"
  local lines
  mapfile -t lines < <(npm_lines)
  if ((${#lines[@]} == 0)); then
    say "   no npm packages listed"
    step_done
    return
  fi
  command -v npm >/dev/null || fail "npm" "npm is not installed (apt package 'npm')"
  mkdir -p "$NPM_DIR"
  local l
  for l in "${lines[@]}"; do npm_fetch_one "$l"; done
  step_done
}

# ---------------------------------------------------------------------------------------------
# 3. Configure and build
build() {
  step "configure + build ($BUILD_TYPE, -j$JOBS) in ${BUILD_DIR#"$ROOT"/}"
  local log=$LOG_DIR/cmake.log
  : >"$log"
  # Only pass the build type when configuring for the first time, so a re-run keeps the cache.
  # The prefix /usr is Debian's layout, which scripts/package.sh packages (docs/packaging.md).
  local cfg=(-S "$ROOT" -B "$BUILD_DIR")
  [[ -f $BUILD_DIR/CMakeCache.txt ]] ||
    cfg+=(-DCMAKE_BUILD_TYPE="$BUILD_TYPE" -DCMAKE_INSTALL_PREFIX="${NNS_INSTALL_PREFIX:-/usr}")
  cmake "${cfg[@]}" >>"$log" 2>&1 || fail "cmake configure" "see the CMake errors below" "$log"
  # Optional parts that will not be built (back ends without their dependency, ...).
  grep -iE '^-- .*(not built|skipping|not found)' "$log" |
    grep -vE 'Check for working|Looking for|Performing Test|Detecting' | sed 's/^/[setup]    /' || true
  local blog=$LOG_DIR/build.log
  local b0
  b0=$(date +%s)
  if ! cmake --build "$BUILD_DIR" -j"$JOBS" >"$blog" 2>&1; then
    printf '[setup] compiler errors:\n' >&2
    grep -E -A5 'error:|Error [0-9]' "$blog" | head -n 60 | sed 's/^/    /' >&2 || true
    fail "build" "cmake --build failed (full log: ${blog#"$ROOT"/})" "$blog"
  fi
  say "   build took $(($(date +%s) - b0)) s"
  step_done
}

# ---------------------------------------------------------------------------------------------
# 4. Demo
demo() {
  step "demo (examples/demo/run_demo.sh)"
  local rc=0
  NNS_BUILD_DIR=$BUILD_DIR bash "$ROOT/examples/demo/run_demo.sh" || rc=$?
  case $rc in
    0) step_done ;;
    77) say "   demo skipped (see the reason above)" ;;
    *) fail "demo" "examples/demo/run_demo.sh exited with $rc" ;;
  esac
}

((do_apt)) && apt_packages
((do_npm)) && npm_packages
((do_build)) && build
((do_demo)) && demo
say "setup finished in $(($(date +%s) - t_start)) s"
