// SPDX-License-Identifier: LGPL-2.1-only
// Flexible/sparse header: round trip, refusals naming the field, and the regressions found by
// fuzz/meta_header_fuzz.cc (the inputs are also in fuzz/regressions/meta_header/).
#include "core/meta_header.h"

#include <gtest/gtest.h>

#include <cstring>

#include "core/error.h"

namespace nns {
namespace {

std::string parse_error(const uint8_t *b, std::size_t n) {
  try {
    parse_meta_header(b, n);
  } catch (const Error &e) {
    return e.what();
  }
  return "";
}

TEST(MetaHeader, RoundTrip) {
  MetaHeader h;
  h.type = TensorType::kFloat32;
  h.dims = {3, 4, 5};
  h.format = TensorFormat::kFlexible;
  uint8_t b[kMetaHeaderSize];
  write_meta_header(h, b);
  ASSERT_TRUE(has_meta_header(b, sizeof b));
  MetaHeader g = parse_meta_header(b, sizeof b);
  EXPECT_EQ(TensorType::kFloat32, g.type);
  EXPECT_EQ(h.dims, g.dims);
  EXPECT_EQ(240u, g.payload_size());
}

TEST(MetaHeader, RefusalsNameTheField) {
  uint8_t b[kMetaHeaderSize];
  MetaHeader h;
  h.type = TensorType::kUInt8;
  h.dims = {2};
  write_meta_header(h, b);
  EXPECT_NE(std::string::npos, parse_error(b, 100).find("shorter than the 128-byte header"));
  b[8] = 42;  // type
  EXPECT_NE(std::string::npos, parse_error(b, sizeof b).find("type 42"));
  b[0] = 0;  // magic
  EXPECT_NE(std::string::npos, parse_error(b, sizeof b).find("magic"));
}

// Fuzz finding 1: dimensions whose product overflowed size_t were accepted, so payload_size()
// wrapped to a small number and a short memory passed the size check.
TEST(MetaHeader, FuzzRegressionDimsOverflowRefused) {
  MetaHeader h;
  h.type = TensorType::kInt64;
  h.dims = {65536, 65536, 65536, 65536};  // 2^64 elements
  uint8_t b[kMetaHeaderSize];
  write_meta_header(h, b);
  EXPECT_NE(std::string::npos, parse_error(b, sizeof b).find("overflows"));
  // Byte-overflow only (element count fits, times 8 does not).
  h.dims = {65536, 65536, 65536, 8192};  // 2^61 elements of 8 bytes
  write_meta_header(h, b);
  EXPECT_NE(std::string::npos, parse_error(b, sizeof b).find("overflows"));
  // Just below the limit is accepted.
  h.type = TensorType::kUInt8;
  h.dims = {65536, 65536, 65536, 32767};
  write_meta_header(h, b);
  EXPECT_EQ("", parse_error(b, sizeof b));
}

TEST(MetaHeader, SparsePayloadIsExact) {
  MetaHeader h;
  h.type = TensorType::kUInt8;
  h.dims = {65536, 65536, 65536, 32767};
  h.format = TensorFormat::kSparse;
  h.nnz = 0xFFFFFFFFu;  // fits the element count; nnz * 5 bytes fits size_t too
  uint8_t b[kMetaHeaderSize];
  write_meta_header(h, b);
  MetaHeader g = parse_meta_header(b, sizeof b);
  EXPECT_EQ(std::size_t{0xFFFFFFFFu} * 5, g.payload_size());
}

}  // namespace
}  // namespace nns
