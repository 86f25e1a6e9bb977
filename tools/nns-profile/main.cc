// SPDX-License-Identifier: LGPL-2.1-only
// nns-profile: runs a gst-launch pipeline with the nnsprofile tracer (or reads the tracer's
// output file of another program) and writes a text table naming the bottleneck, an HTML report
// and a JSON report (docs/profiler.md).
#include <glib-unix.h>
#include <sys/resource.h>
#include <gst/gst.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "report.h"

namespace {

using nlohmann::json;
namespace rp = nns::profile::report;

struct Options {
  std::string pipeline, from, html = "nns-profile.html", json_out = "nns-profile.json", trace;
  std::string only;  // --pipeline
  double duration = 0, wait = 0;
  int progress = -1;  // -1: when stderr is a terminal
};

void usage(FILE *f) {
  std::fputs(
      "usage: nns-profile [options] \"<gst-launch pipeline description>\"\n"
      "       nns-profile --from FILE [--wait SECONDS] [--pipeline NAME] [options]\n"
      "Runs the pipeline to EOS with the nnsprofile tracer (Ctrl-C sends EOS), then prints a\n"
      "table of elements sorted by share of time naming the bottleneck, and writes an HTML and\n"
      "a JSON report. --from reads the output file of a program run with\n"
      "GST_TRACERS=\"nnsprofile(file=FILE)\" instead (while it runs, or after).\n"
      "options:\n"
      "  --html FILE       HTML report (default nns-profile.html; '' for none)\n"
      "  --json FILE       JSON report (default nns-profile.json; '' for none)\n"
      "  --trace FILE      where the tracer writes while the pipeline runs (default: temporary)\n"
      "  --duration S      send EOS after S seconds (for endless sources)\n"
      "  --wait S          with --from: follow the file for S seconds before reporting\n"
      "  --pipeline NAME   with --from: only the elements of that top-level pipeline\n"
      "  --progress        always show the progress line; --quiet: never\n",
      f);
}

bool parse(int argc, char **argv, Options &o) {
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto value = [&](std::string &dst) {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      dst = argv[++i];
    };
    auto number = [&](double &dst) {
      std::string v;
      value(v);
      char *end = nullptr;
      dst = std::strtod(v.c_str(), &end);
      if (v.empty() || *end || dst < 0)
        throw std::runtime_error(a + " needs a number of seconds >= 0, got '" + v + "'");
    };
    if (a == "-h" || a == "--help") {
      usage(stdout);
      std::exit(0);
    } else if (a == "--from") {
      value(o.from);
    } else if (a == "--html") {
      value(o.html);
    } else if (a == "--json") {
      value(o.json_out);
    } else if (a == "--trace") {
      value(o.trace);
    } else if (a == "--pipeline") {
      value(o.only);
    } else if (a == "--duration") {
      number(o.duration);
    } else if (a == "--wait") {
      number(o.wait);
    } else if (a == "--progress") {
      o.progress = 1;
    } else if (a == "--quiet" || a == "-q") {
      o.progress = 0;
    } else if (a.rfind("--", 0) == 0) {
      throw std::runtime_error("unknown option " + a);
    } else {
      o.pipeline += (o.pipeline.empty() ? "" : " ") + a;
    }
  }
  if (o.from.empty() == o.pipeline.empty())
    throw std::runtime_error(o.from.empty() ? "no pipeline description given"
                                            : "give either a pipeline or --from FILE, not both");
  if (o.progress < 0) o.progress = isatty(STDERR_FILENO) ? 1 : 0;
  return true;
}

// The tracer's latest output, or null when the file is missing or half-written.
json read_trace(const std::string &path) {
  std::ifstream f(path);
  if (!f) return nullptr;
  std::stringstream ss;
  ss << f.rdbuf();
  return json::parse(ss.str(), nullptr, false);
}

void show_progress(const Options &o, const json &trace, double elapsed) {
  if (!o.progress) return;
  std::string line = "nns-profile: " + std::to_string(static_cast<int>(elapsed * 10) / 10) + "." +
                     std::to_string(static_cast<int>(elapsed * 10) % 10) + " s";
  if (trace.is_object()) {
    try {
      rp::Report r = rp::analyse(trace, o.only, "");
      uint64_t at_sinks = 0;
      double rate = 0;
      for (const auto &k : r.links)
        if (k.to_sink) {
          at_sinks += k.buffers;
          rate += k.rate;
        }
      char b[160];
      std::snprintf(b, sizeof b, ", %llu buffers at sinks (%.1f/s)",
                    static_cast<unsigned long long>(at_sinks), rate);
      line += b;
      if (r.bottleneck >= 0) {
        const auto &e = r.elements[static_cast<std::size_t>(r.bottleneck)];
        std::snprintf(b, sizeof b, ", busiest %s %.0f%%", e.name.c_str(), e.busy * 100);
        line += b;
      }
    } catch (const std::exception &) {
    }
  }
  std::fprintf(stderr, "\r%-100s", line.c_str());
  std::fflush(stderr);
}

struct Run {
  GMainLoop *loop = nullptr;
  GstElement *pipeline = nullptr;
  const Options *opt = nullptr;
  std::string trace_file;
  std::chrono::steady_clock::time_point start;
  bool error = false;
  bool eos_sent = false;
};

gboolean on_bus(GstBus *, GstMessage *m, gpointer data) {
  auto *run = static_cast<Run *>(data);
  if (GST_MESSAGE_TYPE(m) == GST_MESSAGE_EOS) {
    g_main_loop_quit(run->loop);
  } else if (GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    GError *e = nullptr;
    gchar *dbg = nullptr;
    gst_message_parse_error(m, &e, &dbg);
    std::fprintf(stderr, "\nnns-profile: error from %s: %s\n%s\n", GST_OBJECT_NAME(m->src),
                 e->message, dbg ? dbg : "");
    g_error_free(e);
    g_free(dbg);
    run->error = true;
    g_main_loop_quit(run->loop);
  }
  return TRUE;
}

gboolean on_tick(gpointer data) {
  auto *run = static_cast<Run *>(data);
  const double el =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - run->start).count();
  show_progress(*run->opt, read_trace(run->trace_file), el);
  if (run->opt->duration > 0 && el >= run->opt->duration && !run->eos_sent) {
    run->eos_sent = true;
    gst_element_send_event(run->pipeline, gst_event_new_eos());
  }
  return TRUE;
}

gboolean on_sigint(gpointer data) {
  auto *run = static_cast<Run *>(data);
  if (!run->eos_sent) {
    run->eos_sent = true;
    gst_element_send_event(run->pipeline, gst_event_new_eos());
  } else {
    g_main_loop_quit(run->loop);
  }
  return TRUE;
}

void prepend_env(const char *name, const std::string &dir) {
  const char *old = std::getenv(name);
  std::string v = old ? old : "";
  if (v.find(dir) != std::string::npos) return;
  setenv(name, (dir + (v.empty() ? "" : ":" + v)).c_str(), 1);
}

// Runs the pipeline; returns the tracer's final output (null on failure) and sets `failed`.
int64_t process_cpu_ns() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  auto ns = [](const timeval &t) {
    return static_cast<int64_t>(t.tv_sec) * 1000000000 + static_cast<int64_t>(t.tv_usec) * 1000;
  };
  return ns(u.ru_utime) + ns(u.ru_stime);
}

json run_pipeline(const Options &o, bool &failed, json &process) {
  std::string trace = o.trace;
  std::string own_dir;  // our temporary folder when the user gave no trace file
  if (trace.empty()) {
    gchar *dir = g_dir_make_tmp("nns-profile-XXXXXX", nullptr);
    if (dir) own_dir = dir;
    trace = std::string(dir ? dir : "/tmp") + "/trace.json";
    g_free(dir);
  }
  // Removes the temporary trace and its folder on every way out, early failures included.
  struct TempTrace {
    const std::string &dir;
    ~TempTrace() {
      if (dir.empty()) return;
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } temp_trace{own_dir};
  std::remove(trace.c_str());
  // The build tree's plugin and sub-plugins, unless the environment already names them.
  const std::string b = NNS_BUILD_DIR;
  prepend_env("GST_PLUGIN_PATH", b + "/plugin");
  setenv("NNSTREAMER_CONF", (b + "/nnstreamer.ini").c_str(), 0);
  setenv("NNSTREAMER_FILTERS", (b + "/subplugins/filters").c_str(), 0);
  setenv("NNSTREAMER_DECODERS", (b + "/subplugins/decoders").c_str(), 0);
  setenv("NNSTREAMER_CONVERTERS", (b + "/subplugins/converters").c_str(), 0);
  // Other tracers the user asked for stay; an nnsprofile entry of theirs gives way to ours.
  std::string tracers = "nnsprofile(file=\"" + trace + "\",interval=250)";
  if (const char *old = std::getenv("GST_TRACERS")) {
    gchar **items = g_strsplit(old, ";", 0);
    for (gchar **it = items; *it; ++it)
      if (**it && std::strncmp(*it, "nnsprofile", 10) != 0)
        tracers = std::string(*it) + ";" + tracers;
    g_strfreev(items);
  }
  setenv("GST_TRACERS", tracers.c_str(), 1);
  gst_init(nullptr, nullptr);

  bool have = false;
  GList *ts = gst_tracing_get_active_tracers();
  for (GList *l = ts; l; l = l->next)
    if (!std::strcmp(G_OBJECT_TYPE_NAME(l->data), "NnsProfileTracer")) have = true;
  g_list_free_full(ts, gst_object_unref);
  if (!have) {
    std::fprintf(stderr,
                 "nns-profile: the nnsprofile tracer did not start: the nnstreamer plugin was not "
                 "found on GST_PLUGIN_PATH (%s)\n",
                 std::getenv("GST_PLUGIN_PATH"));
    failed = true;
    return nullptr;
  }
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(o.pipeline.c_str(), &err);
  if (!p || err) {
    std::fprintf(stderr, "nns-profile: cannot build the pipeline: %s\n",
                 err ? err->message : "unknown error");
    if (err) g_error_free(err);
    if (p) gst_object_unref(p);
    failed = true;
    return nullptr;
  }
  gst_object_set_name(GST_OBJECT(p), "nns-profile");
  Run run;
  run.loop = g_main_loop_new(nullptr, FALSE);
  run.pipeline = p;
  run.opt = &o;
  run.trace_file = trace;
  run.start = std::chrono::steady_clock::now();
  const int64_t cpu0 = process_cpu_ns();
  GstBus *bus = gst_element_get_bus(p);
  const guint watch = gst_bus_add_watch(bus, on_bus, &run);
  const guint tick = g_timeout_add(250, on_tick, &run);
  const guint sig = g_unix_signal_add(SIGINT, on_sigint, &run);
  if (gst_element_set_state(p, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE) {
    // The bus carries the reason; let on_bus print it.
    run.error = true;
  }
  g_main_loop_run(run.loop);
  {
    const int64_t cpu = process_cpu_ns() - cpu0;
    const int64_t wall = std::chrono::duration_cast<std::chrono::nanoseconds>(
                             std::chrono::steady_clock::now() - run.start)
                             .count();
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    process = json{{"cpu_ns", cpu},
                   {"wall_ns", wall},
                   {"cpu_share", wall > 0 ? static_cast<double>(cpu) / wall : 0.0},
                   {"max_rss_kb", u.ru_maxrss}};
  }
  g_source_remove(tick);
  g_source_remove(sig);
  g_source_remove(watch);
  gst_element_set_state(p, GST_STATE_NULL);  // the tracer writes its "stop" output here
  gst_object_unref(bus);
  gst_object_unref(p);
  g_main_loop_unref(run.loop);
  if (o.progress) {
    const double el =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - run.start).count();
    show_progress(o, read_trace(trace), el);
    std::fputc('\n', stderr);
  }
  failed = run.error;
  return read_trace(trace);
}

bool write_text(const std::string &path, const std::string &text) {
  if (path.empty()) return true;
  std::ofstream f(path);
  f << text;
  f.close();
  if (!f) {
    std::fprintf(stderr, "nns-profile: cannot write %s\n", path.c_str());
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char **argv) {
  Options o;
  try {
    parse(argc, argv, o);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "nns-profile: %s\n", e.what());
    usage(stderr);
    return 2;
  }
  json trace, process;
  bool failed = false;
  std::string title = o.pipeline;
  if (!o.from.empty()) {
    title = o.from;
    const auto start = std::chrono::steady_clock::now();
    for (;;) {
      json t = read_trace(o.from);
      if (t.is_object()) trace = t;
      const double el =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (el >= o.wait || (trace.is_object() && trace.value("reason", "") == "exit")) break;
      show_progress(o, trace, el);
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
    if (o.progress && o.wait > 0) std::fputc('\n', stderr);
    if (!trace.is_object()) {
      std::fprintf(stderr, "nns-profile: cannot read nnsprofile output from %s\n", o.from.c_str());
      return 2;
    }
  } else {
    o.only = "nns-profile";
    trace = run_pipeline(o, failed, process);
    if (!trace.is_object()) {
      if (!failed) std::fprintf(stderr, "nns-profile: the tracer wrote no output\n");
      return failed ? 1 : 2;
    }
  }
  int rc = failed ? 1 : 0;
  try {
    rp::Report r = rp::analyse(trace, o.only, title);
    r.process = process;
    std::fputs(rp::text_table(r).c_str(), stdout);
    if (!write_text(o.html, rp::html_page(r))) rc = 2;
    if (!write_text(o.json_out, rp::report_json(r).dump(2) + "\n")) rc = 2;
    if (!o.html.empty() || !o.json_out.empty())
      std::fprintf(stderr, "nns-profile: wrote %s%s%s\n", o.html.c_str(),
                   o.html.empty() || o.json_out.empty() ? "" : " and ", o.json_out.c_str());
  } catch (const std::exception &e) {
    std::fprintf(stderr, "nns-profile: %s\n", e.what());
    return 2;
  }
  if (o.from.empty()) gst_deinit();
  return rc;
}
