// SPDX-License-Identifier: LGPL-2.1-only
// Caps honesty: flexible caps carry no tensor description, so a capsfilter such as
// `other/tensors,types=float32` intersects with them. An element must not negotiate such
// decorated flexible caps when the tensors it pushes are something else: negotiation fails with
// a bus error naming both (tensor_transform: TensorTransformCompat, tensor_filter:
// TensorFilter.CapsfilterAskingAnotherTypeFailsNamingBoth).
#include <gtest/gtest.h>

#include <string>

#include "support/harness.h"

namespace {

using nns::test::run_pipeline;

const std::string kGray8 =
    "videotestsrc num-buffers=1 ! video/x-raw,format=GRAY8,width=10,height=4 ! ";

}  // namespace

TEST(CapsHonesty, ConverterRefusesFlexibleCapsSayingAnotherType) {
  auto r =
      run_pipeline(kGray8 + "tensor_converter name=c ! other/tensors,types=float32 ! fakesink");
  ASSERT_TRUE(r.error) << "negotiated";
  EXPECT_EQ(r.error_source, "c") << r.error_text;
  EXPECT_NE(r.error_text.find("types=(string)float32"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("types=(string)uint8"), std::string::npos) << r.error_text;
  // The same request with the right type still negotiates.
  r = run_pipeline(kGray8 + "tensor_converter ! other/tensors,types=uint8 ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

TEST(CapsHonesty, ConverterRefusesFlexibleCapsSayingOtherDimensions) {
  auto r = run_pipeline(kGray8 +
                        "tensor_converter name=c ! other/tensors,dimensions=(string)4:10 ! "
                        "fakesink");
  ASSERT_TRUE(r.error) << "negotiated";
  EXPECT_NE(r.error_text.find("dimensions=(string)4:10"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("1:10:4:1"), std::string::npos) << r.error_text;
}
