// SPDX-License-Identifier: LGPL-2.1-only
// nns-profile's analysis on a hand-made tracer output: every derived figure is checked against
// the arithmetic of docs/profiler.md, and the three reports carry them.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "report.h"

namespace {

using nlohmann::json;
namespace rp = nns::profile::report;

// src (source) -> work (filter, 3 ms per buffer, invoke 2 ms) -> q (queue) -> out (sink), 100
// buffers over one second; plus the top-level bin, which the report leaves out.
json trace() {
  auto el = [](int id, const char *name, const char *factory, const char *kind) {
    return json{{"id", id},
                {"name", name},
                {"factory", factory},
                {"pipeline", "p"},
                {"kind", kind},
                {"spans", 0},
                {"self_ns", 0},
                {"self_max_ns", 0},
                {"self_hist", json::array()},
                {"gaps", 0},
                {"gap_ns", 0},
                {"pulls", 0},
                {"pull_ns", 0},
                {"invokes", 0},
                {"invoke_ns", 0},
                {"invoke_max_ns", 0},
                {"invoke_hist", json::array()},
                {"first_ns", 0},
                {"last_ns", 0}};
  };
  json t;
  t["format"] = "nnsprofile";
  t["version"] = 1;
  json src = el(0, "src", "videotestsrc", "source");
  src["gaps"] = 99;
  src["gap_ns"] = 99 * 100000;  // 0.1 ms per buffer
  json work = el(1, "work", "tensor_filter", "filter");
  work["spans"] = 100;
  work["self_ns"] = 100 * 3000000;
  work["self_max_ns"] = 3500000;
  work["self_hist"] = json::array({json::array({2621440, 60}), json::array({3145728, 40})});
  work["invokes"] = 100;
  work["invoke_ns"] = 100 * 2000000;
  work["invoke_max_ns"] = 2100000;
  work["invoke_hist"] = json::array({json::array({1835008, 100})});
  json q = el(2, "q", "queue", "queue");
  q["spans"] = 100;
  q["self_ns"] = 50000000;
  q["queue"] = json{{"samples", 10},       {"full_samples", 5},    {"sum_buffers", 30},
                    {"max_buffers", 4},    {"sum_bytes", 300},     {"max_bytes", 40},
                    {"sum_time_ns", 0},    {"max_time_ns", 0},     {"max_size_buffers", 4},
                    {"max_size_bytes", 0}, {"max_size_time_ns", 0}};
  json out = el(3, "out", "fakesink", "sink");
  out["spans"] = 100;
  out["self_ns"] = 100 * 1000000;
  json bin = el(4, "p", "pipeline", "bin");
  bin["pipeline"] = "";
  t["elements"] = json::array({src, work, q, out, bin});
  auto link = [](int from, int to, const char *fp, const char *tp, int64_t first, int64_t last,
                 int64_t lat_total) {
    return json{{"from", from},
                {"to", to},
                {"from_pad", fp},
                {"to_pad", tp},
                {"mode", "push"},
                {"source", from == 0},
                {"buffers", 100},
                {"bytes", 100 * 1000},
                {"first_ns", first},
                {"last_ns", last},
                {"latency", json{{"count", lat_total ? 100 : 0},
                                 {"total_ns", lat_total},
                                 {"min_ns", lat_total ? lat_total / 100 : 0},
                                 {"max_ns", lat_total ? lat_total / 100 : 0}}},
                {"latency_hist", json::array()},
                {"latency_by_source", json::array()}};
  };
  t["links"] = json::array({link(0, 1, "src:src", "work:sink", 0, 990000000, 0),
                            link(1, 2, "work:src", "q:sink", 3000000, 993000000, 100 * 3000000),
                            link(2, 3, "q:src", "out:sink", 4000000, 1000000000, 100 * 5000000)});
  t["threads"] = json::array({json{{"tid", 10},
                                   {"name", "src:src"},
                                   {"root", 0},
                                   {"first_ns", 0},
                                   {"last_ns", 1000000000},
                                   {"pushes", 200},
                                   {"cpu_ns", 400000000}},
                              json{{"tid", 11},
                                   {"name", "q:src"},
                                   {"root", 2},
                                   {"first_ns", 0},
                                   {"last_ns", 1000000000},
                                   {"pushes", 100},
                                   {"cpu_ns", 100000000}}});
  return t;
}

TEST(NnsProfileReport, DerivedFiguresAndBottleneck) {
  rp::Report r = rp::analyse(trace(), "p", "test");
  EXPECT_EQ(r.duration_ns, 1000000000);
  ASSERT_EQ(r.elements.size(), 4u);  // the bin is left out
  // Sorted by share: work (300 ms), out (100 ms), src (9.9 ms), q (waits: 0).
  EXPECT_EQ(r.elements[0].name, "work");
  EXPECT_EQ(r.elements[1].name, "out");
  EXPECT_EQ(r.elements[2].name, "src");
  EXPECT_EQ(r.elements[3].name, "q");
  const rp::Element &w = r.elements[0];
  EXPECT_EQ(w.buffers, 100u);
  EXPECT_EQ(w.busy_ns, 300000000);
  EXPECT_DOUBLE_EQ(w.busy, 0.3);
  EXPECT_DOUBLE_EQ(w.share, 300.0 / (300 + 100 + 9.9));
  EXPECT_DOUBLE_EQ(w.per_buffer_ns, 3000000);
  EXPECT_DOUBLE_EQ(w.invoke_mean_ns, 2000000);
  EXPECT_DOUBLE_EQ(w.in_rate, 100);
  EXPECT_EQ(r.elements[3].busy_ns, 0);
  EXPECT_EQ(r.elements[3].wait_ns, 50000000);
  EXPECT_DOUBLE_EQ(r.elements[3].queue["mean_buffers"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(r.elements[3].queue["full_share"].get<double>(), 0.5);
  EXPECT_EQ(r.elements[2].buffers, 100u);  // a source's buffers are what it pushed
  ASSERT_EQ(r.bottleneck, 0);
  EXPECT_NE(r.bottleneck_text.find("bottleneck: work (tensor_filter), busy 30.0%"),
            std::string::npos)
      << r.bottleneck_text;
  // Link figures.
  ASSERT_EQ(r.links.size(), 3u);
  EXPECT_DOUBLE_EQ(r.links[0].rate, 99 * 1e9 / 990000000);
  EXPECT_TRUE(r.links[2].to_sink);
  EXPECT_DOUBLE_EQ(r.links[2].latency_mean_ns, 5000000);
  ASSERT_EQ(r.threads.size(), 2u);
  EXPECT_EQ(r.threads[0].root, "src");
  EXPECT_DOUBLE_EQ(r.threads[0].cpu_share, 0.4);
}

TEST(NnsProfileReport, TextTableJsonAndHtmlCarryTheFigures) {
  rp::Report r = rp::analyse(trace(), "p", "a<b> & c");
  const std::string text = rp::text_table(r);
  EXPECT_NE(text.find("bottleneck: work (tensor_filter)"), std::string::npos) << text;
  // The table is sorted by share: work's row comes before out's, before src's.
  const auto pw = text.find("\nwork "), po = text.find("\nout "), ps = text.find("\nsrc ");
  ASSERT_NE(pw, std::string::npos);
  EXPECT_LT(pw, po);
  EXPECT_LT(po, ps);
  EXPECT_NE(text.find("mean    5.00 ms"), std::string::npos) << text;
  json j = rp::report_json(r);
  EXPECT_EQ(j["tool"], "nns-profile");
  EXPECT_EQ(j["bottleneck"], "work");
  EXPECT_EQ(j["elements"].size(), 4u);
  for (const char *k :
       {"name", "factory", "kind", "buffers", "busy_ns", "wait_ns", "busy", "share",
        "per_buffer_ns", "max_ns", "quantiles", "hist", "in_rate", "out_rate", "invokes"})
    EXPECT_TRUE(j["elements"][0].contains(k)) << k;
  EXPECT_DOUBLE_EQ(j["elements"][0]["invoke"]["share_of_busy"].get<double>(), 2.0 / 3.0);
  for (const char *k : {"from", "to", "from_pad", "to_pad", "mode", "buffers", "bytes", "rate",
                        "bytes_rate", "to_sink", "latency"})
    EXPECT_TRUE(j["links"][0].contains(k)) << k;
  const std::string html = rp::html_page(r);
  EXPECT_NE(html.find("a&lt;b&gt; &amp; c"), std::string::npos);  // escaped title
  for (const char *n : {"work", "out", "src", "q"})
    EXPECT_NE(html.find(std::string("data-name=\"") + n + "\""), std::string::npos) << n;
  EXPECT_EQ(html.find("src=\""), std::string::npos);  // nothing loaded from anywhere
  EXPECT_EQ(html.find("href="), std::string::npos);
}

TEST(NnsProfileReport, RejectsOtherJson) {
  try {
    rp::analyse(json{{"format", "other"}}, "", "x");
    FAIL();
  } catch (const std::runtime_error &e) {
    EXPECT_NE(std::string(e.what()).find("not nnsprofile tracer output"), std::string::npos);
  }
  json t = trace();
  t.erase("links");
  EXPECT_THROW(rp::analyse(t, "", "x"), std::runtime_error);
}

}  // namespace
