// SPDX-License-Identifier: LGPL-2.1-only
#include "core/tensor_debug_format.h"

#include <gtest/gtest.h>

namespace nns::tdbg {
namespace {

TEST(TensorDebugFormat, DecodesUpstreamFlagValues) {
  EXPECT_EQ(decode_outputs(kConsoleInfo).console, Level::kInfo);
  EXPECT_EQ(decode_outputs(kConsoleInfo).gst, Level::kNone);
  EXPECT_EQ(decode_outputs(kConsoleWarn).console, Level::kWarn);
  EXPECT_EQ(decode_outputs(kConsoleError).console, Level::kError);
  EXPECT_EQ(decode_outputs(kGstInfo).gst, Level::kInfo);
  EXPECT_EQ(decode_outputs(kGstWarn).gst, Level::kWarn);
  EXPECT_EQ(decode_outputs(kGstError).gst, Level::kError);
  auto both = decode_outputs(kConsoleInfo | kGstWarn);
  EXPECT_EQ(both.console, Level::kInfo);
  EXPECT_EQ(both.gst, Level::kWarn);
  EXPECT_EQ(decode_outputs(kOutputDisabled).console, Level::kNone);
  EXPECT_TRUE(decode_outputs(kCircularBuf).unsupported);
  EXPECT_TRUE(decode_outputs(kFileWrite | kConsoleInfo).unsupported);
}

TEST(TensorDebugFormat, Texts) {
  EXPECT_EQ(format_time(1500000000ull), "0:00:01.500000000");
  EXPECT_EQ(format_time(3723000000001ull), "1:02:03.000000001");
  EXPECT_EQ(format_time(kNoTime), "none");
  TensorsInfo info;
  info.tensors.push_back(TensorInfo{"", TensorType::kUInt8, make_dims({3, 4, 1, 1})});
  info.tensors.push_back(TensorInfo{"", TensorType::kFloat32, make_dims({10})});
  EXPECT_EQ(describe_tensors(info), "static, 2 tensor(s): [0] uint8 3:4:1:1, [1] float32 10");
  MetaHeader h;
  h.type = TensorType::kInt16;
  h.dims = make_dims({4, 2});
  h.format = TensorFormat::kSparse;
  h.nnz = 3;
  EXPECT_EQ(describe_headers({h}), "sparse, 1 tensor(s): [0] int16 4:2 nnz=3");
  EXPECT_EQ(describe_timestamps(0, kNoTime, 33333333, 7),
            "pts 0:00:00.000000000, dts none, duration 0:00:00.033333333, offset 7");
  MetaHeader h2 = h;
  EXPECT_TRUE(same_headers({h}, {h2}));
  h2.dims = make_dims({4, 3});
  EXPECT_FALSE(same_headers({h}, {h2}));
}

}  // namespace
}  // namespace nns::tdbg
