// SPDX-License-Identifier: LGPL-2.1-only
// The 128-byte header in front of each flexible tensor, byte for byte as NNStreamer 2.7 writes
// it (docs/interop.md, finding 4): the `format` word (offset 76) is 0 from tensor_converter,
// tensor_transform and tensor_mux, which fill the header from the tensor's info.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "golden_util.h"

namespace nns::test {
namespace {

// Header words: magic, version 1.0, type, dims[16], format, media type, nnz, then zeros.
std::vector<uint8_t> header(uint32_t type, std::initializer_list<uint32_t> dims, uint32_t format,
                            uint32_t media) {
  std::vector<uint8_t> h(128, 0);
  auto put = [&](std::size_t off, uint32_t v) {
    for (int b = 0; b < 4; ++b) h[off + b] = static_cast<uint8_t>(v >> (8 * b));
  };
  put(0, 0xfeedcced);
  put(4, 0xde001000);
  put(8, type);
  std::size_t i = 0;
  for (uint32_t d : dims) put(12 + 4 * i++, d);
  put(76, format);
  put(80, media);
  return h;
}

const char *kVideo =
    "videotestsrc num-buffers=1 pattern=black ! "
    "video/x-raw,format=RGB,width=8,height=6,framerate=10/1 ! tensor_converter ! ";

// Captured from NNStreamer 2.7.0's tensor_converter (the same stream written by its
// datareposink; Datarepo.ReadsARepositoryWrittenByNNStreamer270 holds those bytes):
// uint8 (5), 3:8:6:1, format 0, media video (0).
TEST(FlexibleHeader, ConverterWritesNNStreamersBytes) {
  PipelineBytes r =
      run_to_bytes(std::string(kVideo) + "other/tensors,format=flexible ! filesink location=@OUT@");
  ASSERT_TRUE(r.run.eos) << r.run.error_text;
  ASSERT_EQ(r.bytes.size(), 128u + 144u);
  const std::vector<uint8_t> want = header(5, {3, 8, 6, 1}, 0, 0);
  EXPECT_EQ(std::vector<uint8_t>(r.bytes.begin(), r.bytes.begin() + 128), want);
}

// Captured from NNStreamer 2.7.0's tensor_transform (static in, flexible out):
// float32 (7), 3:8:6:1, format 0, media tensor (4).
TEST(FlexibleHeader, TransformToFlexibleWritesFormatZero) {
  PipelineBytes r = run_to_bytes(std::string(kVideo) +
                                 "tensor_transform mode=typecast option=float32 ! "
                                 "other/tensors,format=flexible ! filesink location=@OUT@");
  ASSERT_TRUE(r.run.eos) << r.run.error_text;
  ASSERT_EQ(r.bytes.size(), 128u + 144u * 4);
  const std::vector<uint8_t> want = header(7, {3, 8, 6, 1}, 0, 4);
  EXPECT_EQ(std::vector<uint8_t>(r.bytes.begin(), r.bytes.begin() + 128), want);
}

// Captured from NNStreamer 2.7.0's tensor_mux (two static inputs, flexible out): each memory
// gets a header from its tensor's info, format 0, media tensor (4).
TEST(FlexibleHeader, MuxToFlexibleWritesFormatZero) {
  PipelineBytes r = run_to_bytes(
      "tensor_mux name=m ! other/tensors,format=flexible ! filesink location=@OUT@ " +
      std::string(kVideo) +
      "m.sink_0 videotestsrc num-buffers=1 pattern=black ! "
      "video/x-raw,format=GRAY8,width=4,height=2,framerate=10/1 ! tensor_converter ! m.sink_1");
  ASSERT_TRUE(r.run.eos) << r.run.error_text;
  ASSERT_EQ(r.bytes.size(), 128u + 144u + 128u + 8u);
  EXPECT_EQ(std::vector<uint8_t>(r.bytes.begin(), r.bytes.begin() + 128),
            header(5, {3, 8, 6, 1}, 0, 4));
  EXPECT_EQ(std::vector<uint8_t>(r.bytes.begin() + 272, r.bytes.begin() + 400),
            header(5, {1, 4, 2, 1}, 0, 4));
}

}  // namespace
}  // namespace nns::test
