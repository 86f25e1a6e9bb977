// SPDX-License-Identifier: LGPL-2.1-only
#include "core/backend_desc.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace nns {
namespace {

nns_tensor_desc make(uint32_t type, std::initializer_list<uint32_t> dims, const char *name = "") {
  nns_tensor_desc d{};
  d.type = type;
  std::size_t i = 0;
  for (auto v : dims) d.dims[i++] = v;
  set_name(d, name);
  return d;
}

TEST(BackendDesc, ShapeIsReversedDims) {
  auto d = make(_NNS_UINT8, {3, 224, 224, 1});
  EXPECT_EQ(shape_of(d, 4), (std::vector<int64_t>{1, 224, 224, 3}));
  // Rank 3 dims padded to a rank-4 model with leading 1.
  auto e = make(_NNS_UINT8, {3, 224, 224});
  EXPECT_EQ(shape_of(e, 4), (std::vector<int64_t>{1, 224, 224, 3}));
  // Trailing 1s may be dropped for a lower-rank model.
  EXPECT_EQ(shape_of(d, 3), (std::vector<int64_t>{224, 224, 3}));
  EXPECT_THROW(shape_of(d, 2), Error);
}

TEST(BackendDesc, SetDimsFromShape) {
  nns_tensor_desc d{};
  set_dims(d, {1, 1001});
  EXPECT_EQ(d.dims[0], 1001u);
  EXPECT_EQ(d.dims[1], 1u);
  EXPECT_EQ(d.dims[2], 0u);
  set_dims(d, {-1, 3, 4}, 7);
  EXPECT_EQ(d.dims[2], 7u);
  set_dims(d, {});
  EXPECT_EQ(desc_rank(d), 1u);
}

TEST(BackendDesc, BytesAndStrings) {
  auto d = make(_NNS_FLOAT32, {4, 3, 1}, "a");
  EXPECT_EQ(desc_bytes(d), 48u);
  EXPECT_EQ(desc_string(d), "'a' float32 4:3:1");
  EXPECT_EQ(desc_dims_string(d), "4:3:1");
  EXPECT_TRUE(desc_dims_equal(d, make(_NNS_UINT8, {4, 3})));
  EXPECT_FALSE(desc_dims_equal(d, make(_NNS_UINT8, {3, 4})));
  EXPECT_EQ(shape_string({-1, 3}), "[?,3]");
  EXPECT_EQ(desc_bytes(make(99, {4})), 0u);
}

}  // namespace
}  // namespace nns
