#!/usr/bin/env bash
# SPDX-License-Identifier: LGPL-2.1-only
# Checks C/C++ formatting against .clang-format (clang-format --dry-run --Werror).
# usage: scripts/format-check.sh [--fix] [--quiet (counts only)] [files...]   (default: every tracked source in
#        src/ include/ tests/ bench/ backends/ examples/ tools/)
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$ROOT"
fix=0 quiet=0 files=()
for a in "$@"; do
  case $a in
    --fix) fix=1 ;;
    --quiet) quiet=1 ;;
    *) files+=("$a") ;;
  esac
done
CF=${CLANG_FORMAT:-$(command -v clang-format || command -v clang-format-14 || true)}
if [[ -z $CF ]]; then
  echo "format-check: clang-format not found (apt package clang-format); skipping" >&2
  exit 0
fi
if ((${#files[@]} == 0)); then
  dirs=()
  for d in src include tests bench backends examples tools; do [[ -d $d ]] && dirs+=("$d"); done
  ((${#dirs[@]})) || exit 0
  # Tracked and new (untracked, not ignored) files, so a check before committing sees them.
  mapfile -t files < <(git ls-files --cached --others --exclude-standard -- "${dirs[@]}" 2>/dev/null |
    grep -E '\.(c|cc|cpp|h|hh|hpp)$' | while read -r f; do [[ -f $f ]] && echo "$f"; done)
fi
((${#files[@]})) || exit 0
if ((fix)); then
  "$CF" -i --style=file "${files[@]}"
  echo "format-check: reformatted ${#files[@]} files"
  exit 0
fi
bad=()
for f in "${files[@]}"; do
  "$CF" --dry-run --Werror --style=file "$f" >/dev/null 2>&1 || bad+=("$f")
done
if ((${#bad[@]})); then
  echo "format-check: ${#bad[@]} of ${#files[@]} files need clang-format" >&2
  if ((!quiet)); then
    printf '  %s\n' "${bad[@]}" >&2
    echo "  fix with: scripts/format-check.sh --fix ${bad[*]}" >&2
  fi
  exit 1
fi
((quiet)) || echo "format-check: ${#files[@]} files OK"
exit 0
