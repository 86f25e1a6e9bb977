// SPDX-License-Identifier: LGPL-2.1-only
#include "core/datarepo/datarepo_meta.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/datarepo/sample_order.h"
#include "core/error.h"

using nns::datarepo::check_against_file;
using nns::datarepo::Meta;
using nns::datarepo::parse_meta;
using nns::datarepo::SampleOrder;
using nns::datarepo::write_meta;

namespace {

std::string error_of(const std::function<void()> &f) {
  try {
    f();
  } catch (const nns::Error &e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(DatarepoMeta, ParsesNnstreamersStaticLayout) {
  // As NNStreamer's datareposink writes it (json-glib, pretty).
  const char *text = R"({
  "gst_caps" : "other/tensors, format=(string)static, framerate=(fraction)0/1, num_tensors=(int)2, dimensions=(string)1:1:784:1.1:1:10:1, types=(string)float32.float32",
  "total_samples" : 1000,
  "sample_size" : 3176
})";
  Meta m = parse_meta(text, "mnist.json");
  EXPECT_EQ(m.total_samples, 1000u);
  EXPECT_EQ(m.sample_size, 3176u);
  EXPECT_FALSE(m.per_sample());
  EXPECT_NE(m.caps.find("1:1:784:1.1:1:10:1"), std::string::npos);
  EXPECT_NO_THROW(check_against_file(m, 3176000, "mnist.data", "mnist.json"));
  std::string e = error_of([&] { check_against_file(m, 3176 * 999 + 100, "mnist.data", "j"); });
  EXPECT_NE(e.find("sample 999"), std::string::npos) << e;
  EXPECT_NE(e.find("byte offset 3172824"), std::string::npos) << e;
  EXPECT_NE(e.find("needs 3176 bytes"), std::string::npos) << e;
  EXPECT_NE(e.find("has 100 from there"), std::string::npos) << e;
}

TEST(DatarepoMeta, PerSampleLayoutRoundTrips) {
  Meta m;
  m.caps = "other/tensors,format=flexible,framerate=0/1";
  m.total_samples = 3;
  m.sample_offset = {0, 200, 328};
  m.tensor_size = {136, 64, 128, 140, 132};
  m.tensor_count = {0, 2, 3};
  Meta back = parse_meta(write_meta(m), "x.json");
  EXPECT_EQ(back.sample_offset, m.sample_offset);
  EXPECT_EQ(back.tensor_size, m.tensor_size);
  EXPECT_EQ(back.tensor_count, m.tensor_count);
  EXPECT_EQ(back.tensor_count_of(0), 2u);
  EXPECT_EQ(back.tensor_count_of(2), 2u);
  EXPECT_EQ(back.sample_bytes(2), 272u);
  EXPECT_NO_THROW(check_against_file(back, 600, "d", "j"));
  std::string e = error_of([&] { check_against_file(back, 599, "x.data", "x.json"); });
  EXPECT_NE(e.find("sample 2"), std::string::npos) << e;
  EXPECT_NE(e.find("byte offset 328"), std::string::npos) << e;
}

TEST(DatarepoMeta, RejectsBadMetaNamingTheMember) {
  EXPECT_NE(error_of([] { parse_meta("{", "a.json"); }).find("a.json: not valid JSON"),
            std::string::npos);
  EXPECT_NE(
      error_of([] { parse_meta(R"({"total_samples":1,"sample_size":4})", "a"); }).find("gst_caps"),
      std::string::npos);
  EXPECT_NE(error_of([] {
              parse_meta(R"({"gst_caps":"x","total_samples":-3,"sample_size":4})", "a");
            }).find("total_samples"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              parse_meta(R"({"gst_caps":"x","total_samples":2})", "a");
            }).find("sample_size"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              parse_meta(R"({"gst_caps":"x","total_samples":2,"sample_offset":[0,5],
                            "tensor_size":[5],"tensor_count":[0,3]})",
                         "a");
            }).find("tensor_count\"[1] = 3"),
            std::string::npos);
  EXPECT_NE(error_of([] {
              parse_meta(R"({"gst_caps":"x","total_samples":3,"sample_offset":[0,5],
                            "tensor_size":[5,5],"tensor_count":[0,1]})",
                         "a");
            }).find("for 3 samples"),
            std::string::npos);
}

TEST(DatarepoOrder, InOrderRangeAndEpochs) {
  SampleOrder o(3, 6, 2, false, 0);
  std::vector<uint32_t> got;
  uint32_t i;
  while (o.next(&i)) got.push_back(i);
  EXPECT_EQ(got, (std::vector<uint32_t>{3, 4, 5, 6, 3, 4, 5, 6}));
}

TEST(DatarepoOrder, ShuffleIsSeededAPermutationPerEpoch) {
  auto run = [](uint64_t seed) {
    SampleOrder o(0, 99, 3, true, seed);
    std::vector<uint32_t> v;
    uint32_t i;
    while (o.next(&i)) v.push_back(i);
    return v;
  };
  auto a = run(42), b = run(42), c = run(43);
  ASSERT_EQ(a.size(), 300u);
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
  for (int e = 0; e < 3; ++e) {
    std::set<uint32_t> s(a.begin() + e * 100, a.begin() + (e + 1) * 100);
    EXPECT_EQ(s.size(), 100u);
    EXPECT_EQ(*s.begin(), 0u);
    EXPECT_EQ(*s.rbegin(), 99u);
  }
  EXPECT_FALSE(std::equal(a.begin(), a.begin() + 100, a.begin() + 100));  // reshuffled
  std::vector<uint32_t> sorted(a.begin(), a.begin() + 100);
  std::sort(sorted.begin(), sorted.end());
  EXPECT_NE(sorted, std::vector<uint32_t>(a.begin(), a.begin() + 100));
  // The first draws for seed 42 are fixed by the algorithm (mt19937_64 + multiply-shift).
  SampleOrder small(0, 4, 1, true, 42);
  std::vector<uint32_t> v;
  uint32_t i;
  while (small.next(&i)) v.push_back(i);
  EXPECT_EQ(v.size(), 5u);
  std::vector<uint32_t> again;
  SampleOrder small2(0, 4, 1, true, 42);
  while (small2.next(&i)) again.push_back(i);
  EXPECT_EQ(v, again);
}
