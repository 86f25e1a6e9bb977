#!/usr/bin/python3
# SPDX-License-Identifier: LGPL-2.1-only
"""Every function declared in an installed C header is exported by the library that NNStreamer
puts it in: libnnstreamer-single.so for the GStreamer-free utility, configuration, logging and
single-shot headers, libcapi-nnstreamer.so for the Pipeline API (nnstreamer.h), the plugin
libnnstreamer.so for the rest.
  check_exports.py <installed include/nnstreamer dir> <libnnstreamer-single.so> <libnnstreamer.so>
                   [<library>=<function>,<function>...]...
The optional arguments list what a library without an installed header (NNStreamer's decoder and
converter helper libraries) must export. Exits 1 listing each missing symbol."""
import re
import subprocess
import sys
from pathlib import Path

SINGLE_HEADERS = {"nnstreamer_plugin_api_util.h", "nnstreamer_conf.h", "nnstreamer_log.h",
                  "nnstreamer-single.h", "ml-api-common.h", "nnstreamer-tizen-internal.h",
                  "nnstreamer_internal.h"}
# The ML Pipeline API has a library of its own (NNStreamer's libcapi-nnstreamer), beside single.
CAPI_HEADERS = {"nnstreamer.h"}


def declared_functions(text):
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"//[^\n]*", " ", text)
    text = re.sub(r"\\\n", " ", text)
    text = "\n".join(l for l in text.splitlines() if not l.lstrip().startswith("#"))
    names = []
    for stmt in text.split(";"):
        stmt = stmt.replace("G_BEGIN_DECLS", " ").replace("G_END_DECLS", " ")
        stmt = re.sub(r'extern\s+"C"\s*\{', " ", stmt).strip().lstrip("}").strip()
        if "(" not in stmt or "{" in stmt or stmt.startswith("typedef"):
            continue
        m = re.match(r"[\w\s\*]*?\b([A-Za-z_]\w*)\s*\(", stmt)
        if m and not re.match(r"\(\s*\*", stmt[m.end() - 1:]):
            names.append(m.group(1))
    return names


def exported(lib):
    out = subprocess.run(["nm", "-D", "--defined-only", lib], check=True, capture_output=True,
                         text=True).stdout
    return {l.split()[-1].split("@")[0] for l in out.splitlines() if l.split()[1:2] == ["T"]}


def main():
    inc, single, plugin = sys.argv[1:4]
    libs = {"libnnstreamer-single.so": exported(single), "libnnstreamer.so": exported(plugin)}
    capi = Path(single).with_name("libcapi-nnstreamer.so")
    if capi.exists():
        libs["libcapi-nnstreamer.so"] = exported(str(capi))
    missing, checked = [], 0
    for h in sorted(Path(inc).glob("*.h")):
        if h.name in CAPI_HEADERS:
            lib = "libcapi-nnstreamer.so"
            if lib not in libs:
                missing.append(f"{h.name} is installed but {capi} is not")
                continue
        else:
            lib = "libnnstreamer-single.so" if h.name in SINGLE_HEADERS else "libnnstreamer.so"
        for fn in declared_functions(h.read_text()):
            checked += 1
            if fn not in libs[lib]:
                missing.append(f"{h.name}: {fn} is not exported by {lib}")
    for extra in sys.argv[4:]:
        lib, _, names = extra.partition("=")
        have = exported(lib)
        for fn in names.split(","):
            checked += 1
            if fn not in have:
                missing.append(f"{fn} is not exported by {lib}")
    print(f"{checked} declared functions checked")
    for m in missing:
        print(m)
    return 1 if missing or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
