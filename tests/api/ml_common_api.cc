// SPDX-License-Identifier: LGPL-2.1-only
// The common ML API (ml-api-common.h) against NNStreamer's rules: the rank limit of 4 of a
// plain info handle and 16 of an extended one, clone/compare/data_clone, ml_information_*,
// the version, ml_error/ml_strerror, ml_option_set's key check, the error codes of
// ml_single_open for a missing framework or model, and every function's argument checks.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "api/ml_api_internal.h"
#include "nnstreamer-single.h"
#include "nnstreamer-tizen-internal.h"
#include "tensor_filter_custom_easy.h"

namespace {

constexpr int kInval = ML_ERROR_INVALID_PARAMETER;

struct Info {
  ml_tensors_info_h h = nullptr;
  explicit Info(bool extended = false) {
    EXPECT_EQ(extended ? ml_tensors_info_create_extended(&h) : ml_tensors_info_create(&h),
              ML_ERROR_NONE);
  }
  ~Info() {
    if (h) ml_tensors_info_destroy(h);
  }
  Info(const Info &) = delete;
  Info &operator=(const Info &) = delete;
};

std::vector<unsigned> dims_of(ml_tensors_info_h h, unsigned index = 0) {
  ml_tensor_dimension d;
  std::memset(d, 0x5a, sizeof(d));  // every entry must be written
  EXPECT_EQ(ml_tensors_info_get_tensor_dimension(h, index, d), ML_ERROR_NONE);
  return {d, d + ML_TENSOR_RANK_LIMIT};
}

std::vector<unsigned> padded(std::vector<unsigned> v) {
  v.resize(ML_TENSOR_RANK_LIMIT, 0);
  return v;
}

// A plain handle reads dimension[0..3] only: what follows is garbage the application never
// set (filled here with a pattern so a read of it shows).
TEST(MlCommonRank, PlainInfoReadsFourDimensionsOnly) {
  Info info;
  ASSERT_EQ(ml_tensors_info_set_count(info.h, 1), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_type(info.h, 0, ML_TENSOR_TYPE_UINT8), ML_ERROR_NONE);
  ml_tensor_dimension d;
  std::memset(d, 0xab, sizeof(d));
  d[0] = 3;
  d[1] = 224;
  d[2] = 224;
  d[3] = 1;
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, d), ML_ERROR_NONE) << ml_error();
  EXPECT_EQ(dims_of(info.h), padded({3, 224, 224, 1}));
  size_t size = 0;
  ASSERT_EQ(ml_tensors_info_get_tensor_size(info.h, 0, &size), ML_ERROR_NONE);
  EXPECT_EQ(size, 3u * 224 * 224);
  bool valid = false;
  ASSERT_EQ(ml_tensors_info_validate(info.h, &valid), ML_ERROR_NONE);
  EXPECT_TRUE(valid);
}

// As applications written for the rank limit of 4 do: only dimension[0..3] initialised.
TEST(MlCommonRank, PlainInfoWithUninitialisedTail) {
  Info info;
  ASSERT_EQ(ml_tensors_info_set_count(info.h, 1), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_type(info.h, 0, ML_TENSOR_TYPE_FLOAT32), ML_ERROR_NONE);
  ml_tensor_dimension d;
  d[0] = 10;
  d[1] = 1;
  d[2] = 1;
  d[3] = 1;
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, d), ML_ERROR_NONE) << ml_error();
  EXPECT_EQ(dims_of(info.h), padded({10, 1, 1, 1}));
  ml_tensors_data_h data = nullptr;
  ASSERT_EQ(ml_tensors_data_create(info.h, &data), ML_ERROR_NONE);
  void *raw = nullptr;
  size_t size = 0;
  ASSERT_EQ(ml_tensors_data_get_tensor_data(data, 0, &raw, &size), ML_ERROR_NONE);
  EXPECT_EQ(size, 40u);
  ml_tensors_data_destroy(data);
}

TEST(MlCommonRank, PlainInfoDropsRankFiveAndGetZeroesTheTail) {
  Info info;
  ASSERT_EQ(ml_tensors_info_set_count(info.h, 1), ML_ERROR_NONE);
  ml_tensor_dimension d = {2, 3, 4, 5, 6, 7};
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, d), ML_ERROR_NONE);
  EXPECT_EQ(dims_of(info.h), padded({2, 3, 4, 5}));
}

TEST(MlCommonRank, ExtendedInfoTakesSixteen) {
  Info info(true);
  ASSERT_EQ(ml_tensors_info_set_count(info.h, 1), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_type(info.h, 0, ML_TENSOR_TYPE_INT8), ML_ERROR_NONE);
  ml_tensor_dimension d = {2, 1, 1, 1, 1, 3, 1, 1, 1, 1, 1, 1, 1, 1, 1, 2};
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, d), ML_ERROR_NONE) << ml_error();
  EXPECT_EQ(dims_of(info.h), std::vector<unsigned>(d, d + ML_TENSOR_RANK_LIMIT));
  size_t size = 0;
  ASSERT_EQ(ml_tensors_info_get_tensor_size(info.h, -1, &size), ML_ERROR_NONE);
  EXPECT_EQ(size, 12u);
}

TEST(MlCommonRank, DimensionRules) {
  for (bool ext : {false, true}) {
    Info info(ext);
    ASSERT_EQ(ml_tensors_info_set_count(info.h, 1), ML_ERROR_NONE);
    ml_tensor_dimension zero_first = {0, 3};
    EXPECT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, zero_first), kInval);
    EXPECT_NE(std::string(ml_error()).find("dimension[0] is 0"), std::string::npos);
    ml_tensor_dimension gap = {2, 0, 3};
    EXPECT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, gap), kInval);
    EXPECT_NE(std::string(ml_error()).find("dimension[2] is 3 after a 0"), std::string::npos)
        << ml_error();
    ml_tensor_dimension late = {2, 1, 1, 1, 0, 5};  // a gap past 4: only an extended one sees it
    EXPECT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, late), ext ? kInval : ML_ERROR_NONE);
    EXPECT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, nullptr), kInval);
    EXPECT_EQ(ml_tensors_info_get_tensor_dimension(info.h, 0, nullptr), kInval);
    ml_tensor_dimension ok = {2};
    EXPECT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 1, ok), kInval);  // index
    EXPECT_EQ(ml_tensors_info_get_tensor_dimension(info.h, 1, ok), kInval);
  }
}

TEST(MlCommonRank, CloneKeepsTheKindAndNeedsAValidSource) {
  Info ext(true), plain, dest;
  ASSERT_EQ(ml_tensors_info_set_count(ext.h, 1), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_type(ext.h, 0, ML_TENSOR_TYPE_UINT16), ML_ERROR_NONE);
  ml_tensor_dimension d = {2, 2, 2, 2, 2};
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(ext.h, 0, d), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_clone(dest.h, ext.h), ML_ERROR_NONE);
  EXPECT_EQ(dims_of(dest.h), padded({2, 2, 2, 2, 2}));
  // dest is extended now: it keeps a rank-6 dimension
  ml_tensor_dimension d6 = {1, 1, 1, 1, 1, 7};
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(dest.h, 0, d6), ML_ERROR_NONE);
  EXPECT_EQ(dims_of(dest.h)[5], 7u);
  bool equal = true;
  ASSERT_EQ(_ml_tensors_info_compare(dest.h, ext.h, &equal), ML_ERROR_NONE);
  EXPECT_FALSE(equal);
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(dest.h, 0, d), ML_ERROR_NONE);
  ASSERT_EQ(_ml_tensors_info_compare(dest.h, ext.h, &equal), ML_ERROR_NONE);
  EXPECT_TRUE(equal);
  EXPECT_EQ(_ml_tensors_info_compare(dest.h, nullptr, &equal), kInval);
  EXPECT_EQ(_ml_tensors_info_compare(dest.h, ext.h, nullptr), kInval);

  // A plain clone of a plain source reads 4 entries again.
  ASSERT_EQ(ml_tensors_info_set_count(plain.h, 1), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_type(plain.h, 0, ML_TENSOR_TYPE_UINT8), ML_ERROR_NONE);
  ml_tensor_dimension d4 = {4, 1, 1, 1};
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(plain.h, 0, d4), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_clone(dest.h, plain.h), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(dest.h, 0, d6), ML_ERROR_NONE);
  EXPECT_EQ(dims_of(dest.h), padded({1, 1, 1, 1}));

  // The source must be valid (NNStreamer: "src should be a valid tensors info handle").
  Info empty;
  EXPECT_EQ(ml_tensors_info_clone(dest.h, empty.h), kInval);
  EXPECT_NE(std::string(ml_error()).find("src is not valid"), std::string::npos);
  EXPECT_EQ(ml_tensors_info_clone(nullptr, plain.h), kInval);
  EXPECT_EQ(ml_tensors_info_clone(dest.h, nullptr), kInval);
}

TEST(MlCommonData, CloneCopiesEveryTensor) {
  Info info(true);
  ASSERT_EQ(ml_tensors_info_set_count(info.h, 2), ML_ERROR_NONE);
  ml_tensor_dimension d0 = {3}, d1 = {1, 1, 1, 1, 2};
  ASSERT_EQ(ml_tensors_info_set_tensor_type(info.h, 0, ML_TENSOR_TYPE_UINT8), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_type(info.h, 1, ML_TENSOR_TYPE_FLOAT32), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, d0), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 1, d1), ML_ERROR_NONE);
  ml_tensors_data_h a = nullptr, b = nullptr;
  ASSERT_EQ(ml_tensors_data_create(info.h, &a), ML_ERROR_NONE);
  const uint8_t bytes[3] = {7, 8, 9};
  const float floats[2] = {1.5f, -2.25f};
  ASSERT_EQ(ml_tensors_data_set_tensor_data(a, 0, bytes, 3), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_data_set_tensor_data(a, 1, floats, 8), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_data_clone(a, &b), ML_ERROR_NONE);
  void *pa = nullptr, *pb = nullptr;
  size_t sa = 0, sb = 0;
  for (unsigned i = 0; i < 2; ++i) {
    ASSERT_EQ(ml_tensors_data_get_tensor_data(a, i, &pa, &sa), ML_ERROR_NONE);
    ASSERT_EQ(ml_tensors_data_get_tensor_data(b, i, &pb, &sb), ML_ERROR_NONE);
    EXPECT_NE(pa, pb);
    ASSERT_EQ(sa, sb);
    EXPECT_EQ(std::memcmp(pa, pb, sa), 0);
  }
  // The clone's info: same tensors, still extended (rank 5 kept).
  ml_tensors_info_h bi = nullptr;
  ASSERT_EQ(ml_tensors_data_get_info(b, &bi), ML_ERROR_NONE);
  bool equal = false;
  ASSERT_EQ(_ml_tensors_info_compare(bi, info.h, &equal), ML_ERROR_NONE);
  EXPECT_TRUE(equal);
  EXPECT_EQ(dims_of(bi, 1), padded({1, 1, 1, 1, 2}));
  ml_tensors_info_destroy(bi);
  // Independent buffers
  ASSERT_EQ(ml_tensors_data_get_tensor_data(a, 0, &pa, &sa), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_data_get_tensor_data(b, 0, &pb, &sb), ML_ERROR_NONE);
  static_cast<uint8_t *>(pa)[0] = 42;
  EXPECT_EQ(static_cast<uint8_t *>(pb)[0], 7);
  EXPECT_EQ(ml_tensors_data_clone(nullptr, &b), kInval);
  EXPECT_EQ(ml_tensors_data_clone(a, nullptr), kInval);
  ml_tensors_data_destroy(a);
  ml_tensors_data_destroy(b);
}

TEST(MlCommonData, WrapBorrowsTheCallersMemory) {
  Info info;
  ASSERT_EQ(ml_tensors_info_set_count(info.h, 1), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_info_set_tensor_type(info.h, 0, ML_TENSOR_TYPE_UINT8), ML_ERROR_NONE);
  ml_tensor_dimension d = {4, 1, 1, 1};
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, d), ML_ERROR_NONE);
  uint8_t mine[4] = {1, 2, 3, 4};
  void *ptrs[1] = {mine};
  ml_tensors_data_h data = nullptr;
  ASSERT_EQ(nns_ml_tensors_data_wrap(info.h, ptrs, 1, &data), ML_ERROR_NONE);
  void *raw = nullptr;
  size_t size = 0;
  ASSERT_EQ(ml_tensors_data_get_tensor_data(data, 0, &raw, &size), ML_ERROR_NONE);
  EXPECT_EQ(raw, static_cast<void *>(mine));
  EXPECT_EQ(size, 4u);
  ASSERT_EQ(ml_tensors_data_destroy(data), ML_ERROR_NONE);  // does not free `mine`
  EXPECT_EQ(nns_ml_tensors_data_wrap(info.h, ptrs, 2, &data), kInval);
  void *none[1] = {nullptr};
  EXPECT_EQ(nns_ml_tensors_data_wrap(info.h, none, 1, &data), kInval);
}

void free_string(void *p) {
  std::free(p);
}

TEST(MlCommonInformation, GetIterateAndList) {
  ml_information_h a = nullptr, b = nullptr;
  ASSERT_EQ(_ml_information_create(&a), ML_ERROR_NONE);
  ASSERT_EQ(_ml_information_create(&b), ML_ERROR_NONE);
  ASSERT_EQ(_ml_information_set(a, "name", strdup("mobilenet"), free_string), ML_ERROR_NONE);
  ASSERT_EQ(_ml_information_set(a, "version", strdup("1"), free_string), ML_ERROR_NONE);
  ASSERT_EQ(_ml_information_set(a, "version", strdup("2"), free_string), ML_ERROR_NONE);
  char x[] = "x";  // refused: the library takes no ownership of it
  EXPECT_EQ(_ml_information_set(a, "", x, nullptr), kInval);
  EXPECT_EQ(_ml_information_set(nullptr, "k", x, nullptr), kInval);
  EXPECT_EQ(_ml_information_set(a, "k", nullptr, nullptr), kInval);
  void *v = nullptr;
  ASSERT_EQ(ml_information_get(a, "version", &v), ML_ERROR_NONE);
  EXPECT_STREQ(static_cast<char *>(v), "2");
  EXPECT_EQ(ml_information_get(a, "missing", &v), kInval);
  EXPECT_NE(std::string(ml_error()).find("'missing'"), std::string::npos);
  EXPECT_EQ(ml_information_get(a, nullptr, &v), kInval);
  EXPECT_EQ(ml_information_get(a, "name", nullptr), kInval);
  std::string seen;
  ASSERT_EQ(ml_information_iterate(
                a,
                [](const char *k, const void *val, void *user) {
                  *static_cast<std::string *>(user) +=
                      std::string(k) + "=" + static_cast<const char *>(val) + ";";
                },
                &seen),
            ML_ERROR_NONE);
  EXPECT_EQ(seen, "name=mobilenet;version=2;");

  ml_information_list_h list = nullptr;
  ASSERT_EQ(_ml_information_list_create(&list), ML_ERROR_NONE);
  ASSERT_EQ(_ml_information_list_add(list, a), ML_ERROR_NONE);
  ASSERT_EQ(_ml_information_list_add(list, b), ML_ERROR_NONE);
  EXPECT_EQ(_ml_information_list_add(list, list), kInval);
  unsigned n = 0;
  ASSERT_EQ(ml_information_list_length(list, &n), ML_ERROR_NONE);
  EXPECT_EQ(n, 2u);
  ml_information_h got = nullptr;
  ASSERT_EQ(ml_information_list_get(list, 1, &got), ML_ERROR_NONE);
  EXPECT_EQ(got, b);
  EXPECT_EQ(ml_information_list_get(list, 2, &got), kInval);
  EXPECT_NE(std::string(ml_error()).find("index 2"), std::string::npos);
  EXPECT_EQ(ml_information_list_length(list, nullptr), kInval);
  EXPECT_EQ(ml_information_list_get(list, 0, nullptr), kInval);
  // Handles of the wrong kind
  EXPECT_EQ(ml_information_list_length(a, &n), kInval);
  EXPECT_EQ(ml_information_destroy(list), kInval);
  ml_option_h opt = nullptr;
  ASSERT_EQ(ml_option_create(&opt), ML_ERROR_NONE);
  EXPECT_EQ(ml_information_destroy(opt), kInval);
  EXPECT_EQ(ml_option_destroy(a), kInval);
  EXPECT_EQ(ml_information_get(opt, "name", &v), kInval);
  ml_option_destroy(opt);
  ASSERT_EQ(ml_information_list_destroy(list), ML_ERROR_NONE);  // frees a and b (LSan checks)
  EXPECT_EQ(ml_information_destroy(nullptr), kInval);
  EXPECT_EQ(ml_information_list_destroy(nullptr), kInval);
  EXPECT_EQ(_ml_information_create(nullptr), kInval);
  EXPECT_EQ(_ml_information_list_create(nullptr), kInval);
}

TEST(MlCommonVersion, NumbersAndString) {
  unsigned major = 0, minor = 0, micro = 0;
  ml_api_get_version(&major, &minor, &micro);
  ml_api_get_version(nullptr, nullptr, nullptr);
  char *s = ml_api_get_version_string();
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(std::string(s), "Machine Learning API " + std::to_string(major) + "." +
                                std::to_string(minor) + "." + std::to_string(micro));
  EXPECT_EQ(std::string(s), "Machine Learning API 1.8.8");
  std::free(s);
}

TEST(MlCommonErrors, ErrorTextIsPerThreadAndNullWhenNone) {
  std::thread([] { EXPECT_EQ(ml_error(), nullptr); }).join();
  EXPECT_EQ(ml_tensors_info_set_count(nullptr, 1), kInval);
  ASSERT_NE(ml_error(), nullptr);
  EXPECT_NE(std::string(ml_error()).find("ml_tensors_info_set_count"), std::string::npos);
  std::thread([] { EXPECT_EQ(ml_error(), nullptr); }).join();
  EXPECT_STREQ(ml_strerror(ML_ERROR_INVALID_PARAMETER), "invalid parameter");
  EXPECT_STREQ(ml_strerror(ML_ERROR_NOT_SUPPORTED), "not supported");
  EXPECT_EQ(ml_strerror(12345), nullptr);
}

TEST(MlCommonErrors, OptionKeyMustBeANonEmptyString) {
  ml_option_h opt = nullptr;
  ASSERT_EQ(ml_option_create(&opt), ML_ERROR_NONE);
  char v[] = "x";
  EXPECT_EQ(ml_option_set(opt, "", v, nullptr), kInval);
  EXPECT_NE(std::string(ml_error()).find("key is NULL or empty"), std::string::npos);
  EXPECT_EQ(ml_option_set(opt, nullptr, v, nullptr), kInval);
  EXPECT_EQ(ml_option_set(opt, "k", nullptr, nullptr), kInval);
  EXPECT_EQ(ml_option_set(nullptr, "k", v, nullptr), kInval);
  ASSERT_EQ(ml_option_set(opt, "k", v, nullptr), ML_ERROR_NONE);
  void *got = nullptr;
  EXPECT_EQ(ml_option_get(opt, "", &got), kInval);
  EXPECT_EQ(ml_option_get(opt, "other", &got), kInval);
  EXPECT_EQ(ml_option_get(opt, "k", nullptr), kInval);
  ASSERT_EQ(ml_option_get(opt, "k", &got), ML_ERROR_NONE);
  EXPECT_EQ(got, static_cast<void *>(v));
  EXPECT_EQ(ml_option_create(nullptr), kInval);
  EXPECT_EQ(ml_option_destroy(nullptr), kInval);
  ml_option_destroy(opt);
}

// NULL handles and out-pointers: ML_ERROR_INVALID_PARAMETER everywhere (NNStreamer's checks).
TEST(MlCommonErrors, ArgumentChecks) {
  Info info;
  ASSERT_EQ(ml_tensors_info_set_count(info.h, 1), ML_ERROR_NONE);
  unsigned n = 0;
  bool valid = false;
  char *name = nullptr;
  ml_tensor_type_e type;
  size_t size = 0;
  EXPECT_EQ(ml_tensors_info_create(nullptr), kInval);
  EXPECT_EQ(ml_tensors_info_create_extended(nullptr), kInval);
  EXPECT_EQ(ml_tensors_info_destroy(nullptr), kInval);
  EXPECT_EQ(ml_tensors_info_validate(nullptr, &valid), kInval);
  EXPECT_EQ(ml_tensors_info_validate(info.h, nullptr), kInval);
  EXPECT_EQ(ml_tensors_info_set_count(info.h, 0), kInval);
  EXPECT_EQ(ml_tensors_info_set_count(info.h, ML_TENSOR_SIZE_LIMIT + 1), kInval);
  EXPECT_EQ(ml_tensors_info_get_count(nullptr, &n), kInval);
  EXPECT_EQ(ml_tensors_info_get_count(info.h, nullptr), kInval);
  EXPECT_EQ(ml_tensors_info_set_tensor_name(nullptr, 0, "a"), kInval);
  EXPECT_EQ(ml_tensors_info_set_tensor_name(info.h, 1, "a"), kInval);
  EXPECT_EQ(ml_tensors_info_get_tensor_name(info.h, 0, nullptr), kInval);
  EXPECT_EQ(ml_tensors_info_get_tensor_name(info.h, 1, &name), kInval);
  ASSERT_EQ(ml_tensors_info_get_tensor_name(info.h, 0, &name), ML_ERROR_NONE);
  EXPECT_EQ(name, nullptr);  // no name set
  EXPECT_EQ(ml_tensors_info_set_tensor_type(info.h, 0, ML_TENSOR_TYPE_UNKNOWN), kInval);
  EXPECT_EQ(ml_tensors_info_set_tensor_type(info.h, 0, static_cast<ml_tensor_type_e>(-1)), kInval);
  EXPECT_EQ(ml_tensors_info_get_tensor_type(info.h, 0, nullptr), kInval);
  EXPECT_EQ(ml_tensors_info_get_tensor_type(info.h, 1, &type), kInval);
  EXPECT_EQ(ml_tensors_info_get_tensor_size(nullptr, 0, &size), kInval);
  EXPECT_EQ(ml_tensors_info_get_tensor_size(info.h, 0, nullptr), kInval);
  size = 99;
  EXPECT_EQ(ml_tensors_info_get_tensor_size(info.h, 1, &size), kInval);
  EXPECT_EQ(size, 0u);  // NNStreamer sets 0 first
  ml_tensors_data_h data = nullptr;
  EXPECT_EQ(ml_tensors_data_create(info.h, &data), kInval);  // no type/dimension yet
  EXPECT_EQ(ml_tensors_data_create(nullptr, &data), kInval);
  ASSERT_EQ(ml_tensors_info_set_tensor_type(info.h, 0, ML_TENSOR_TYPE_UINT8), ML_ERROR_NONE);
  ml_tensor_dimension d = {4, 1, 1, 1};
  ASSERT_EQ(ml_tensors_info_set_tensor_dimension(info.h, 0, d), ML_ERROR_NONE);
  EXPECT_EQ(ml_tensors_data_create(info.h, nullptr), kInval);
  ASSERT_EQ(ml_tensors_data_create(info.h, &data), ML_ERROR_NONE);
  void *raw = nullptr;
  const uint8_t five[5] = {};
  EXPECT_EQ(ml_tensors_data_get_tensor_data(nullptr, 0, &raw, &size), kInval);
  EXPECT_EQ(ml_tensors_data_get_tensor_data(data, 0, nullptr, &size), kInval);
  EXPECT_EQ(ml_tensors_data_get_tensor_data(data, 0, &raw, nullptr), kInval);
  EXPECT_EQ(ml_tensors_data_get_tensor_data(data, 1, &raw, &size), kInval);
  EXPECT_EQ(ml_tensors_data_set_tensor_data(data, 0, nullptr, 4), kInval);
  EXPECT_EQ(ml_tensors_data_set_tensor_data(data, 0, five, 0), kInval);
  EXPECT_EQ(ml_tensors_data_set_tensor_data(data, 0, five, 5), kInval);
  EXPECT_EQ(ml_tensors_data_set_tensor_data(data, 1, five, 4), kInval);
  EXPECT_EQ(ml_tensors_data_set_tensor_data(data, 0, five, 3), ML_ERROR_NONE);  // <= size
  ml_tensors_info_h got = nullptr;
  EXPECT_EQ(ml_tensors_data_get_info(nullptr, &got), kInval);
  EXPECT_EQ(ml_tensors_data_get_info(data, nullptr), kInval);
  EXPECT_EQ(ml_tensors_data_destroy(nullptr), kInval);
  ml_tensors_data_destroy(data);

  ml_single_h single = nullptr;
  EXPECT_EQ(ml_single_close(nullptr), kInval);
  EXPECT_EQ(ml_single_open(nullptr, "m", nullptr, nullptr, ML_NNFW_TYPE_ANY, ML_NNFW_HW_ANY),
            kInval);
  EXPECT_EQ(ml_single_open(&single, nullptr, nullptr, nullptr, ML_NNFW_TYPE_ANY, ML_NNFW_HW_ANY),
            kInval);
  EXPECT_EQ(ml_single_open_with_option(&single, nullptr), kInval);
  EXPECT_EQ(ml_single_get_input_info(nullptr, &got), kInval);
  EXPECT_EQ(ml_single_set_timeout(nullptr, 1), kInval);
  EXPECT_EQ(ml_single_set_property(nullptr, "input", "1"), kInval);
}

// A framework with no back end here: NOT_SUPPORTED; a model file that does not exist:
// INVALID_PARAMETER (NNStreamer checks the file first).
TEST(MlCommonErrors, SingleOpenCodes) {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("nns_ml_common_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::string pb = (dir / "model.pb").string();
  std::FILE *f = std::fopen(pb.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  std::fputs("not a model", f);
  std::fclose(f);
  ml_single_h h = nullptr;
  EXPECT_EQ(
      ml_single_open(&h, pb.c_str(), nullptr, nullptr, ML_NNFW_TYPE_TENSORFLOW, ML_NNFW_HW_ANY),
      ML_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(h, nullptr);
  EXPECT_NE(std::string(ml_error()).find("framework 'tensorflow' is not available"),
            std::string::npos)
      << ml_error();
  EXPECT_EQ(ml_single_open(&h, (dir / "missing.onnx").string().c_str(), nullptr, nullptr,
                           ML_NNFW_TYPE_ONNX_RUNTIME, ML_NNFW_HW_ANY),
            kInval);
  EXPECT_NE(std::string(ml_error()).find("missing.onnx' is not a file"), std::string::npos)
      << ml_error();
  std::filesystem::remove_all(dir);
}

// As NNStreamer's _ml_validate_model_file: a framework that does not open the model file's
// extension is ML_ERROR_INVALID_PARAMETER, checked before the framework is looked for (tensorflow
// has no back end here, which would give ML_ERROR_NOT_SUPPORTED).
TEST(MlCommonErrors, SingleOpenFrameworkNotMatchingTheModelFile) {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("nns_ml_mismatch_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string tflite = (dir / "add.tflite").string();
  std::FILE *f = std::fopen(tflite.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  std::fputs("not a model", f);
  std::fclose(f);
  for (ml_nnfw_type_e nnfw :
       {ML_NNFW_TYPE_TENSORFLOW, ML_NNFW_TYPE_PYTORCH, ML_NNFW_TYPE_CUSTOM_FILTER}) {
    SCOPED_TRACE(static_cast<int>(nnfw));
    ml_single_h h = nullptr;
    EXPECT_EQ(ml_single_open(&h, tflite.c_str(), nullptr, nullptr, nnfw, ML_NNFW_HW_ANY), kInval);
    EXPECT_EQ(h, nullptr);
    EXPECT_NE(std::string(ml_error()).find("does not match the framework"), std::string::npos)
        << ml_error();
  }
  // The same through ml_single_open_with_option's "nnfw".
  ml_option_h opt = nullptr;
  ASSERT_EQ(ml_option_create(&opt), ML_ERROR_NONE);
  ml_nnfw_type_e torch = ML_NNFW_TYPE_PYTORCH;
  ASSERT_EQ(ml_option_set(opt, "models", const_cast<char *>(tflite.c_str()), nullptr),
            ML_ERROR_NONE);
  ASSERT_EQ(ml_option_set(opt, "nnfw", &torch, nullptr), ML_ERROR_NONE);
  ml_single_h h = nullptr;
  EXPECT_EQ(ml_single_open_with_option(&h, opt), kInval);
  ml_option_destroy(opt);
  // A folder is for ML_NNFW_TYPE_NNFW only.
  EXPECT_EQ(ml_single_open(&h, dir.string().c_str(), nullptr, nullptr, ML_NNFW_TYPE_PYTORCH,
                           ML_NNFW_HW_ANY),
            kInval);
  // Frameworks that accept the extension get past the check (armnn reads .tflite; this file is
  // no model, so the open itself fails, but not as a mismatch).
  EXPECT_NE(
      ml_single_open(&h, tflite.c_str(), nullptr, nullptr, ML_NNFW_TYPE_ARMNN, ML_NNFW_HW_ANY),
      ML_ERROR_NONE);
  EXPECT_EQ(std::string(ml_error()).find("does not match the framework"), std::string::npos)
      << ml_error();
  std::filesystem::remove_all(dir);
}

// Info handles the library makes from a model: extended when a rank is above 4.
int copy5(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
          GstTensorMemory *out) {
  std::memcpy(out[0].data, in[0].data, in[0].size);
  return 0;
}

TEST(MlCommonRank, ModelInfoOfRankFiveIsExtended) {
  GstTensorsInfo io{};
  io.num_tensors = 1;
  io.info[0].type = _NNS_UINT8;
  const uint32_t d5[5] = {2, 1, 1, 1, 3};
  for (int i = 0; i < 5; ++i) io.info[0].dimension[i] = d5[i];
  ASSERT_EQ(NNS_custom_easy_register("mlc_rank5", copy5, nullptr, &io, &io), 0);
  ml_single_h h = nullptr;
  ASSERT_EQ(ml_single_open(&h, "mlc_rank5", nullptr, nullptr, ML_NNFW_TYPE_ANY, ML_NNFW_HW_ANY),
            kInval);  // no framework given and no extension to detect it from
  ml_option_h opt = nullptr;
  ASSERT_EQ(ml_option_create(&opt), ML_ERROR_NONE);
  char model[] = "mlc_rank5", fw[] = "custom-easy";
  ml_option_set(opt, "models", model, nullptr);
  ml_option_set(opt, "framework_name", fw, nullptr);
  ASSERT_EQ(ml_single_open_with_option(&h, opt), ML_ERROR_NONE) << ml_error();
  ml_option_destroy(opt);
  ml_tensors_info_h in = nullptr;
  ASSERT_EQ(ml_single_get_input_info(h, &in), ML_ERROR_NONE);
  EXPECT_EQ(dims_of(in), padded({2, 1, 1, 1, 3}));
  ml_tensors_data_h data = nullptr, out = nullptr;
  ASSERT_EQ(ml_tensors_data_create(in, &data), ML_ERROR_NONE);
  ASSERT_EQ(ml_single_invoke(h, data, &out), ML_ERROR_NONE) << ml_error();
  ml_tensors_info_h oi = nullptr;
  ASSERT_EQ(ml_tensors_data_get_info(out, &oi), ML_ERROR_NONE);
  EXPECT_EQ(dims_of(oi), padded({2, 1, 1, 1, 3}));
  ml_tensors_info_destroy(oi);
  ml_tensors_data_destroy(out);
  ml_tensors_data_destroy(data);
  ml_tensors_info_destroy(in);
  ml_single_close(h);
  NNS_custom_easy_unregister("mlc_rank5");
}

// NULL arguments of every ml_single_* call on a live handle (NNStreamer's
// invoke_invalid_param, invoke_dynamic_fail, property_02, set_input_info_fail tests).
TEST(MlCommonErrors, SingleArgumentChecks) {
  GstTensorsInfo io{};
  io.num_tensors = 1;
  io.info[0].type = _NNS_UINT8;
  io.info[0].dimension[0] = 4;
  ASSERT_EQ(NNS_custom_easy_register("mlc_args", copy5, nullptr, &io, &io), 0);
  ml_option_h opt = nullptr;
  ASSERT_EQ(ml_option_create(&opt), ML_ERROR_NONE);
  char model[] = "mlc_args", fw[] = "custom-easy";
  ml_option_set(opt, "models", model, nullptr);
  ml_option_set(opt, "framework_name", fw, nullptr);
  ml_single_h h = nullptr;
  ASSERT_EQ(ml_single_open_with_option(&h, opt), ML_ERROR_NONE) << ml_error();
  ml_option_destroy(opt);
  ml_tensors_info_h in_info = nullptr, out_info = nullptr;
  ASSERT_EQ(ml_single_get_input_info(h, &in_info), ML_ERROR_NONE);
  ml_tensors_data_h in = nullptr, out = nullptr;
  ASSERT_EQ(ml_tensors_data_create(in_info, &in), ML_ERROR_NONE);
  EXPECT_EQ(ml_single_invoke(nullptr, in, &out), kInval);
  EXPECT_EQ(ml_single_invoke(h, nullptr, &out), kInval);
  EXPECT_EQ(ml_single_invoke(h, in, nullptr), kInval);
  EXPECT_EQ(ml_single_invoke_fast(h, in, nullptr), kInval);
  EXPECT_EQ(ml_single_invoke_fast(h, nullptr, in), kInval);
  EXPECT_EQ(ml_single_invoke_dynamic(nullptr, in, in_info, &out, &out_info), kInval);
  EXPECT_EQ(ml_single_invoke_dynamic(h, nullptr, in_info, &out, &out_info), kInval);
  EXPECT_EQ(ml_single_invoke_dynamic(h, in, nullptr, &out, &out_info), kInval);
  EXPECT_EQ(ml_single_invoke_dynamic(h, in, in_info, nullptr, &out_info), kInval);
  EXPECT_EQ(ml_single_invoke_dynamic(h, in, in_info, &out, nullptr), kInval);
  EXPECT_EQ(ml_single_set_input_info(h, nullptr), kInval);
  Info empty;
  EXPECT_EQ(ml_single_set_input_info(h, empty.h), kInval);
  EXPECT_EQ(ml_single_get_input_info(h, nullptr), kInval);
  EXPECT_EQ(ml_single_get_output_info(h, nullptr), kInval);
  EXPECT_EQ(ml_single_get_output_info(nullptr, &out_info), kInval);
  char *value = nullptr;
  EXPECT_EQ(ml_single_get_property(h, "unknown_prop", &value), ML_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(ml_single_set_property(h, "unknown_prop", "INVALID"), ML_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(ml_single_set_property(h, "input", nullptr), kInval);
  EXPECT_EQ(ml_single_set_property(h, nullptr, "INVALID"), kInval);
  EXPECT_EQ(ml_single_get_property(h, "input", nullptr), kInval);
  EXPECT_EQ(ml_single_get_property(h, nullptr, &value), kInval);
  // A fixed model refuses another input through the property, and keeps its own.
  EXPECT_EQ(ml_single_set_property(h, "input", "3:4:4:1"), ML_ERROR_NOT_SUPPORTED);
  ASSERT_EQ(ml_single_get_property(h, "input", &value), ML_ERROR_NONE);
  EXPECT_STREQ(value, "4");
  std::free(value);
  // Still usable after all of that.
  ASSERT_EQ(ml_single_invoke(h, in, &out), ML_ERROR_NONE) << ml_error();
  ml_tensors_data_destroy(out);
  ml_tensors_data_destroy(in);
  ml_tensors_info_destroy(in_info);
  EXPECT_EQ(ml_single_close(h), ML_ERROR_NONE);
  NNS_custom_easy_unregister("mlc_args");
}

// A .tflite model on Arm NN (ML_NNFW_TYPE_ARMNN; tensorflow-lite resolves to our tflite back end,
// which resizes, see ml_single_dynamic.cc): Arm NN 20.08
// networks have fixed shapes, so another input shape is ML_ERROR_NOT_SUPPORTED with a message
// that says so, and the handle keeps working with the model's own shape.
TEST(MlSingleArmnn, FixedShapesOnlyAndSaysSo) {
  const std::string model = std::string(NNS_BUILD_DIR) + "/tests/models/add_mul.tflite";
  if (!std::filesystem::exists(std::string(NNS_BUILD_DIR) +
                               "/subplugins/filters/libnnstreamer_filter_armnn.so"))
    GTEST_SKIP() << "the armnn back end is not built";
  if (!std::filesystem::exists(model)) GTEST_SKIP() << model << " missing (nns_test_models)";
  ml_single_h h = nullptr;
  ASSERT_EQ(ml_single_open(&h, model.c_str(), nullptr, nullptr, ML_NNFW_TYPE_ARMNN, ML_NNFW_HW_ANY),
            ML_ERROR_NONE)
      << ml_error();
  ml_tensors_info_h in = nullptr;
  ASSERT_EQ(ml_single_get_input_info(h, &in), ML_ERROR_NONE);
  unsigned n = 0;
  ASSERT_EQ(ml_tensors_info_get_count(in, &n), ML_ERROR_NONE);
  ASSERT_EQ(n, 2u);
  EXPECT_EQ(dims_of(in, 0), padded({4, 3, 1}));
  // The model's own shape: a+b and a*b.
  ml_tensors_data_h data = nullptr, out = nullptr;
  ASSERT_EQ(ml_tensors_data_create(in, &data), ML_ERROR_NONE);
  std::vector<float> a(12), b(12);
  for (int i = 0; i < 12; ++i) {
    a[i] = 0.5f * i;
    b[i] = 2.0f - i;
  }
  ASSERT_EQ(ml_tensors_data_set_tensor_data(data, 0, a.data(), 48), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_data_set_tensor_data(data, 1, b.data(), 48), ML_ERROR_NONE);
  ASSERT_EQ(ml_single_invoke(h, data, &out), ML_ERROR_NONE) << ml_error();
  void *p0 = nullptr, *p1 = nullptr;
  size_t s0 = 0, s1 = 0;
  ASSERT_EQ(ml_tensors_data_get_tensor_data(out, 0, &p0, &s0), ML_ERROR_NONE);
  ASSERT_EQ(ml_tensors_data_get_tensor_data(out, 1, &p1, &s1), ML_ERROR_NONE);
  ASSERT_EQ(s0, 48u);
  for (int i = 0; i < 12; ++i) {
    EXPECT_FLOAT_EQ(static_cast<float *>(p0)[i], a[i] + b[i]) << i;
    EXPECT_FLOAT_EQ(static_cast<float *>(p1)[i], a[i] * b[i]) << i;
  }
  ml_tensors_data_destroy(out);
  // The same shapes: accepted without asking the back end.
  EXPECT_EQ(ml_single_set_input_info(h, in), ML_ERROR_NONE) << ml_error();
  // Batch 2: not supported, and the message names the shapes and the reason.
  Info batch2(true);
  ml_tensor_dimension d2 = {4, 3, 2};
  ASSERT_EQ(ml_tensors_info_set_count(batch2.h, 2), ML_ERROR_NONE);
  for (unsigned i = 0; i < 2; ++i) {
    ASSERT_EQ(ml_tensors_info_set_tensor_type(batch2.h, i, ML_TENSOR_TYPE_FLOAT32), ML_ERROR_NONE);
    ASSERT_EQ(ml_tensors_info_set_tensor_dimension(batch2.h, i, d2), ML_ERROR_NONE);
  }
  EXPECT_EQ(ml_single_set_input_info(h, batch2.h), ML_ERROR_NOT_SUPPORTED);
  const std::string err = ml_error() ? ml_error() : "";
  EXPECT_NE(err.find("cannot change its input from"), std::string::npos) << err;
  EXPECT_NE(err.find("4:3:2"), std::string::npos) << err;
  EXPECT_NE(err.find("fixed input shapes only"), std::string::npos) << err;
  ml_tensors_data_h data2 = nullptr;
  ml_tensors_info_h oi = nullptr;
  ASSERT_EQ(ml_tensors_data_create(batch2.h, &data2), ML_ERROR_NONE);
  EXPECT_EQ(ml_single_invoke_dynamic(h, data2, batch2.h, &out, &oi), ML_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(out, nullptr);
  // Still the model's shape afterwards.
  ASSERT_EQ(ml_single_invoke(h, data, &out), ML_ERROR_NONE) << ml_error();
  ml_tensors_data_destroy(out);
  ml_tensors_data_destroy(data2);
  ml_tensors_data_destroy(data);
  ml_tensors_info_destroy(in);
  ml_single_close(h);
}

}  // namespace
