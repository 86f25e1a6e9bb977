# SPDX-License-Identifier: LGPL-2.1-only
"""Checks and reports the paper experiments (examples/paper/run.sh).

  report.py check <dumps folder>
      compares every output dump of a Control run (control.<exp>.<stream>.f32) with the
      pipeline's (nns.<exp>.<stream>.f32): same number of values and equal within the
      experiment's tolerance (exact model inputs: 1e-4; E4, where videoscale and the Control's
      own bilinear resize differ by rounding: max 0.1, mean 0.01). Exit 1 on any difference.
  report.py plot <results.jsonl> <out folder>
      e1.png .. e4.png (matplotlib) and tables.md from the JSON lines of nns-paper; batch
      figures are medians over repeated runs. With <out>/profile/<tag>.trace.json (nnsprofile
      tracer files of profiled runs) also per-element tables and E3's per-stage invoke times.
      tables.md starts with the cores, ONNX Runtime threads and load range of the runs and ends
      with the pipeline / Control ratio of every batch configuration beside the CPU %, run-queue
      time and threads of each side. Exit 1 when a run lacks its figures or a throughput is not
      positive.
"""

import glob
import json
import os
import statistics
import sys

import numpy as np


def check(folder):
    bad = 0
    ctl = sorted(glob.glob(os.path.join(folder, "control.*.f32")))
    if not ctl:
        print("check: no dumps in %s" % folder)
        return 1
    for c in ctl:
        name = os.path.basename(c)[len("control."):]
        n = os.path.join(folder, "nns." + name)
        a = np.fromfile(c, np.float32)
        if not os.path.exists(n):
            print("check: %s: the pipeline wrote no %s" % (name, n))
            bad += 1
            continue
        b = np.fromfile(n, np.float32)
        if a.size != b.size or a.size == 0:
            print("check: %s: Control has %d values, pipeline %d" % (name, a.size, b.size))
            bad += 1
            continue
        d = np.abs(a - b)
        e4 = name.startswith("e4")
        ok = (d.max() <= 0.1 and d.mean() <= 0.01) if e4 else d.max() <= 1e-4
        print("check: %-22s %7d values  max |diff| %.3g  mean %.3g  %s"
              % (name, a.size, d.max(), d.mean(), "ok" if ok else "DIFFERENT"))
        bad += 0 if ok else 1
    return 1 if bad else 0


def load(path):
    runs = [json.loads(line) for line in open(path) if line.strip()]
    for r in runs:
        f = r["figures"]
        fps = [v for k, v in f.items() if k.startswith("fps")]
        if not fps or min(fps) <= 0 or f.get("cpu_s", -1) < 0:
            raise SystemExit("plot: run %s %s %s has no positive throughput: %s"
                             % (r["exp"], r["mode"], r["config"], f))
    return runs


def pick(runs, exp, mode, config=None, live=None):
    """Runs of one configuration; measurement runs (no dump) when there are any."""
    sel = [r for r in runs if r["exp"] == exp and r["mode"] == mode
           and (config is None or r["config"] == config)
           and (live is None or r["info"].get("live") == ("yes" if live else "no"))]
    plain = [r for r in sel if r["info"].get("dump") != "yes"]
    return plain or sel


def med(runs, key, lat=None, field="p50"):
    if lat:
        v = [r["latency_ms"][lat][field] for r in runs if lat in r["latency_ms"]]
    else:
        v = [r["figures"][key] for r in runs if key in r["figures"]]
    return statistics.median(v) if v else float("nan")


def per_cpu(runs, key):
    """Work per CPU second (figure / CPU %): robust against the share of a loaded machine."""
    return med(runs, key) / max(1e-9, med(runs, "cpu_pct") / 100.0)


def measured(runs, exp, config=None):
    """(live, runs per mode): live runs when there are any, else batch."""
    live = any(r["info"].get("live") == "yes" for r in pick(runs, exp, "nns", config))
    return live, {m: pick(runs, exp, m, config, live) for m in ("control", "nns")}


def bars(ax, labels, series, title, ylabel):
    x = np.arange(len(labels))
    w = 0.8 / len(series)
    for i, (name, vals) in enumerate(series):
        b = ax.bar(x + (i - (len(series) - 1) / 2) * w, vals, w, label=name)
        ax.bar_label(b, fmt="%.1f", fontsize=7)
    ax.set_xticks(x)
    ax.set_xticklabels(labels, fontsize=8)
    ax.set_title(title, fontsize=9)
    ax.set_ylabel(ylabel, fontsize=8)
    ax.legend(fontsize=7)


def e1(runs, plt, out, md):
    cfgs = [c for c in ["fast", "mid", "slow", "fast,mid", "mid,slow", "fast,slow",
                        "fast,mid,slow"] if pick(runs, "e1", "nns", c)]
    fig, axs = plt.subplots(3, 1, figsize=(13, 10))
    rows = []
    labels, tput, cpu, rss = [], {"control": [], "nns": []}, {"control": [], "nns": []}, \
        {"control": [], "nns": []}
    for c in cfgs:
        live, by = measured(runs, "e1", c)
        for k in c.split(","):
            labels.append("%s\n(%s)" % (k, "alone" if "," not in c else c.replace(",", "+")))
            for m in by:
                tput[m].append(med(by[m], "fps_" + k))
        for m in by:
            cpu[m].append(med(by[m], "cpu_pct"))
            rss[m].append(med(by[m], "rss_peak_mib"))
            rows.append("| %s | %s | %s | %s | %.1f | %.1f | %s |" % (
                m, c, "30 fps live" if live else "batch",
                ", ".join("%.1f" % med(by[m], "fps_" + k) for k in c.split(",")),
                med(by[m], "cpu_pct"), med(by[m], "rss_peak_mib"),
                ", ".join("%.1f" % med(by[m], None, k) for k in c.split(","))))
    bars(axs[0], labels, [("Control", tput["control"]), ("NNStreamer-cpp", tput["nns"])],
         "E1 throughput per model", "frames/s")
    bars(axs[1], [c.replace(",", "+") for c in cfgs], [("Control", cpu["control"]),
                                                     ("NNStreamer-cpp", cpu["nns"])],
         "E1 CPU (100% = one core)", "%")
    bars(axs[2], [c.replace(",", "+") for c in cfgs], [("Control", rss["control"]),
                                                     ("NNStreamer-cpp", rss["nns"])],
         "E1 peak RSS", "MiB")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "e1.png"), dpi=80)
    md.append("### E1\n\n| impl | models | input | throughput per model (fps) | CPU % | "
              "peak RSS MiB | latency p50 per model (ms) |\n|---|---|---|---|---|---|---|")
    md.extend(rows)
    batch = {m: pick(runs, "e1", m, "fast,mid,slow", False) for m in ("control", "nns")}
    if batch["nns"]:
        md.append("\nBatch (every frame through every model, median of %d): " % len(batch["nns"])
                  + "; ".join("%s %.1f fps, CPU %.0f%%, %.1f frames per CPU s"
                              % (m, med(batch[m], "fps_slow"), med(batch[m], "cpu_pct"),
                                 per_cpu(batch[m], "fps_slow")) for m in batch))
    md.append("")


def e2(runs, plt, out, md):
    fig, axs = plt.subplots(1, 3, figsize=(13, 3.6))
    live = {m: pick(runs, "e2", m, live=True) for m in ("control", "nns")}
    batch = {m: pick(runs, "e2", m, live=False) for m in ("control", "nns")}
    md.append("### E2\n\n| impl | input | video fps | audio chunks/s | windows/s | CPU % | "
              "video frames per CPU s | peak RSS MiB | GRU p50 ms |\n"
              "|---|---|---|---|---|---|---|---|---|")
    for name, sel in (("30 fps live", live), ("batch", batch)):
        for m in sel:
            if sel[m]:
                md.append("| %s | %s | %.1f | %.1f | %.1f | %.1f | %.1f | %.1f | %.2f |" % (
                    m, name, med(sel[m], "fps_video"), med(sel[m], "fps_audio"),
                    med(sel[m], "fps_windows"), med(sel[m], "cpu_pct"),
                    per_cpu(sel[m], "fps_video"), med(sel[m], "rss_peak_mib"),
                    med(sel[m], None, "gru")))
    md.append("")
    modes = [("Control", "control"), ("NNStreamer-cpp", "nns")]
    src = live if live["nns"] else batch
    tag = "30 fps live" if live["nns"] else "batch"
    bars(axs[0], ["CPU %% (%s)" % tag], [(n, [med(src[m], "cpu_pct")]) for n, m in modes],
         "E2 CPU", "%")
    bars(axs[1], ["peak RSS"], [(n, [med(src[m], "rss_peak_mib")]) for n, m in modes],
         "E2 memory", "MiB")
    bars(axs[2], ["video frames/s", "audio chunks/s", "windows/s"],
         [(n, [med(batch[m], k) for k in ("fps_video", "fps_audio", "fps_windows")])
          for n, m in modes], "E2 batch rates (recorded inputs)", "per second")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "e2.png"), dpi=80)


def e3(runs, plt, out, md):
    tr = trace(out, "e3")
    fig, axs = plt.subplots(1, 3 if tr else 2, figsize=(14 if tr else 10, 3.6))
    batch = {m: pick(runs, "e3", m, live=False) for m in ("control", "nns")}
    live = {m: pick(runs, "e3", m, live=True) for m in ("control", "nns")}
    lat = live if live["nns"] else batch
    modes = [("Control", "control"), ("NNStreamer-cpp", "nns")]
    bars(axs[0], ["throughput (batch)"], [(n, [med(batch[m], "fps")]) for n, m in modes],
         "E3 throughput", "frames/s")
    stages = ["overall", "pnet", "rnet", "onet"]
    bars(axs[1], stages, [(n, [med(lat[m], None, s, "mean") for s in stages]) for n, m in modes],
         "E3 latency (%s)" % ("5 fps paced input" if live["nns"] else "batch"), "ms (mean)")
    if tr:  # per-stage model time: tracer invoke times vs the Control's stage times (batch)
        inv = invoke_ms(tr)
        ours = [sum(inv.get("p%d" % i, 0) for i in range(3)), inv.get("rnet", 0),
                inv.get("onet", 0)]
        ctl = [med(batch["control"], None, s, "mean") for s in ("pnet", "rnet", "onet")]
        bars(axs[2], ["P-Net (3 scales)", "R-Net", "O-Net"],
             [("Control stage (batch)", ctl), ("NNStreamer-cpp invoke (nnsprofile)", ours)],
             "E3 per-stage time", "ms per frame")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "e3.png"), dpi=80)
    md.append("### E3\n\n| row | Control | NNStreamer-cpp |\n|---|---|---|")
    md.append("| throughput (fps, batch) | %.1f | %.1f |" % tuple(med(batch[m], "fps")
                                                           for _, m in modes))
    for s in stages:
        md.append("| %s latency (ms, mean) | %.2f | %.2f |" % ((s,) + tuple(
            med(lat[m], None, s, "mean") for _, m in modes)))
    md.append("| CPU %% (batch) | %.1f | %.1f |" % tuple(med(batch[m], "cpu_pct")
                                                      for _, m in modes))
    if all("runq_s" in batch[m][0]["figures"] for _, m in modes):
        md.append("| run-queue s / voluntary switches (batch) | %.2f / %.0f | %.2f / %.0f |" % (
            med(batch["control"], "runq_s"), med(batch["control"], "vcsw"),
            med(batch["nns"], "runq_s"), med(batch["nns"], "vcsw")))
        md.append("| threads (batch) | %.0f | %.0f |" % tuple(med(batch[m], "threads")
                                                          for _, m in modes))
    md.append("| frames per CPU second (batch) | %.1f | %.1f |" % tuple(
        per_cpu(batch[m], "fps") for _, m in modes))
    md.append("| peak RSS MiB | %.1f | %.1f |" % tuple(med(batch[m], "rss_peak_mib")
                                                      for _, m in modes))
    faces = [med(batch[m], "face_frames") for _, m in modes]
    frames = [med(batch[m], "frames") for _, m in modes]
    if faces[0] != faces[1] or not 0 < faces[1] < frames[1]:
        raise SystemExit("plot: E3 frames with a face: Control %s, pipeline %s of %s (expected "
                         "equal, some but not all)" % (faces[0], faces[1], frames[1]))
    md.append("| frames with a face / frames | %d / %d | %d / %d |" % (
        med(batch["control"], "face_frames"), med(batch["control"], "frames"),
        med(batch["nns"], "face_frames"), med(batch["nns"], "frames")))
    md.append("")


def e4(runs, plt, out, md):
    fig, axs = plt.subplots(1, 3, figsize=(13, 3.6))
    modes = [("Control", "control"), ("NNStreamer-cpp", "nns")]
    sizes = [s for s in ("160", "320") if pick(runs, "e4", "nns", s)]
    md.append("### E4\n\n| impl | model | input | throughput fps | CPU % | frames per CPU s | "
              "latency p50 ms | peak RSS MiB |\n|---|---|---|---|---|---|---|---|")
    for s in sizes:
        for live in (False, True):
            for _, m in modes:
                sel = pick(runs, "e4", m, s, live)
                if sel and (not live or any(r["info"].get("live") == "yes" for r in sel)):
                    md.append("| %s | %sx%s | %s | %.1f | %.1f | %.1f | %.2f | %.1f |" % (
                        m, s, s, "30 fps live" if live else "batch", med(sel, "fps"),
                        med(sel, "cpu_pct"), per_cpu(sel, "fps"), med(sel, None, "overall"),
                        med(sel, "rss_peak_mib")))
    md.append("")

    def series(key, live, lat=None):
        return [(n, [med(pick(runs, "e4", m, s, live), key, lat) for s in sizes])
                for n, m in modes]

    labels = ["SSD %sx%s" % (s, s) for s in sizes]
    bars(axs[0], labels, series("fps", False), "E4 throughput (batch)", "frames/s")
    has_live = any(r["info"].get("live") == "yes" for r in pick(runs, "e4", "nns"))
    bars(axs[1], labels, series("cpu_pct", has_live),
         "E4 CPU (%s)" % ("30 fps live" if has_live else "batch"), "%")
    bars(axs[2], labels, series(None, False, "overall"), "E4 latency p50 (batch)", "ms")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "e4.png"), dpi=80)


BATCH = [("E1 (fast+mid+slow)", "e1", "fast,mid,slow", "fps_slow"),
         ("E2", "e2", None, "fps_video"), ("E3", "e3", None, "fps"),
         ("E4 160x160", "e4", "160", "fps"), ("E4 320x320", "e4", "320", "fps")]


def ratios(runs, md):
    """Pipeline / Control throughput of the batch runs with the CPU each used.

    On c cores a pipeline can be at most c times a Control that has one full core and does the
    same work per frame; a larger ratio means the Control did not get its core (other jobs:
    see its run-queue time) or the two did different work.
    """
    rows = []
    for name, exp, config, key in BATCH:
        by = {m: pick(runs, exp, m, config, False) for m in ("control", "nns")}
        if not by["control"] or not by["nns"]:
            continue
        c, n = by["control"], by["nns"]
        cores = int(med(n, "cpus")) if "cpus" in n[0]["figures"] else 0
        ratio = med(n, key) / med(c, key)
        note = []
        if med(c, "cpu_pct") < 90:
            note.append("Control below one core (%.0f %%): %s" % (
                med(c, "cpu_pct"), "squeezed by other tasks, %.2f s on the run queue"
                % med(c, "runq_s") if "runq_s" in c[0]["figures"] else "squeezed or waiting"))
        if cores and ratio > cores:
            note.append("ratio above the %d cores: the CPU shares differ %.1fx, work per CPU "
                        "second %.2fx" % (cores, med(n, "cpu_pct") / max(1e-9, med(c, "cpu_pct")),
                                          per_cpu(n, key) / max(1e-9, per_cpu(c, key))))

        def fig(sel, k, fmt):
            return fmt % med(sel, k) if k in sel[0]["figures"] else "-"

        rows.append("| %s | %.1f | %.1f | %s | %s | %.1f | %.1f | %s | %s | %.2f | %s | %s |" % (
            name, med(c, key), med(c, "cpu_pct"), fig(c, "runq_s", "%.2f"),
            fig(c, "vcsw", "%.0f"), med(n, key), med(n, "cpu_pct"), fig(n, "runq_s", "%.2f"),
            fig(n, "threads", "%.0f"), ratio, cores or "-", "; ".join(note) or "-"))
    if not rows:
        return
    md.append("### Pipeline / Control (batch, medians)\n")
    md.append("CPU % is process CPU time over wall time (100 = one core); run-queue s is the time "
              "the process's threads were runnable but other tasks held the cores; voluntary "
              "switches count the Control's waits (blocking, sleeping) in the measured loop.\n")
    md.append("| experiment | Control fps | Control CPU % | Control run-queue s | Control "
              "voluntary switches | pipeline fps | pipeline CPU % | pipeline run-queue s | "
              "pipeline threads | pipeline / Control | cores | note |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|---|")
    md.extend(rows)
    md.append("")


def machine(runs):
    """One line: cores, pinning, ONNX Runtime threads, the load averages of the runs and whether
    another task held the cores. The 1-minute load average includes the benchmark's own load (a
    pipeline on every core raises it to about the core count), so the machine is judged by the
    Controls' run-queue time instead: a single-threaded Control that is never runnable-but-waiting
    had a core to itself whenever it wanted one."""
    loads = [float(r["info"][k].split()[0]) for r in runs for k in ("loadavg_start", "loadavg_end")
             if k in r["info"]]
    cpus = sorted({int(r["figures"]["cpus"]) for r in runs if "cpus" in r["figures"]})
    ort = sorted({r["info"]["ort_intra_threads"] for r in runs if "ort_intra_threads" in r["info"]})
    if not loads:
        return "Load average not recorded (runs made before it was)."
    runq = [float(r["figures"]["runq_s"]) for r in runs
            if r.get("mode") == "control" and "runq_s" in r["figures"]]
    if runq:
        verdict = ("; the Controls were kept off a core for %.2f s at most in any run (%s)" % (
            max(runq), "no other task held the cores: a quiet machine" if max(runq) < 0.05 else
            "NOT a quiet machine: CPU shares, not the design, decide the ratios"))
    else:
        verdict = ("" if max(loads) < 0.5 * max(cpus or [1]) else
                   " (NOT a quiet machine: CPU shares, not the design, decide the ratios)")
    return ("Runs pinned to %s core(s), ONNX Runtime intra-op threads %s; 1-minute load average "
            "between %.2f and %.2f over the runs (their own load included)%s." % (
                "/".join(map(str, cpus)) or "?", "/".join(ort) or "?", min(loads), max(loads),
                verdict))


def trace(out, tag):
    """The nnsprofile tracer file of a profiled run (docs/profiler.md), or None."""
    p = os.path.join(out, "profile", tag + ".trace.json")
    return json.load(open(p)) if os.path.exists(p) else None


def invoke_ms(tr):
    """tensor_filter name -> mean invoke time in ms, from a tracer file."""
    return {e["name"]: e["invoke_ns"] / e["invokes"] / 1e6
            for e in tr["elements"] if e.get("invokes")}


def profiles(out, md):
    tags = [t for t in ("e1", "e2", "e3", "e4-320") if trace(out, t)]
    if not tags:
        return
    md.append("### Where the pipelines spend their time (nnsprofile tracer, nns-profile)\n")
    md.append("Separate runs under `GST_TRACERS=nnsprofile`; own time is wall time inside an "
              "element's chain function (an element that blocks waiting for a partner buffer, "
              "such as tensor_crop or an aggregating mux, counts the wait).\n")
    for t in tags:
        tr = trace(out, t)
        els = sorted((e for e in tr["elements"] if e.get("spans") and e["kind"] != "queue"),
                     key=lambda e: -e["self_ns"])
        total = sum(e["self_ns"] for e in els) or 1
        txt = os.path.join(out, "profile", t + ".txt")
        bott = [ln.strip() for ln in open(txt) if ln.startswith("bottleneck")] \
            if os.path.exists(txt) else []
        md.append("**%s** %s\n" % (t, bott[0] if bott else ""))
        md.append("| element | factory | buffers | own time per buffer (ms) | share | "
                  "invoke (ms) |\n|---|---|---|---|---|---|")
        inv = invoke_ms(tr)
        for e in els[:8]:
            md.append("| %s | %s | %d | %.3f | %.1f%% | %s |" % (
                e["name"], e["factory"], e["spans"], e["self_ns"] / e["spans"] / 1e6,
                100.0 * e["self_ns"] / total,
                "%.3f" % inv[e["name"]] if e["name"] in inv else "-"))
        cpu = sum(th.get("cpu_ns", 0) for th in tr.get("threads", [])) / 1e9
        md.append("\nstreaming threads: %d, their CPU time %.2f s\n"
                  % (len(tr.get("threads", [])), cpu))


def plot(path, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    runs = load(path)
    md = ["<!-- made by examples/paper/report.py from %d runs -->" % len(runs), "",
          machine(runs), ""]
    for f in (e1, e2, e3, e4):
        f(runs, plt, out, md)
        plt.close("all")
    ratios(runs, md)
    profiles(out, md)
    with open(os.path.join(out, "tables.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    for e in ("e1", "e2", "e3", "e4"):
        p = os.path.join(out, e + ".png")
        if not os.path.exists(p) or os.path.getsize(p) < 1000:
            raise SystemExit("plot: %s was not written" % p)
    print("\n".join(md))
    return 0


def main():
    if len(sys.argv) == 3 and sys.argv[1] == "check":
        return check(sys.argv[2])
    if len(sys.argv) == 4 and sys.argv[1] == "plot":
        return plot(sys.argv[2], sys.argv[3])
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main())
