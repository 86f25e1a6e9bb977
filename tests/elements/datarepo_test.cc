// SPDX-License-Identifier: LGPL-2.1-only
// datareposink writes, datareposrc reads back: static tensors (with tensors-sequence), flexible
// tensors (headers kept), video, audio, octet, images; epochs, ranges and the seeded shuffle;
// errors naming the sample index and byte offset.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "core/datarepo/datarepo_meta.h"
#include "core/datarepo/sample_order.h"
#include "core/meta_header.h"
#include "elements/stream_util.h"
#include "support/harness.h"

namespace fs = std::filesystem;
using nns::test::make_buffer;
using nns::test::Pipe;
using nns::test::run_pipeline;
using nns::test::tensor_bytes;

namespace {

struct TempDir {
  fs::path dir = nns::test::make_temp_dir();
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string operator/(const std::string &name) const { return (dir / name).string(); }
};

std::vector<uint8_t> bytes_of(const std::string &path) {
  return nns::test::read_file(path);
}

nns::datarepo::Meta meta_of(const std::string &path) {
  std::ifstream f(path);
  std::string s((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return nns::datarepo::parse_meta(s, path);
}

std::vector<uint8_t> all_bytes(GstBuffer *b) {
  std::vector<uint8_t> v;
  for (guint i = 0; i < gst_buffer_n_memory(b); ++i) {
    auto t = tensor_bytes(b, i);
    v.insert(v.end(), t.begin(), t.end());
  }
  return v;
}

// Sample k of a two-tensor static stream: uint8[3] then float32[2].
std::vector<std::vector<uint8_t>> two_tensors(int k) {
  std::vector<uint8_t> a = {uint8_t(k), uint8_t(k + 1), uint8_t(k + 2)};
  float f[2] = {k * 0.5f, -k * 1.0f};
  std::vector<uint8_t> b(reinterpret_cast<uint8_t *>(f), reinterpret_cast<uint8_t *>(f) + 8);
  return {a, b};
}

const char *kTwoCaps =
    "other/tensors,format=static,num_tensors=2,dimensions=(string)3.2,"
    "types=(string)uint8.float32,framerate=(fraction)10/1";

void write_two_tensor_repo(const TempDir &d, int samples) {
  Pipe w(nns::test::appsrc("in", kTwoCaps) + "! datareposink location=" + d / "s.dat" +
         " json=" + d / "s.json");
  gst_element_set_state(w.pipeline(), GST_STATE_PLAYING);
  for (int k = 0; k < samples; ++k)
    w.push("in", make_buffer(two_tensors(k), k * GST_MSECOND * 100));
  w.eos("in");
  auto r = w.run();
  ASSERT_TRUE(r.eos) << r.error_text;
}

}  // namespace

TEST(Datarepo, StaticTensorsRoundTripWithSequence) {
  TempDir d;
  write_two_tensor_repo(d, 6);
  auto m = meta_of(d / "s.json");
  EXPECT_EQ(m.total_samples, 6u);
  EXPECT_EQ(m.sample_size, 11u);
  auto file = bytes_of(d / "s.dat");
  ASSERT_EQ(file.size(), 66u);
  for (int k = 0; k < 6; ++k) {
    auto t = two_tensors(k);
    EXPECT_TRUE(std::equal(t[0].begin(), t[0].end(), file.begin() + k * 11));
    EXPECT_TRUE(std::equal(t[1].begin(), t[1].end(), file.begin() + k * 11 + 3));
  }
  // Read back samples 1..4 in order, the float tensor first.
  Pipe r("datareposrc location=" + d / "s.dat" + " json=" + d / "s.json" +
         " start-sample-index=1 stop-sample-index=4 is-shuffle=false tensors-sequence=1,0 ! "
         "appsink name=out sync=false");
  r.collect("out");
  auto res = r.run();
  ASSERT_TRUE(res.eos) << res.error_text;
  ASSERT_EQ(r.out().size(), 4u);
  for (int i = 0; i < 4; ++i) {
    GstBuffer *b = r.out()[i];
    auto t = two_tensors(i + 1);
    ASSERT_EQ(gst_buffer_n_memory(b), 2u);
    EXPECT_EQ(tensor_bytes(b, 0), t[1]);
    EXPECT_EQ(tensor_bytes(b, 1), t[0]);
    EXPECT_EQ(GST_BUFFER_OFFSET(b), guint64(i + 1));
    EXPECT_EQ(GST_BUFFER_PTS(b), i * 100 * GST_MSECOND);
    EXPECT_EQ(GST_BUFFER_DURATION(b), 100 * GST_MSECOND);
  }
  // The caps follow the sequence: float32 first.
  Pipe c("datareposrc location=" + d / "s.dat" + " json=" + d / "s.json" +
         " tensors-sequence=1,0 ! appsink name=out sync=false");
  gst_element_set_state(c.pipeline(), GST_STATE_PLAYING);
  GstSample *smp = gst_app_sink_try_pull_sample(GST_APP_SINK(c.get("out")), 5 * GST_SECOND);
  ASSERT_NE(smp, nullptr);
  gchar *cs = gst_caps_to_string(gst_sample_get_caps(smp));
  EXPECT_NE(std::string(cs).find("float32\\,uint8"), std::string::npos) << cs;
  EXPECT_NE(std::string(cs).find("2\\,3"), std::string::npos) << cs;
  g_free(cs);
  gst_sample_unref(smp);
}

TEST(Datarepo, EpochsAndSeededShuffle) {
  TempDir d;
  write_two_tensor_repo(d, 8);
  auto order_of = [&](const std::string &extra) {
    Pipe r("datareposrc location=" + d / "s.dat" + " json=" + d / "s.json" + " " + extra +
           " ! appsink name=out sync=false");
    r.collect("out");
    auto res = r.run();
    EXPECT_TRUE(res.eos) << res.error_text;
    std::vector<uint32_t> idx;
    for (GstBuffer *b : r.out()) {
      idx.push_back(static_cast<uint32_t>(GST_BUFFER_OFFSET(b)));
      EXPECT_EQ(tensor_bytes(b, 0), two_tensors(idx.back())[0]);  // data matches the index
    }
    return idx;
  };
  auto a = order_of("epochs=3 shuffle-seed=11");
  auto b = order_of("epochs=3 shuffle-seed=11");
  ASSERT_EQ(a.size(), 24u);
  EXPECT_EQ(a, b);
  nns::datarepo::SampleOrder ref(0, 7, 3, true, 11);
  std::vector<uint32_t> want;
  uint32_t i;
  while (ref.next(&i)) want.push_back(i);
  EXPECT_EQ(a, want);
  for (int e = 0; e < 3; ++e)
    EXPECT_EQ(std::set<uint32_t>(a.begin() + e * 8, a.begin() + e * 8 + 8).size(), 8u);
  EXPECT_EQ(order_of("epochs=2 is-shuffle=false stop-sample-index=2"),
            (std::vector<uint32_t>{0, 1, 2, 0, 1, 2}));
}

TEST(Datarepo, FlexibleTensorsKeepTheirHeaders) {
  TempDir d;
  auto flex = [](int k) {
    // Sample k: (k % 3) + 1 tensors of k+1 int16 values each, with their headers.
    std::vector<std::vector<uint8_t>> ts;
    for (int t = 0; t < k % 3 + 1; ++t) {
      nns::MetaHeader h;
      h.type = nns::TensorType::kInt16;
      h.dims = nns::make_dims({static_cast<uint32_t>(k + 1)});
      h.format = nns::TensorFormat::kFlexible;
      std::vector<uint8_t> mem(nns::kMetaHeaderSize + 2 * (k + 1));
      nns::write_meta_header(h, mem.data());
      for (std::size_t j = nns::kMetaHeaderSize; j < mem.size(); ++j)
        mem[j] = uint8_t(k * 7 + t + j);
      ts.push_back(mem);
    }
    return ts;
  };
  {
    Pipe w(nns::test::appsrc("in", "other/tensors,format=flexible,framerate=(fraction)0/1") +
           "! datareposink location=" + d / "f.dat" + " json=" + d / "f.json");
    gst_element_set_state(w.pipeline(), GST_STATE_PLAYING);
    for (int k = 0; k < 5; ++k) w.push("in", make_buffer(flex(k), k * GST_MSECOND));
    w.eos("in");
    auto r = w.run();
    ASSERT_TRUE(r.eos) << r.error_text;
  }
  auto m = meta_of(d / "f.json");
  ASSERT_TRUE(m.per_sample());
  EXPECT_EQ(m.tensor_count, (std::vector<uint64_t>{0, 1, 3, 6, 7}));
  EXPECT_EQ(m.sample_offset[1], 130u);  // sample 0: one tensor of 128 + 2 bytes
  EXPECT_EQ(m.tensor_size.size(), 9u);
  Pipe r("datareposrc location=" + d / "f.dat" + " json=" + d / "f.json" +
         " is-shuffle=false ! appsink name=out sync=false");
  r.collect("out");
  auto res = r.run();
  ASSERT_TRUE(res.eos) << res.error_text;
  ASSERT_EQ(r.out().size(), 5u);
  for (int k = 0; k < 5; ++k) {
    auto want = flex(k);
    ASSERT_EQ(gst_buffer_n_memory(r.out()[k]), want.size());
    for (std::size_t t = 0; t < want.size(); ++t)
      EXPECT_EQ(tensor_bytes(r.out()[k], t), want[t]) << "sample " << k << " tensor " << t;
  }
  // A corrupted header is an error naming the sample and the byte offset.
  {
    std::fstream f(d / "f.dat", std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(m.sample_offset[2] + m.tensor_size[3]));
    f.put('\x42');
  }
  auto bad = run_pipeline("datareposrc location=" + d / "f.dat" + " json=" + d / "f.json" +
                          " is-shuffle=false ! fakesink");
  ASSERT_TRUE(bad.error);
  EXPECT_NE(bad.error_text.find("sample 2, tensor 1"), std::string::npos) << bad.error_text;
  EXPECT_NE(
      bad.error_text.find("byte offset " + std::to_string(m.sample_offset[2] + m.tensor_size[3])),
      std::string::npos)
      << bad.error_text;
}

TEST(Datarepo, VideoAudioOctetAndImages) {
  TempDir d;
  // Video
  ASSERT_TRUE(run_pipeline("videotestsrc num-buffers=4 pattern=ball ! "
                           "video/x-raw,format=RGB,width=20,height=10,framerate=5/1 ! tee name=t "
                           "t. ! queue ! datareposink location=" +
                           d / "v.dat" + " json=" + d / "v.json" +
                           " t. ! queue ! filesink location=" + d / "v.raw")
                  .eos);
  EXPECT_EQ(meta_of(d / "v.json").sample_size, 600u);
  EXPECT_EQ(bytes_of(d / "v.dat"), bytes_of(d / "v.raw"));
  ASSERT_TRUE(run_pipeline("datareposrc location=" + d / "v.dat" + " json=" + d / "v.json" +
                           " is-shuffle=false ! video/x-raw,format=RGB,width=20 ! filesink "
                           "location=" +
                           d / "v.back")
                  .eos);
  EXPECT_EQ(bytes_of(d / "v.back"), bytes_of(d / "v.raw"));
  // Audio: 3 buffers of 100 samples
  ASSERT_TRUE(run_pipeline("audiotestsrc num-buffers=3 samplesperbuffer=100 ! "
                           "audio/x-raw,format=S16LE,rate=8000,channels=1,layout=interleaved ! "
                           "datareposink location=" +
                           d / "a.dat" + " json=" + d / "a.json")
                  .eos);
  EXPECT_EQ(meta_of(d / "a.json").sample_size, 200u);
  ASSERT_TRUE(run_pipeline("datareposrc location=" + d / "a.dat" + " json=" + d / "a.json" +
                           " is-shuffle=false ! filesink location=" + d / "a.back")
                  .eos);
  EXPECT_EQ(bytes_of(d / "a.back"), bytes_of(d / "a.dat"));
  // Images: one PNG per sample
  ASSERT_TRUE(run_pipeline("videotestsrc num-buffers=3 ! video/x-raw,width=16,height=16 ! "
                           "pngenc ! datareposink location=" +
                           d / "img_%02d.png" + " json=" + d / "i.json")
                  .eos);
  ASSERT_TRUE(fs::exists(d / "img_02.png"));
  Pipe r("datareposrc location=" + d / "img_%02d.png" + " json=" + d / "i.json" +
         " is-shuffle=false ! appsink name=out sync=false");
  r.collect("out");
  ASSERT_TRUE(r.run().eos);
  ASSERT_EQ(r.out().size(), 3u);
  EXPECT_EQ(all_bytes(r.out()[1]), bytes_of(d / "img_01.png"));
}

// A repository as NNStreamer 2.7.0 writes it (nnstreamer 5b13ea6, docs/interop.md):
// `videotestsrc ! video/x-raw,format=RGB,width=8,height=6 ! tensor_converter !
// other/tensors,format=flexible ! datareposink`. Its meta text is json-glib's (`"key" : value`,
// one array element a line) and its tensor headers say format 0 (static), which is what
// NNStreamer's converter writes into a flexible header; ours writes 1. Both must be read as is.
TEST(Datarepo, ReadsARepositoryWrittenByNNStreamer270) {
  TempDir d;
  {
    std::ofstream j(d / "up.json", std::ios::binary);
    j << "{\n  \"gst_caps\" : \"other/tensors, format=(string)flexible, "
         "framerate=(fraction)10/1\",\n"
         "  \"total_samples\" : 6,\n  \"sample_offset\" : [\n    0,\n    272,\n    544,\n"
         "    816,\n    1088,\n    1360\n  ],\n  \"tensor_size\" : [\n    272,\n    272,\n"
         "    272,\n    272,\n    272,\n    272\n  ],\n  \"tensor_count\" : [\n    0,\n"
         "    1,\n    2,\n    3,\n    4,\n    5\n  ]\n}";
  }
  // NNStreamer's header: magic, version 1.0, type uint8 (5), dims 3:8:6:1, format 0, media 0.
  const uint8_t head[28] = {0xed, 0xcc, 0xed, 0xfe, 0x00, 0x10, 0x00, 0xde, 0x05, 0x00,
                            0x00, 0x00, 0x03, 0x00, 0x00, 0x00, 0x08, 0x00, 0x00, 0x00,
                            0x06, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00};
  auto sample = [&](int k) {
    std::vector<uint8_t> s(272, 0);
    std::copy(std::begin(head), std::end(head), s.begin());
    for (std::size_t j = 128; j < s.size(); ++j) s[j] = uint8_t(k * 31 + j);
    return s;
  };
  {
    std::ofstream f(d / "up.dat", std::ios::binary);
    for (int k = 0; k < 6; ++k) {
      auto s = sample(k);
      f.write(reinterpret_cast<const char *>(s.data()), static_cast<std::streamsize>(s.size()));
    }
  }
  Pipe r(
      "datareposrc location=" + d / "up.dat" + " json=" + d / "up.json" +
      " is-shuffle=false start-sample-index=1 stop-sample-index=4 ! appsink name=out sync=false");
  r.collect("out");
  auto res = r.run();
  ASSERT_TRUE(res.eos) << res.error_text;
  ASSERT_EQ(r.out().size(), 4u);
  for (int k = 1; k <= 4; ++k) {
    GstBuffer *b = r.out()[k - 1];
    ASSERT_EQ(gst_buffer_n_memory(b), 1u);
    EXPECT_EQ(tensor_bytes(b, 0), sample(k)) << "sample " << k;
    EXPECT_EQ(GST_BUFFER_PTS(b), static_cast<GstClockTime>(k - 1) * GST_MSECOND * 100);
  }
}

TEST(Datarepo, CapsPropertyWithoutJson) {
  TempDir d;
  write_two_tensor_repo(d, 4);
  Pipe r(std::string("datareposrc location=") + d / "s.dat" + " stop-sample-index=3 " +
         "is-shuffle=false caps=\"" + kTwoCaps + "\" ! appsink name=out sync=false");
  r.collect("out");
  auto res = r.run();
  ASSERT_TRUE(res.eos) << res.error_text;
  ASSERT_EQ(r.out().size(), 4u);
  EXPECT_EQ(tensor_bytes(r.out()[3], 1), two_tensors(3)[1]);
}

namespace {

void expect_error(const std::string &desc, std::initializer_list<std::string> parts) {
  auto r = run_pipeline(desc, 10);
  ASSERT_TRUE(r.error) << "no error for " << desc;
  for (const auto &p : parts) EXPECT_NE(r.error_text.find(p), std::string::npos) << r.error_text;
}

}  // namespace

TEST(DatarepoErrors, RangesSettingsAndDisagreements) {
  TempDir d;
  write_two_tensor_repo(d, 5);
  const std::string src = "datareposrc location=" + d / "s.dat" + " json=" + d / "s.json" + " ";
  expect_error(src + "start-sample-index=3 stop-sample-index=2 ! fakesink",
               {"start-sample-index 3", "stop-sample-index 2", "indices 0..4"});
  expect_error(src + "stop-sample-index=9 ! fakesink", {"stop-sample-index 9", "it has 5"});
  expect_error(src + "epochs=0 ! fakesink", {"epochs"});
  expect_error(src + "tensors-sequence=0,2 ! fakesink", {"tensors-sequence", "tensor 2"});
  expect_error("datareposrc json=" + d / "s.json" + " ! fakesink", {"location"});
  expect_error("datareposrc location=" + d / "s.dat" + " ! fakesink", {"json", "caps"});
  expect_error("datareposrc location=" + d / "missing.dat json=" + d / "s.json" + " ! fakesink",
               {"missing.dat"});
  // Truncated: sample 4 is cut.
  fs::resize_file(d / "s.dat", 50);
  expect_error(src + "! fakesink", {"sample 4", "byte offset 44", "needs 11 bytes", "has 6"});
  // JSON that disagrees with its caps.
  {
    std::ofstream(d / "bad.json") << "{\"gst_caps\":\"" << kTwoCaps
                                  << "\",\"total_samples\":4,\"sample_size\":12}";
  }
  expect_error("datareposrc location=" + d / "s.dat" + " json=" + d / "bad.json" + " ! fakesink",
               {"sample_size 12", "11 bytes"});
  { std::ofstream(d / "broken.json") << "{\"gst_caps\": 3}"; }
  expect_error("datareposrc location=" + d / "s.dat" + " json=" + d / "broken.json" + " ! fakesink",
               {"broken.json", "gst_caps"});
  // The sink: location and json are required; samples of one size.
  expect_error("videotestsrc num-buffers=1 ! datareposink json=" + d / "x.json", {"location"});
  expect_error("videotestsrc num-buffers=1 ! datareposink location=" + d / "x.dat", {"json"});
  expect_error(
      "videotestsrc num-buffers=2 ! video/x-raw,width=16,height=16 ! pngenc ! "
      "datareposink location=" +
          d / "img.png" + " json=" + d / "i.json",
      {"location", "integer conversion"});
}

TEST(Datarepo, OctetAndTextSamples) {
  TempDir d;
  for (const std::string caps : {"application/octet-stream", "text/x-raw,format=utf8"}) {
    {
      Pipe w(nns::test::appsrc("in", caps) + "! datareposink location=" + d / "o.dat" +
             " json=" + d / "o.json");
      gst_element_set_state(w.pipeline(), GST_STATE_PLAYING);
      for (int k = 0; k < 3; ++k) {
        std::vector<uint8_t> s = {uint8_t('a' + k), uint8_t('b' + k), uint8_t('c' + k), '\n'};
        w.push("in", make_buffer({s}, k * GST_MSECOND));
      }
      w.eos("in");
      ASSERT_TRUE(w.run().eos) << caps;
    }
    auto m = meta_of(d / "o.json");
    EXPECT_EQ(m.sample_size, 4u);
    EXPECT_EQ(m.total_samples, 3u);
    EXPECT_NE(m.caps.find(caps.substr(0, 10)), std::string::npos) << m.caps;
    Pipe r("datareposrc location=" + d / "o.dat" + " json=" + d / "o.json" +
           " is-shuffle=false start-sample-index=1 ! appsink name=out sync=false");
    r.collect("out");
    ASSERT_TRUE(r.run().eos) << caps;
    ASSERT_EQ(r.out().size(), 2u) << caps;
    EXPECT_EQ(all_bytes(r.out()[1]), (std::vector<uint8_t>{'c', 'd', 'e', '\n'})) << caps;
  }
}

// The repository's caps are '.'-spelled (as written by the appsrc above): a capsfilter with
// either spelling of several tensors negotiates the same config.
TEST(Datarepo, CapsfilterInEitherSpellingOfSeveralTensors) {
  TempDir d;
  write_two_tensor_repo(d, 2);
  for (const std::string &filter :
       {std::string("other/tensors,num_tensors=2,dimensions=(string)\"3:1,2\","
                    "types=(string)\"uint8,float32\""),
        std::string("other/tensors,num_tensors=2,dimensions=3.2:1,types=uint8.float32")}) {
    SCOPED_TRACE(filter);
    Pipe r("datareposrc location=" + d / "s.dat" + " json=" + d / "s.json" +
           " is-shuffle=false ! " + filter + " ! appsink name=out sync=false");
    r.collect("out");
    auto res = r.run();
    ASSERT_TRUE(res.eos) << res.error_text;
    ASSERT_EQ(r.out().size(), 2u);
    EXPECT_EQ(tensor_bytes(r.out()[1], 1), two_tensors(1)[1]);
  }
  // Other dimensions do not negotiate.
  auto bad = run_pipeline("datareposrc location=" + d / "s.dat" + " json=" + d / "s.json" +
                          " ! other/tensors,dimensions=3:1.3,types=uint8.float32 ! fakesink");
  EXPECT_TRUE(bad.error);
}
