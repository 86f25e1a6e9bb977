#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Writes debian/control, debian/<package>.install, debian/changelog and debian/nns-vars.mk
from packaging/packages.txt and the files `cmake --install` staged in debian/tmp.

Every staged file must belong to exactly one package of the table; an optional package none of
whose files was staged (its dependency was missing at build time) is left out.
Used by scripts/package.sh; see docs/packaging.md."""
import argparse
import email.utils
import fnmatch
import os
import textwrap
import sys

LONG = (" nnstreamer-cpp is a C++20 reimplementation of NNStreamer: GStreamer elements\n"
        " that turn media into tensor streams, transform them and run neural networks on\n"
        " them, with NNStreamer's element names, properties, caps and 2.x plug-in ABI.\n")


def parse_table(path, lib):
    rows = []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            cols = [c.strip() for c in line.split("|")]
            if len(cols) != 7:
                sys.exit(f"{path}:{n}: expected 7 '|'-separated columns, got {len(cols)}")
            name, need, section, upstream, depends, desc, files = cols
            if need not in ("required", "optional"):
                sys.exit(f"{path}:{n}: column 2 must be required or optional, got '{need}'")
            pats = [p.replace("$SUB", "$LIB/nnstreamer").replace("$LIB", lib) for p in files.split()]
            rows.append(dict(name=name, required=need == "required", section=section,
                             upstream=[] if upstream == "-" else upstream.split(),
                             depends="" if depends == "-" else depends, desc=desc, pats=pats,
                             files=[]))
    return rows


def staged_files(stage):
    out = []
    for d, dirs, files in os.walk(stage):
        for name in files + [x for x in dirs if os.path.islink(os.path.join(d, x))]:
            out.append(os.path.relpath(os.path.join(d, name), stage))
    return sorted(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--table", required=True)
    ap.add_argument("--stage", required=True, help="debian/tmp, filled by cmake --install")
    ap.add_argument("--debian", required=True, help="the debian/ folder to write into")
    ap.add_argument("--version", required=True, help="Debian version, e.g. 0.1.0-1")
    ap.add_argument("--multiarch", required=True, help="e.g. x86_64-linux-gnu")
    ap.add_argument("--python", default="", help="python3 major.minor the module is built for")
    ap.add_argument("--maintainer", required=True)
    ap.add_argument("--note", default="", help="changelog line")
    a = ap.parse_args()

    rows = parse_table(a.table, "usr/lib/" + a.multiarch)
    errors = []
    for f in staged_files(a.stage):
        owners = [r for r in rows if any(fnmatch.fnmatchcase(f, p) for p in r["pats"])]
        if len(owners) != 1:
            errors.append(f"{f}: matches {len(owners)} packages "
                          f"({', '.join(r['name'] for r in owners) or 'none'})")
        else:
            owners[0]["files"].append(f)
    for r in rows:
        if r["required"] and not r["files"]:
            errors.append(f"{r['name']}: required, but none of its files was installed")
    if errors:
        sys.exit("packaging/packages.txt does not match what cmake --install installed:\n  " +
                 "\n  ".join(errors))
    built = [r for r in rows if r["files"]]
    names = {r["name"] for r in built}

    ctl = [f"Source: nnstreamer-cpp\nSection: libs\nPriority: optional\n"
           f"Maintainer: {a.maintainer}\n"
           "Build-Depends: debhelper-compat (= 13), cmake, pkgconf, libgstreamer1.0-dev,\n"
           " libgstreamer-plugins-base1.0-dev\n"
           "Standards-Version: 4.6.2\nRules-Requires-Root: no\n"
           "Homepage: https://github.com/nnstreamer/nnstreamer\n"]
    for r in built:
        deps = ["${shlibs:Depends}", "${misc:Depends}"]
        for d in [x.strip() for x in r["depends"].split(",") if x.strip()]:
            # A dependency on one of our packages that is not built this time is dropped.
            if d.split()[0].startswith("nnstreamer-cpp") and d.split()[0] not in names:
                continue
            deps.append(d)
        s = (f"Package: {r['name']}\nSection: {r['section']}\nArchitecture: any\n"
             f"Depends: {', '.join(deps)}\n")
        if r["upstream"]:
            up = ", ".join(r["upstream"])
            s += f"Provides: {up}\nConflicts: {up}\nReplaces: {up}\n"
        body = textwrap.fill(f"This package contains: {r['desc']}.", 78,
                             initial_indent=" ", subsequent_indent=" ")
        s += f"Description: {r['desc']}\n{LONG} .\n{body}\n"
        ctl.append(s)
        with open(os.path.join(a.debian, r["name"] + ".install"), "w", encoding="utf-8") as f:
            f.write("".join(x + "\n" for x in r["files"]))
    with open(os.path.join(a.debian, "control"), "w", encoding="utf-8") as f:
        f.write("\n".join(ctl))

    date = email.utils.formatdate(localtime=False)
    with open(os.path.join(a.debian, "changelog"), "w", encoding="utf-8") as f:
        f.write(f"nnstreamer-cpp ({a.version}) bookworm; urgency=medium\n\n"
                f"  * {a.note or 'Built by scripts/package.sh.'}\n\n"
                f" -- {a.maintainer}  {date}\n")
    pydep = ""
    if a.python:
        major, minor = a.python.split(".")
        pydep = f"python3 (>= {major}.{minor}~), python3 (<< {major}.{int(minor) + 1})"
    with open(os.path.join(a.debian, "nns-vars.mk"), "w", encoding="utf-8") as f:
        f.write(f"NNS_PYTHON3_DEPENDS := {pydep}\n")
    print(" ".join(r["name"] for r in built))


if __name__ == "__main__":
    main()
