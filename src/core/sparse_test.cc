// SPDX-License-Identifier: LGPL-2.1-only
// Sparse encode/decode: exact round trip for every type and rank 1..16, the byte layout
// (header words, values then uint32 indices), zero rules (-0.0, NaN) and corrupt input.
#include "core/sparse.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "core/error.h"

namespace nns {
namespace {

uint32_t word(const std::vector<uint8_t> &b, std::size_t i) {
  uint32_t v;
  std::memcpy(&v, b.data() + 4 * i, 4);
  return v;
}

// Dense bytes with about 1/3 non-zero elements; non-zero values never have the zero pattern.
std::vector<uint8_t> make_dense(const TensorInfo &info, std::mt19937 &rng) {
  std::size_t e = type_size(info.type);
  std::vector<uint8_t> d(info.byte_size(), 0);
  for (std::size_t i = 0; i < info.element_count(); ++i) {
    if (rng() % 3) continue;
    for (std::size_t b = 0; b < e; ++b) d[i * e + b] = static_cast<uint8_t>(rng());
    d[i * e] |= 1;  // never a +/-0 bit pattern, for any type (lowest byte first)
    if (info.type == TensorType::kFloat32 || info.type == TensorType::kFloat64 ||
        info.type == TensorType::kFloat16)
      d[i * e + e - 1] = 0x3c;  // finite, not NaN
  }
  return d;
}

TEST(Sparse, RoundTripEveryTypeAndRank) {
  std::mt19937 rng(7);
  for (std::size_t t = 0; t < kNumTypes; ++t) {
    for (std::size_t rank = 1; rank <= kRankLimit; ++rank) {
      TensorInfo info;
      info.type = static_cast<TensorType>(t);
      for (std::size_t r = 0; r < rank; ++r) info.dims[r] = r < 3 ? 3 + r : (r % 2 ? 2 : 1);
      auto dense = make_dense(info, rng);
      auto enc = sparse_encode(info, dense.data());
      std::size_t nnz = sparse_count_nonzero(info, dense.data());
      ASSERT_EQ(enc.size(), sparse_encoded_size(info.type, nnz));
      MetaHeader h = sparse_parse(enc.data(), enc.size());
      EXPECT_EQ(h.nnz, nnz);
      EXPECT_EQ(h.type, info.type);
      EXPECT_TRUE(dims_equal(h.dims, info.dims));
      std::vector<uint8_t> back(info.byte_size(), 0xAA);
      sparse_decode(h, enc.data(), back.data());
      EXPECT_EQ(back, dense) << info.to_string();
    }
  }
}

TEST(Sparse, ByteLayoutMatchesNNStreamer) {
  TensorInfo info{"", TensorType::kInt16, make_dims({4, 2})};
  int16_t dense[8] = {0, 5, 0, 0, -3, 0, 0, 7};
  auto enc = sparse_encode(info, reinterpret_cast<const uint8_t *>(dense));
  ASSERT_EQ(enc.size(), 128u + 3 * 2 + 3 * 4);
  EXPECT_EQ(word(enc, 0), 0xfeedccedu);
  EXPECT_EQ(word(enc, 1), 0xDE001000u);
  EXPECT_EQ(word(enc, 2), 2u);  // int16
  EXPECT_EQ(word(enc, 3), 4u);
  EXPECT_EQ(word(enc, 4), 2u);
  EXPECT_EQ(word(enc, 5), 0u);
  EXPECT_EQ(word(enc, 19), 2u);  // format sparse
  EXPECT_EQ(word(enc, 20), 4u);  // media type tensor
  EXPECT_EQ(word(enc, 21), 3u);  // nnz
  for (std::size_t i = 22; i < 32; ++i) EXPECT_EQ(word(enc, i), 0u);
  int16_t vals[3];
  std::memcpy(vals, enc.data() + 128, 6);
  EXPECT_EQ(vals[0], 5);
  EXPECT_EQ(vals[1], -3);
  EXPECT_EQ(vals[2], 7);
  uint32_t idx[3];
  std::memcpy(idx, enc.data() + 134, 12);
  EXPECT_EQ(idx[0], 1u);
  EXPECT_EQ(idx[1], 4u);
  EXPECT_EQ(idx[2], 7u);
}

TEST(Sparse, NegativeZeroIsZeroNaNIsStored) {
  TensorInfo info{"", TensorType::kFloat32, make_dims({4})};
  float dense[4] = {-0.0f, std::nanf(""), 0.0f, 1.5f};
  auto enc = sparse_encode(info, reinterpret_cast<const uint8_t *>(dense));
  MetaHeader h = sparse_parse(enc.data(), enc.size());
  EXPECT_EQ(h.nnz, 2u);
  float back[4];
  sparse_decode(h, enc.data(), reinterpret_cast<uint8_t *>(back));
  EXPECT_EQ(back[0], 0.0f);
  EXPECT_FALSE(std::signbit(back[0]));
  EXPECT_TRUE(std::isnan(back[1]));
  EXPECT_EQ(back[3], 1.5f);
}

TEST(Sparse, AllZeroAndAllNonZero) {
  TensorInfo info{"", TensorType::kUInt8, make_dims({5})};
  uint8_t zeros[5] = {};
  auto enc = sparse_encode(info, zeros);
  EXPECT_EQ(enc.size(), 128u);
  EXPECT_EQ(sparse_parse(enc.data(), enc.size()).nnz, 0u);
  uint8_t full[5] = {1, 2, 3, 4, 5};
  enc = sparse_encode(info, full);
  EXPECT_EQ(enc.size(), 128u + 5 + 20);
  uint8_t back[5];
  sparse_decode(sparse_parse(enc.data(), enc.size()), enc.data(), back);
  EXPECT_EQ(std::memcmp(back, full, 5), 0);
}

std::string parse_error(const std::vector<uint8_t> &b) {
  try {
    sparse_parse(b.data(), b.size());
  } catch (const Error &e) {
    EXPECT_EQ(e.kind(), ErrorKind::kStream);
    return e.what();
  }
  return "";
}

TEST(Sparse, RejectsCorruptMemories) {
  TensorInfo info{"", TensorType::kUInt8, make_dims({4})};
  uint8_t dense[4] = {0, 9, 0, 8};
  auto enc = sparse_encode(info, dense);
  auto shorter = enc;
  shorter.pop_back();
  EXPECT_NE(parse_error(shorter).find("has 137 bytes, expected 138"), std::string::npos)
      << parse_error(shorter);
  auto bad_index = enc;
  bad_index[128 + 2 + 4] = 4;  // second index -> 4 (of 4 elements)
  EXPECT_NE(parse_error(bad_index).find("index 4 (entry 1) is outside the 4 elements"),
            std::string::npos)
      << parse_error(bad_index);
  auto flexible = enc;
  flexible[76] = 1;
  EXPECT_NE(parse_error(flexible).find("format=flexible, expected sparse"), std::string::npos);
  auto too_many = enc;
  too_many[84] = 9;  // nnz 9 > 4 elements
  EXPECT_NE(parse_error(too_many).find("nnz 9"), std::string::npos) << parse_error(too_many);
  EXPECT_NE(parse_error({1, 2, 3}).find("shorter than the 128-byte header"), std::string::npos);
}

}  // namespace
}  // namespace nns
