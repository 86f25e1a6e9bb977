// SPDX-License-Identifier: LGPL-2.1-only
// nns-profile: derived figures, the text table and the JSON report (docs/profiler.md).
#include "report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <stdexcept>

#include "profile/hist.h"

namespace nns::profile::report {

using nlohmann::json;

namespace {

std::vector<std::pair<int64_t, uint64_t>> hist_of(const json &a) {
  std::vector<std::pair<int64_t, uint64_t>> h;
  if (!a.is_array()) return h;
  for (const auto &b : a) h.emplace_back(b.at(0).get<int64_t>(), b.at(1).get<uint64_t>());
  return h;
}

Quantiles quantiles(const std::vector<std::pair<int64_t, uint64_t>> &h) {
  return Quantiles{hist_quantile(h, 0.5), hist_quantile(h, 0.9), hist_quantile(h, 0.99)};
}

int64_t num(const json &j, const char *k) {
  auto it = j.find(k);
  return it == j.end() || it->is_null() ? 0 : it->get<int64_t>();
}

std::string pct(double f) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f%%", f * 100);
  return b;
}

std::string fmt_rate(double r) {
  char b[32];
  std::snprintf(b, sizeof b, r >= 100 ? "%.0f/s" : "%.1f/s", r);
  return b;
}

json quant_json(const Quantiles &q) {
  return json{{"p50_ns", q.p50}, {"p90_ns", q.p90}, {"p99_ns", q.p99}};
}

json hist_json(const std::vector<std::pair<int64_t, uint64_t>> &h) {
  json a = json::array();
  for (const auto &[lo, c] : h) a.push_back(json::array({lo, c}));
  return a;
}

}  // namespace

std::string fmt_ns(double ns) {
  char b[32];
  if (ns < 0)
    return "-";
  else if (ns >= 1e9)
    std::snprintf(b, sizeof b, "%.2f s", ns / 1e9);
  else if (ns >= 1e6)
    std::snprintf(b, sizeof b, "%.2f ms", ns / 1e6);
  else if (ns >= 1e3)
    std::snprintf(b, sizeof b, "%.1f us", ns / 1e3);
  else
    std::snprintf(b, sizeof b, "%.0f ns", ns);
  return b;
}

Report analyse(const json &trace, const std::string &pipeline, const std::string &title) {
  if (!trace.is_object() || trace.value("format", "") != "nnsprofile")
    throw std::runtime_error("not nnsprofile tracer output (no \"format\": \"nnsprofile\")");
  for (const char *k : {"elements", "links", "threads"})
    if (!trace.contains(k) || !trace[k].is_array())
      throw std::runtime_error(std::string("nnsprofile output without a \"") + k + "\" array");
  Report r;
  r.title = title;
  r.pipeline_filter = pipeline;

  std::map<int, std::size_t> idx;  // element id -> index in r.elements
  std::map<int, json> raw;
  std::map<int, std::string> kind_of, name_of;
  for (const auto &e : trace["elements"]) {
    const std::string kind = e.value("kind", "");
    if (kind == "bin") continue;
    if (!pipeline.empty() && e.value("pipeline", "") != pipeline) continue;
    Element x;
    x.id = e.at("id").get<int>();
    x.name = e.value("name", "");
    x.factory = e.value("factory", "");
    x.kind = kind;
    idx[x.id] = r.elements.size();
    kind_of[x.id] = kind;
    name_of[x.id] = x.name;
    raw[x.id] = e;
    r.elements.push_back(std::move(x));
  }

  int64_t t0 = INT64_MAX, t1 = INT64_MIN;
  for (const auto &l : trace["links"]) {
    if (l["from"].is_null() || l["to"].is_null()) continue;
    const int from = l["from"].get<int>(), to = l["to"].get<int>();
    if (!idx.count(from) || !idx.count(to)) continue;
    Link k;
    k.from = from;
    k.to = to;
    k.from_pad = l.value("from_pad", "");
    k.to_pad = l.value("to_pad", "");
    k.mode = l.value("mode", "push");
    k.buffers = l.value("buffers", uint64_t{0});
    k.bytes = l.value("bytes", uint64_t{0});
    const int64_t first = num(l, "first_ns"), last = num(l, "last_ns");
    if (k.buffers > 0 && first >= 0) {
      t0 = std::min(t0, first);
      t1 = std::max(t1, last);
      if (k.buffers > 1 && last > first) {
        k.rate = static_cast<double>(k.buffers - 1) * 1e9 / static_cast<double>(last - first);
        k.bytes_rate = k.rate * static_cast<double>(k.bytes) / static_cast<double>(k.buffers);
      }
    }
    const json &lat = l["latency"];
    k.latency_count = lat.value("count", uint64_t{0});
    if (k.latency_count) {
      k.latency_mean_ns = static_cast<double>(num(lat, "total_ns")) / k.latency_count;
      k.latency_min_ns = num(lat, "min_ns");
      k.latency_max_ns = num(lat, "max_ns");
      k.latency_q = quantiles(hist_of(l["latency_hist"]));
    }
    k.to_sink = kind_of[to] == "sink";
    r.links.push_back(std::move(k));
  }
  r.duration_ns = t1 > t0 ? t1 - t0 : 0;
  const double dur = static_cast<double>(r.duration_ns);

  int64_t total_busy = 0;
  for (auto &x : r.elements) {
    const json &e = raw[x.id];
    const int64_t self = num(e, "self_ns"), gap = num(e, "gap_ns"), pull = num(e, "pull_ns");
    uint64_t in = 0, out = 0;
    for (const auto &k : r.links) {
      if (k.to == x.id) in += k.buffers;
      if (k.from == x.id) out += k.buffers;
    }
    if (x.kind == "queue") {
      x.wait_ns = self + gap;
    } else {
      x.busy_ns = self + gap + pull;
    }
    x.buffers = x.kind == "source" ? out : static_cast<uint64_t>(num(e, "spans") + num(e, "pulls"));
    if (x.buffers == 0) x.buffers = std::max(in, out);
    x.per_buffer_ns = x.buffers ? static_cast<double>(x.busy_ns) / x.buffers : 0;
    x.max_ns = num(e, "self_max_ns");
    x.hist = hist_of(e["self_hist"]);
    x.q = quantiles(x.hist);
    x.invokes = static_cast<uint64_t>(num(e, "invokes"));
    if (x.invokes) {
      x.invoke_mean_ns = static_cast<double>(num(e, "invoke_ns")) / x.invokes;
      x.invoke_max_ns = num(e, "invoke_max_ns");
      x.invoke_hist = hist_of(e["invoke_hist"]);
      x.invoke_q = quantiles(x.invoke_hist);
    }
    if (dur > 0) {
      x.busy = x.busy_ns / dur;
      x.in_rate = in * 1e9 / dur;
      x.out_rate = out * 1e9 / dur;
    }
    if (e.contains("queue")) {
      const json &q = e["queue"];
      const double n = std::max<double>(1, q.value("samples", 0.0));
      x.queue = json{{"samples", q.value("samples", 0)},
                     {"mean_buffers", q.value("sum_buffers", 0.0) / n},
                     {"max_buffers", q.value("max_buffers", 0)},
                     {"mean_bytes", q.value("sum_bytes", 0.0) / n},
                     {"max_bytes", q.value("max_bytes", 0)},
                     {"mean_time_ns", q.value("sum_time_ns", 0.0) / n},
                     {"max_time_ns", q.value("max_time_ns", 0)},
                     {"full_share", q.value("full_samples", 0.0) / n},
                     {"max_size_buffers", q.value("max_size_buffers", 0)},
                     {"max_size_bytes", q.value("max_size_bytes", 0)},
                     {"max_size_time_ns", q.value("max_size_time_ns", 0)}};
    }
    total_busy += x.busy_ns;
  }
  for (auto &x : r.elements)
    x.share = total_busy > 0 ? static_cast<double>(x.busy_ns) / total_busy : 0;
  std::stable_sort(r.elements.begin(), r.elements.end(),
                   [](const Element &a, const Element &b) { return a.share > b.share; });

  double best = -1;
  for (std::size_t i = 0; i < r.elements.size(); ++i)
    if (r.elements[i].kind != "queue" && r.elements[i].busy_ns > 0 && r.elements[i].busy > best) {
      best = r.elements[i].busy;
      r.bottleneck = static_cast<int>(i);
    }
  if (r.bottleneck >= 0) {
    const Element &b = r.elements[static_cast<std::size_t>(r.bottleneck)];
    r.bottleneck_text = "bottleneck: " + b.name + " (" + b.factory + "), busy " + pct(b.busy) +
                        " of the " + fmt_ns(dur) + " run, " + fmt_ns(b.per_buffer_ns) +
                        " per buffer, " + pct(b.share) + " of all element time";
    if (b.invokes) r.bottleneck_text += "; invoke " + fmt_ns(b.invoke_mean_ns) + " per buffer";
  } else {
    r.bottleneck_text = "bottleneck: none (no element processed a buffer)";
  }

  for (const auto &t : trace["threads"]) {
    if (t["root"].is_null() || !idx.count(t["root"].get<int>())) continue;
    Thread th;
    th.tid = t.value("tid", 0);
    th.name = t.value("name", "");
    th.root = name_of[t["root"].get<int>()];
    th.wall_ns = num(t, "last_ns") - num(t, "first_ns");
    th.cpu_ns = num(t, "cpu_ns");
    th.cpu_share = th.wall_ns > 0 ? static_cast<double>(th.cpu_ns) / th.wall_ns : 0;
    th.pushes = t.value("pushes", uint64_t{0});
    r.threads.push_back(std::move(th));
  }
  return r;
}

std::string text_table(const Report &r) {
  std::map<int, std::string> names;
  for (const auto &e : r.elements) names[e.id] = e.name;
  std::ostringstream o;
  char line[512];
  o << "nns-profile: " << r.title << "\n";
  o << "run: " << fmt_ns(static_cast<double>(r.duration_ns)) << ", " << r.elements.size()
    << " elements, sorted by share of element time\n\n";
  std::snprintf(line, sizeof line, "%-20s %-18s %-7s %8s %7s %7s %10s %10s %10s %10s %9s\n",
                "element", "factory", "kind", "buffers", "busy", "share", "per-buf", "p99", "max",
                "invoke", "in rate");
  o << line;
  for (const auto &e : r.elements) {
    std::snprintf(line, sizeof line, "%-20s %-18s %-7s %8llu %7s %7s %10s %10s %10s %10s %9s\n",
                  e.name.substr(0, 20).c_str(), e.factory.substr(0, 18).c_str(), e.kind.c_str(),
                  static_cast<unsigned long long>(e.buffers),
                  e.kind == "queue" ? "wait" : pct(e.busy).c_str(), pct(e.share).c_str(),
                  fmt_ns(e.per_buffer_ns).c_str(), fmt_ns(static_cast<double>(e.q.p99)).c_str(),
                  fmt_ns(static_cast<double>(e.max_ns)).c_str(),
                  e.invokes ? fmt_ns(e.invoke_mean_ns).c_str() : "-", fmt_rate(e.in_rate).c_str());
    o << line;
  }
  o << "\n" << r.bottleneck_text << "\n";
  bool any = false;
  for (const auto &k : r.links)
    if (k.to_sink && k.latency_count) {
      if (!any) o << "\nend-to-end latency (source to sink):\n";
      any = true;
      std::snprintf(line, sizeof line, "  %-24s mean %10s  p50 %10s  p99 %10s  max %10s  (%llu)\n",
                    names[k.to].c_str(), fmt_ns(k.latency_mean_ns).c_str(),
                    fmt_ns(static_cast<double>(k.latency_q.p50)).c_str(),
                    fmt_ns(static_cast<double>(k.latency_q.p99)).c_str(),
                    fmt_ns(static_cast<double>(k.latency_max_ns)).c_str(),
                    static_cast<unsigned long long>(k.latency_count));
      o << line;
    }
  any = false;
  for (const auto &e : r.elements)
    if (!e.queue.is_null()) {
      if (!any) o << "\nqueues:\n";
      any = true;
      std::snprintf(line, sizeof line,
                    "  %-24s mean %.1f buffers, max %d of %d, full %s of samples, waited %s\n",
                    e.name.c_str(), e.queue["mean_buffers"].get<double>(),
                    e.queue["max_buffers"].get<int>(), e.queue["max_size_buffers"].get<int>(),
                    pct(e.queue["full_share"].get<double>()).c_str(),
                    fmt_ns(static_cast<double>(e.wait_ns)).c_str());
      o << line;
    }
  if (!r.threads.empty()) o << "\nstreaming threads:\n";
  for (const auto &t : r.threads) {
    std::snprintf(line, sizeof line, "  %-18s (tid %d, starts at %s): CPU %s of %s wall (%s)\n",
                  t.name.c_str(), t.tid, t.root.c_str(),
                  fmt_ns(static_cast<double>(t.cpu_ns)).c_str(),
                  fmt_ns(static_cast<double>(t.wall_ns)).c_str(), pct(t.cpu_share).c_str());
    o << line;
  }
  return o.str();
}

json report_json(const Report &r) {
  json j;
  j["tool"] = "nns-profile";
  j["version"] = 1;
  j["title"] = r.title;
  j["pipeline"] = r.pipeline_filter;
  j["duration_ns"] = r.duration_ns;
  j["bottleneck"] = r.bottleneck >= 0
                        ? json(r.elements[static_cast<std::size_t>(r.bottleneck)].name)
                        : json(nullptr);
  j["bottleneck_text"] = r.bottleneck_text;
  json els = json::array();
  for (const auto &e : r.elements) {
    json x{{"id", e.id},
           {"name", e.name},
           {"factory", e.factory},
           {"kind", e.kind},
           {"buffers", e.buffers},
           {"busy_ns", e.busy_ns},
           {"wait_ns", e.wait_ns},
           {"busy", e.busy},
           {"share", e.share},
           {"per_buffer_ns", e.per_buffer_ns},
           {"max_ns", e.max_ns},
           {"quantiles", quant_json(e.q)},
           {"hist", hist_json(e.hist)},
           {"in_rate", e.in_rate},
           {"out_rate", e.out_rate},
           {"invokes", e.invokes}};
    if (e.invokes)
      x["invoke"] =
          json{{"mean_ns", e.invoke_mean_ns},
               {"max_ns", e.invoke_max_ns},
               {"quantiles", quant_json(e.invoke_q)},
               {"hist", hist_json(e.invoke_hist)},
               {"share_of_busy", e.busy_ns > 0 ? e.invoke_mean_ns * e.invokes / e.busy_ns : 0}};
    if (!e.queue.is_null()) x["queue"] = e.queue;
    els.push_back(std::move(x));
  }
  j["elements"] = std::move(els);
  json links = json::array();
  for (const auto &k : r.links)
    links.push_back(json{{"from", k.from},
                         {"to", k.to},
                         {"from_pad", k.from_pad},
                         {"to_pad", k.to_pad},
                         {"mode", k.mode},
                         {"buffers", k.buffers},
                         {"bytes", k.bytes},
                         {"rate", k.rate},
                         {"bytes_rate", k.bytes_rate},
                         {"to_sink", k.to_sink},
                         {"latency", json{{"count", k.latency_count},
                                          {"mean_ns", k.latency_mean_ns},
                                          {"min_ns", k.latency_min_ns},
                                          {"max_ns", k.latency_max_ns},
                                          {"quantiles", quant_json(k.latency_q)}}}});
  j["links"] = std::move(links);
  json th = json::array();
  for (const auto &t : r.threads)
    th.push_back(json{{"tid", t.tid},
                      {"name", t.name},
                      {"root", t.root},
                      {"wall_ns", t.wall_ns},
                      {"cpu_ns", t.cpu_ns},
                      {"cpu_share", t.cpu_share},
                      {"pushes", t.pushes}});
  j["threads"] = std::move(th);
  return j;
}

}  // namespace nns::profile::report
