#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""The dynamic symbols each library we ship exports (nm -D --defined-only) are exactly those of its
checked-in list tests/abi/<file name>.symbols (docs/abi.md).
  check_abi.py <manifest> <lists dir> [--update]
The manifest has one `<file name>=<path>` line per library built. With --update the lists are
rewritten from the built libraries instead (then review `git diff tests/abi`). Exits 1 with a diff
(+ exported but not listed, - listed but not exported) per library that differs."""
import subprocess
import sys
from pathlib import Path


def exported(lib):
    out = subprocess.run(["nm", "-D", "--defined-only", lib], check=True, capture_output=True,
                         text=True).stdout
    names = set()
    for line in out.splitlines():
        fields = line.split()
        if len(fields) >= 3:
            names.add(fields[2].split("@")[0])
    return names


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    manifest, lists = Path(sys.argv[1]), Path(sys.argv[2])
    update = "--update" in sys.argv[3:]
    failed, checked = [], 0
    for line in manifest.read_text().splitlines():
        name, _, path = line.partition("=")
        if not name or not Path(path).exists():
            continue  # not built in this tree
        have = exported(path)
        listed = lists / f"{name}.symbols"
        if update:
            listed.write_text("".join(f"{s}\n" for s in sorted(have)))
            print(f"wrote {listed} ({len(have)} symbols)")
            continue
        checked += 1
        if not listed.exists():
            failed.append(f"{name}: no list {listed}; run `cmake --build <build> --target "
                          f"abi-update` and review the new file")
            continue
        want = {l.strip() for l in listed.read_text().splitlines() if l.strip()}
        extra, missing = sorted(have - want), sorted(want - have)
        if extra or missing:
            diff = [f"  + {s}   (exported, not in {listed.name})" for s in extra]
            diff += [f"  - {s}   (listed, not exported)" for s in missing]
            failed.append(f"{name} ({path}) differs from {listed}:\n" + "\n".join(diff))
        else:
            print(f"{name}: {len(have)} symbols as listed")
    if update:
        return 0
    for f in failed:
        print(f)
    if failed:
        print("If the change is intended, run `cmake --build <build> --target abi-update` and "
              "commit tests/abi/*.symbols; otherwise fix the export (cmake/abi/*.map).")
    return 1 if failed or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
