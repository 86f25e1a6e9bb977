// SPDX-License-Identifier: LGPL-2.1-only
// The nnsprofile tracer on known pipelines: an identity that sleeps a known time is where the
// time goes, counts are exact, latencies and queue levels are what the pipeline forces, and
// tensor_filter's invoke time is the one its latency property reports.
#include <gtest/gtest.h>
#include <time.h>

#include <filesystem>
#include <fstream>
#include <mutex>
#include <vector>
#include <stdexcept>

#include <cstring>

#include "tensor_filter_custom_easy.h"
#include "profile/profile_test_util.h"
#include "profile/profiler.h"

namespace nns::test {
namespace {

TEST(NnsProfile, SleepingIdentityOwnsItsTimeAndCountsAreExact) {
  auto r = run_named("p_sleep",
                     "videotestsrc num-buffers=40 ! "
                     "capsfilter name=cf caps=video/x-raw,format=GRAY8,width=16,height=16 ! "
                     "identity name=slow sleep-time=4000 ! identity name=fast ! "
                     "fakesink name=out sync=false");
  ASSERT_TRUE(r.eos) << r.error_text;
  Figures f = figures_of("p_sleep");
  ASSERT_TRUE(f.elements.count("slow") && f.elements.count("fast") && f.elements.count("out"));
  const json &slow = f.elements["slow"], &fast = f.elements["fast"];
  EXPECT_EQ(slow["spans"], 40);
  EXPECT_EQ(fast["spans"], 40);
  EXPECT_EQ(f.elements["out"]["spans"], 40);
  EXPECT_EQ(slow["kind"], "filter");
  EXPECT_EQ(f.elements["out"]["kind"], "sink");
  EXPECT_FALSE(f.elements["out"]["clock_wait"].get<bool>());  // sync=false
  // sleep-time=4000 us: at least 4 ms per buffer; all in one thread, so the spans cannot add up
  // to more than the run (first to last buffer on the sink link, plus the last span).
  const double slow_ms = mean_ms(slow, "self_ns", "spans");
  EXPECT_GE(slow_ms, 4.0);
  const json &sink_link = f.links["fast>out"];
  const double run_ms =
      (sink_link["last_ns"].get<double>() - f.links["cf>slow"]["first_ns"].get<double>()) / 1e6;
  EXPECT_LE(slow_ms * 40, run_ms + 1.0);
  EXPECT_GT(slow_ms * 40, 0.8 * run_ms);  // and it is most of the run
  EXPECT_LT(mean_ms(fast, "self_ns", "spans"), 0.25 * slow_ms);
  // The slow identity's downstream work is not part of its own time, and the histogram holds
  // every span.
  uint64_t in_hist = 0;
  for (const auto &b : slow["self_hist"]) {
    in_hist += b[1].get<uint64_t>();
    EXPECT_GE(b[0].get<int64_t>(), 3000000);  // every bucket at or above ~4 ms
  }
  EXPECT_EQ(in_hist, 40u);
  ASSERT_TRUE(f.links.count("slow>fast"));
  EXPECT_EQ(f.links["slow>fast"]["buffers"], 40);
  EXPECT_EQ(f.links["slow>fast"]["bytes"], 40 * 16 * 16);
  // End-to-end latency to the sink: the sleep plus a little.
  const json &to_sink = f.links["fast>out"];
  EXPECT_EQ(to_sink["latency"]["count"], 40);
  const double lat_ms = mean_ms(to_sink["latency"], "total_ns", "count");
  EXPECT_GE(lat_ms, slow_ms);         // the sleep is on the way from the source to the sink
  EXPECT_LT(lat_ms, slow_ms + 20.0);  // a loaded machine delays buffers between elements too
  ASSERT_EQ(to_sink["latency_by_source"].size(), 1u);
  const int src_id = to_sink["latency_by_source"][0]["source"].get<int>();
  EXPECT_EQ(f.all["elements"][src_id]["factory"], "videotestsrc");
}

TEST(NnsProfile, QueueLevelsAndThreads) {
  // A fast source into a 4-buffer queue drained by a 3 ms sleeper: the queue stays full.
  auto r = run_named("p_queue",
                     "videotestsrc name=src num-buffers=60 ! video/x-raw,width=8,height=8 ! "
                     "queue name=q max-size-buffers=4 max-size-bytes=0 max-size-time=0 ! "
                     "identity name=slow sleep-time=3000 ! fakesink sync=false");
  ASSERT_TRUE(r.eos) << r.error_text;
  Figures f = figures_of("p_queue");
  const json &q = f.elements["q"];
  EXPECT_EQ(q["kind"], "queue");
  ASSERT_TRUE(q.contains("queue"));
  const json &lv = q["queue"];
  EXPECT_GT(lv["samples"].get<int>(), 10);
  EXPECT_EQ(lv["max_size_buffers"], 4);
  EXPECT_LE(lv["max_buffers"].get<int>(), 4);
  EXPECT_GE(lv["max_buffers"].get<int>(), 3);
  EXPECT_GT(lv["full_samples"].get<double>(), 0.5 * lv["samples"].get<double>());
  EXPECT_EQ(f.links["q>slow"]["buffers"], 60);
  // Two streaming threads: the source's and the queue's; the queue's thread mostly sleeps.
  int src_threads = 0, q_threads = 0;
  for (const auto &t : f.threads) {
    const std::string root = f.all["elements"][t["root"].get<int>()]["name"];
    const double wall = t["last_ns"].get<double>() - t["first_ns"].get<double>();
    EXPECT_GT(t["cpu_ns"].get<double>(), 0) << root;
    if (root == "src") ++src_threads;
    if (root == "q") {
      ++q_threads;
      EXPECT_GE(wall, 60 * 3e6);
      EXPECT_LT(t["cpu_ns"].get<double>(), 0.5 * wall);
    }
  }
  EXPECT_EQ(src_threads, 1);
  EXPECT_EQ(q_threads, 1);
  EXPECT_TRUE(q["boundary"].get<bool>());
}

GstTensorsInfo u8_info(std::initializer_list<uint32_t> dims) {
  GstTensorsInfo i;
  std::memset(&i, 0, sizeof i);
  i.num_tensors = 1;
  i.info[0].type = _NNS_UINT8;
  unsigned k = 0;
  for (uint32_t d : dims) i.info[0].dimension[k++] = d;
  return i;
}

int sleep_copy(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
               GstTensorMemory *out) {
  timespec ts{0, 3000000};
  nanosleep(&ts, nullptr);
  std::memcpy(out[0].data, in[0].data, in[0].size);
  return 0;
}

TEST(NnsProfile, FilterInvokeTimeIsTheLatencyPropertysMeasurement) {
  GstTensorsInfo i = u8_info({1, 4, 4, 1});
  ASSERT_EQ(NNS_custom_easy_register("prof_sleep3ms", sleep_copy, nullptr, &i, &i), 0);
  profile_file();
  GstElement *p = gst_parse_launch(
      "videotestsrc num-buffers=10 ! video/x-raw,format=GRAY8,width=4,height=4 ! "
      "tensor_converter ! tensor_filter name=tf framework=custom-easy model=prof_sleep3ms "
      "latency=1 ! fakesink sync=false",
      nullptr);
  ASSERT_TRUE(p);
  gst_object_set_name(GST_OBJECT(p), "p_filter");
  GstElement *tf = gst_bin_get_by_name(GST_BIN(p), "tf");
  // The invokes are also logged as "nnsprofile-invoke" tracer records.
  struct Lines {
    std::mutex mu;
    std::vector<std::string> v;
  } lines;
  auto capture = [](GstDebugCategory *cat, GstDebugLevel, const gchar *, const gchar *, gint,
                    GObject *, GstDebugMessage *msg, gpointer data) {
    const char *text = gst_debug_message_get(msg);
    if (std::strcmp(gst_debug_category_get_name(cat), "GST_TRACER") || !text ||
        !std::strstr(text, "nnsprofile-invoke"))
      return;
    auto *l = static_cast<Lines *>(data);
    std::lock_guard<std::mutex> lk(l->mu);
    l->v.emplace_back(text);
  };
  gst_debug_set_threshold_for_name("GST_TRACER", GST_LEVEL_TRACE);
  const GstLogFunction capture_fn = capture;
  gst_debug_add_log_function(capture_fn, &lines, nullptr);
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstBus *bus = gst_element_get_bus(p);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 20 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  ASSERT_TRUE(m && GST_MESSAGE_TYPE(m) == GST_MESSAGE_EOS);
  gst_message_unref(m);
  gst_debug_remove_log_function(capture_fn);
  gst_debug_set_threshold_for_name("GST_TRACER", GST_LEVEL_NONE);
  gint latency_us = -1;
  g_object_get(tf, "latency", &latency_us, nullptr);
  Figures f = figures_of("p_filter");
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(bus);
  gst_object_unref(tf);
  gst_object_unref(p);
  EXPECT_EQ(NNS_custom_easy_unregister("prof_sleep3ms"), 0);

  const json &e = f.elements["tf"];
  EXPECT_EQ(e["invokes"], 10);
  EXPECT_EQ(e["spans"], 10);
  const double inv_ms = mean_ms(e, "invoke_ns", "invokes");
  EXPECT_GE(inv_ms, 3.0);
  EXPECT_LT(inv_ms, 40.0);
  // The element's own time holds the invoke and a little more (the invoke is most of it).
  EXPECT_GE(e["self_ns"].get<int64_t>(), e["invoke_ns"].get<int64_t>());
  EXPECT_GT(inv_ms, 0.7 * mean_ms(e, "self_ns", "spans"));
  ASSERT_EQ(lines.v.size(), 10u);
  EXPECT_NE(lines.v[0].find("nnsprofile-invoke, element=(string)tf, time=(guint64)"),
            std::string::npos)
      << lines.v[0];
  // latency=1 averages the same invoke times (the last 10 of them: all here), in us.
  EXPECT_NEAR(latency_us, e["invoke_ns"].get<double>() / 10 / 1000, 1.0);
}

TEST(NnsProfile, PullModeLinksAndTheirTime) {
  const std::string wav = make_temp_dir() + "/a.wav";
  ASSERT_TRUE(run_pipeline("audiotestsrc num-buffers=20 samplesperbuffer=1024 ! "
                           "audio/x-raw,format=S16LE,rate=16000,channels=1 ! wavenc ! "
                           "filesink location=" +
                           wav)
                  .eos);
  // wavparse pulls from filesrc in its own task and pushes downstream.
  auto r = run_named("p_pull", "filesrc name=file location=" + wav +
                                   " ! wavparse name=parse ! fakesink name=sink sync=false");
  ASSERT_TRUE(r.eos) << r.error_text;
  Figures f = figures_of("p_pull");
  ASSERT_TRUE(f.links.count("file>parse"));
  const json &l = f.links["file>parse"];
  EXPECT_EQ(l["mode"], "pull");
  EXPECT_GT(l["buffers"].get<int>(), 1);
  // Every byte of the file crossed the link (wavparse reads some chunk headers twice).
  const auto size = std::filesystem::file_size(wav);
  EXPECT_GT(size, 20u * 1024 * 2);
  EXPECT_GE(l["bytes"].get<uint64_t>(), size);
  EXPECT_LT(l["bytes"].get<uint64_t>(), size + 256);
  EXPECT_EQ(f.elements["file"]["pulls"], l["buffers"]);
  EXPECT_GT(f.elements["file"]["pull_ns"].get<int64_t>(), 0);
  EXPECT_EQ(f.links["parse>sink"]["mode"], "push");
  EXPECT_GT(f.elements["sink"]["spans"].get<int>(), 0);
  ASSERT_EQ(f.threads.size(), 1u);
  EXPECT_EQ(f.all["elements"][f.threads[0]["root"].get<int>()]["name"], "parse");
}

TEST(NnsProfile, LinksGoThroughBinsAndSpansAreNotCountedTwice) {
  // identity inside a bin (ghost pads on both sides), and decodebin's dynamic children.
  auto r = run_named("p_bin",
                     "videotestsrc num-buffers=20 ! "
                     "capsfilter name=cf caps=video/x-raw,width=16,height=16 ! "
                     "bin.( identity name=inner sleep-time=2000 ) ! jpegenc name=enc ! "
                     "decodebin ! fakesink name=sink sync=false");
  ASSERT_TRUE(r.eos) << r.error_text;
  Figures f = figures_of("p_bin");
  ASSERT_TRUE(f.elements.count("inner"));
  EXPECT_EQ(f.elements["inner"]["spans"], 20);
  EXPECT_GE(mean_ms(f.elements["inner"], "self_ns", "spans"), 2.0);
  EXPECT_EQ(f.elements["enc"]["spans"], 20);
  EXPECT_EQ(f.elements["sink"]["spans"], 20);
  EXPECT_EQ(f.links["cf>inner"]["buffers"], 20) << f.all.dump();
  EXPECT_EQ(f.links["inner>enc"]["buffers"], 20);
  // enc -> decodebin's typefind -> ... -> sink: a chain of element-to-element links.
  ASSERT_TRUE(f.links.count("enc>typefind"));
  std::string at = "typefind";
  for (int hop = 0; hop < 5 && at != "sink"; ++hop) {
    std::string next;
    for (const auto &[k, l] : f.links)
      if (k.rfind(at + ">", 0) == 0) next = k.substr(at.size() + 1);
    ASSERT_FALSE(next.empty()) << "no link out of " << at;
    EXPECT_EQ(f.elements[next]["spans"], 20) << next;
    at = next;
  }
  EXPECT_EQ(at, "sink");
}

TEST(NnsProfile, LiveSourcesAndSyncSinksAreFlagged) {
  auto r = run_named("p_live",
                     "videotestsrc name=live is-live=true num-buffers=3 ! "
                     "video/x-raw,width=8,height=8,framerate=100/1 ! "
                     "fakesink name=synced sync=true");
  ASSERT_TRUE(r.eos) << r.error_text;
  Figures f = figures_of("p_live");
  EXPECT_TRUE(f.elements["live"]["clock_wait"].get<bool>());
  EXPECT_TRUE(f.elements["synced"]["clock_wait"].get<bool>());
  EXPECT_EQ(f.elements["synced"]["spans"], 3);
}

TEST(NnsProfile, WritesTheFileWhenAPipelineStops) {
  const std::string file = profile_file();
  auto r = run_named("p_file", "videotestsrc num-buffers=5 ! fakesink name=file_sink");
  ASSERT_TRUE(r.eos);
  std::ifstream in(file);
  ASSERT_TRUE(in.good()) << file;
  json j = json::parse(in);
  EXPECT_EQ(j["format"], "nnsprofile");
  EXPECT_EQ(j["reason"], "stop");
  bool seen = false;
  for (const auto &e : j["elements"])
    if (e["name"] == "file_sink" && e["pipeline"] == "p_file" && e["spans"] == 5) seen = true;
  EXPECT_TRUE(seen);
}

TEST(NnsProfile, ParametersAreChecked) {
  EXPECT_EQ(nns::profile::parse_params("file=/tmp/x.json,interval=250").interval_ms, 250);
  EXPECT_EQ(nns::profile::parse_params(nullptr).interval_ms, 1000);
  try {
    nns::profile::parse_params("bogus=1");
    FAIL() << "no exception";
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("unknown parameter 'bogus'"), std::string::npos);
  }
  try {
    nns::profile::parse_params("interval=-5");
    FAIL() << "no exception";
  } catch (const std::invalid_argument &e) {
    EXPECT_NE(std::string(e.what()).find("'interval' must be an integer >= 0, got '-5'"),
              std::string::npos)
        << e.what();
  }
}

TEST(NnsProfileHist, BucketsAreOrderedAndQuantilesFallInside) {
  using namespace nns::profile;
  EXPECT_EQ(hist_bucket(0), 0);
  EXPECT_EQ(hist_bucket(63), 0);
  for (int k = 1; k < kHistBuckets - 1; ++k) {
    EXPECT_LT(hist_lower(k), hist_lower(k + 1));
    EXPECT_EQ(hist_bucket(hist_lower(k)), k);
    EXPECT_EQ(hist_bucket(hist_lower(k + 1) - 1), k);
    EXPECT_LE(hist_lower(k + 1) - hist_lower(k), hist_lower(k) / 4 + 1);
  }
  Hist h;
  for (int i = 0; i < 90; ++i) h.add(1000000);
  for (int i = 0; i < 10; ++i) h.add(50000000);
  auto nz = h.nonzero();
  ASSERT_EQ(nz.size(), 2u);
  const int64_t p50 = hist_quantile(nz, 0.5), p99 = hist_quantile(nz, 0.99);
  EXPECT_GE(p50, 800000);
  EXPECT_LE(p50, 1250000);
  EXPECT_GE(p99, 40000000);
  EXPECT_LE(p99, 62500000);
}

}  // namespace
}  // namespace nns::test
