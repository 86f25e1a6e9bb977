// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer 2.x's utility ABI (nnstreamer_plugin_api_util.h from libnnstreamer-single.so,
// nnstreamer_plugin_api.h, nnstreamer_conf.h, nnstreamer_log.h): exact results as NNStreamer
// documents and returns them (dimension strings with rank and padding, lenient parsing, type
// and format names, tensors 16.. in `extra`, the 128-byte header, caps built from a config).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "nnstreamer_conf.h"
#include "nnstreamer_internal.h"
#include "nnstreamer_log.h"
#include "nnstreamer_plugin_api.h"
#include "nnstreamer_plugin_api_filter.h"
#include "support/harness.h"

namespace {

std::string take(gchar *s) {
  std::string r = s ? s : "(null)";
  g_free(s);
  return r;
}

struct Info {
  GstTensorsInfo i;
  Info() { gst_tensors_info_init(&i); }
  ~Info() { gst_tensors_info_free(&i); }
};

struct Config {
  GstTensorsConfig c;
  Config() { gst_tensors_config_init(&c); }
  ~Config() { gst_tensors_config_free(&c); }
};

TEST(CompatDimension, ParsesLikeNNStreamer) {
  tensor_dim d;
  EXPECT_EQ(gst_tensor_parse_dimension("3:224:224:1", d), 4u);
  EXPECT_EQ(d[0], 3u);
  EXPECT_EQ(d[1], 224u);
  EXPECT_EQ(d[3], 1u);
  EXPECT_EQ(d[4], 0u);
  EXPECT_EQ(gst_tensor_parse_dimension("  3 : 4 :5 ", d), 3u);
  EXPECT_EQ(d[2], 5u);
  // Reading stops at an empty field; a field that is not a number reads as 0.
  EXPECT_EQ(gst_tensor_parse_dimension("3::4", d), 1u);
  EXPECT_EQ(gst_tensor_parse_dimension("3:a:4", d), 3u);
  EXPECT_EQ(d[1], 0u);
  EXPECT_EQ(d[2], 4u);
  EXPECT_EQ(gst_tensor_parse_dimension("", d), 0u);
  EXPECT_EQ(gst_tensor_parse_dimension(nullptr, d), 0u);
  // Rank 16; a 17th field stays in the 16th, read up to its ':'.
  EXPECT_EQ(gst_tensor_parse_dimension("1:2:3:4:5:6:7:8:9:10:11:12:13:14:15:16:17", d), 16u);
  EXPECT_EQ(d[15], 16u);
}

TEST(CompatDimension, FormatsWithRankAndPadding) {
  tensor_dim d = {3, 4, 0};
  EXPECT_EQ(take(gst_tensor_get_dimension_string(d)), "3:4");
  EXPECT_EQ(take(gst_tensor_get_rank_dimension_string(d, 4, TRUE)), "3:4:1:1");
  EXPECT_EQ(take(gst_tensor_get_rank_dimension_string(d, 4, FALSE)), "3:4");
  EXPECT_EQ(take(gst_tensor_get_rank_dimension_string(d, 1, TRUE)), "3");
  tensor_dim big = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16};
  EXPECT_EQ(take(gst_tensor_get_dimension_string(big)), "1:2:3:4:5:6:7:8:9:10:11:12:13:14:15:16");
  EXPECT_EQ(take(gst_tensor_get_rank_dimension_string(big, 3, TRUE)), "1:2:3");
  EXPECT_EQ(take(gst_tensor_get_rank_dimension_string(big, 0, FALSE)),
            "1:2:3:4:5:6:7:8:9:10:11:12:13:14:15:16");
}

TEST(CompatDimension, RankValidityEqualityCount) {
  tensor_dim a = {3, 4, 0}, b = {3, 4, 1, 1, 0}, c = {3, 4, 2, 0}, hole = {3, 0, 4, 0};
  tensor_dim empty = {0};
  EXPECT_TRUE(gst_tensor_dimension_is_equal(a, b));
  EXPECT_FALSE(gst_tensor_dimension_is_equal(a, c));
  EXPECT_FALSE(gst_tensor_dimension_is_valid(hole));
  EXPECT_FALSE(gst_tensor_dimension_is_valid(empty));
  EXPECT_FALSE(gst_tensor_dimension_is_equal(hole, hole));
  EXPECT_EQ(gst_tensor_dimension_get_rank(b), 4u);
  EXPECT_EQ(gst_tensor_dimension_get_min_rank(b), 2u);
  tensor_dim ones = {1, 1, 1, 0};
  EXPECT_EQ(gst_tensor_dimension_get_min_rank(ones), 1u);
  tensor_dim img = {3, 224, 224, 1};
  EXPECT_EQ(gst_tensor_get_element_count(img), 150528u);
  EXPECT_EQ(gst_tensor_get_element_count(empty), 0u);
  EXPECT_TRUE(gst_tensor_dimension_string_is_equal("3:4,5", "3:4:1:1.5:1"));
  EXPECT_FALSE(gst_tensor_dimension_string_is_equal("3:4,5", "3:4"));
  EXPECT_FALSE(gst_tensor_dimension_string_is_equal("3:4", "3:5"));
}

TEST(CompatTypes, NamesSizesFormats) {
  EXPECT_EQ(gst_tensor_get_type(" UINT8 "), _NNS_UINT8);
  EXPECT_EQ(gst_tensor_get_type("float16"), _NNS_FLOAT16);
  EXPECT_EQ(gst_tensor_get_type("Int64"), _NNS_INT64);
  EXPECT_EQ(gst_tensor_get_type("int128"), _NNS_END);
  EXPECT_EQ(gst_tensor_get_type("uint8x"), _NNS_END);
  EXPECT_EQ(gst_tensor_get_type(nullptr), _NNS_END);
  EXPECT_STREQ(gst_tensor_get_type_string(_NNS_FLOAT32), "float32");
  EXPECT_EQ(gst_tensor_get_type_string(_NNS_END), nullptr);
  const gsize sizes[] = {4, 4, 2, 2, 1, 1, 8, 4, 8, 8, 2, 0};
  for (int t = 0; t <= _NNS_END; ++t)
    EXPECT_EQ(gst_tensor_get_element_size(static_cast<tensor_type>(t)), sizes[t]) << t;
  EXPECT_EQ(gst_tensor_get_format("Flexible"), _NNS_TENSOR_FORMAT_FLEXIBLE);
  EXPECT_EQ(gst_tensor_get_format("dense"), _NNS_TENSOR_FORMAT_END);
  EXPECT_STREQ(gst_tensor_get_format_string(_NNS_TENSOR_FORMAT_SPARSE), "sparse");
  EXPECT_EQ(gst_tensor_get_format_string(_NNS_TENSOR_FORMAT_END), nullptr);
  const gchar *keys[] = {"nosync", "slowest", "basepad", nullptr};
  EXPECT_EQ(find_key_strv(keys, "BASEPAD"), 2);
  EXPECT_EQ(find_key_strv(keys, "refresh"), -1);
  EXPECT_EQ(find_key_strv(keys, nullptr), -1);
}

TEST(CompatTensorsInfo, ParseFormatCompare) {
  Info a;
  a.i.num_tensors = 2;
  EXPECT_EQ(gst_tensors_info_parse_dimensions_string(&a.i, "3:4.5"), 2u);
  EXPECT_EQ(gst_tensors_info_parse_types_string(&a.i, "uint8,float32"), 2u);
  EXPECT_EQ(gst_tensors_info_parse_names_string(&a.i, " a , "), 2u);
  EXPECT_STREQ(a.i.info[0].name, "a");
  EXPECT_EQ(a.i.info[1].name, nullptr);
  EXPECT_EQ(take(gst_tensors_info_get_dimensions_string(&a.i)), "3:4,5");
  EXPECT_EQ(take(gst_tensors_info_get_rank_dimensions_string(&a.i, 4, TRUE)), "3:4:1:1,5:1:1:1");
  EXPECT_EQ(take(gst_tensors_info_get_types_string(&a.i)), "uint8,float32");
  EXPECT_EQ(take(gst_tensors_info_get_names_string(&a.i)), "a,");
  EXPECT_EQ(gst_tensors_info_get_size(&a.i, -1), 32u);
  EXPECT_EQ(gst_tensors_info_get_size(&a.i, 1), 20u);
  EXPECT_EQ(gst_tensors_info_get_size(&a.i, 2), 0u);
  EXPECT_EQ(take(gst_tensors_info_to_string(&a.i)),
            "Format = static, Num_Tensors = 2, Tensors = [{ 'a' uint8 (3:4) }, { float32 (5) }]");
  EXPECT_TRUE(gst_tensors_info_validate(&a.i));

  Info b;
  gst_tensors_info_copy(&b.i, &a.i);
  EXPECT_TRUE(gst_tensors_info_is_equal(&a.i, &b.i));
  EXPECT_STREQ(b.i.info[0].name, "a");
  EXPECT_NE(b.i.info[0].name, a.i.info[0].name);
  b.i.num_tensors = 1;
  EXPECT_FALSE(gst_tensors_info_is_equal(&a.i, &b.i));
  EXPECT_EQ(take(gst_tensors_info_compare_to_string(&a.i, &b.i)),
            "  0 : 'a' uint8 (3:4) | 'a' uint8 (3:4) \n  1 : float32 (5) | None Not equal\n");

  Info empty;
  EXPECT_EQ(gst_tensors_info_get_dimensions_string(&empty.i), nullptr);
  EXPECT_FALSE(gst_tensors_info_validate(&empty.i));
  EXPECT_EQ(take(gst_tensors_info_to_string(&empty.i)), "Format = static, Num_Tensors = 0");
  empty.i.format = _NNS_TENSOR_FORMAT_FLEXIBLE;
  EXPECT_TRUE(gst_tensors_info_validate(&empty.i));
  EXPECT_EQ(take(gst_tensors_info_to_string(&empty.i)), "Format = flexible");
}

TEST(CompatTensorsInfo, MoreThanSixteenTensorsUseExtra) {
  Info a;
  std::string dims, types;
  for (int i = 1; i <= 20; ++i) {
    dims += (i > 1 ? "," : "") + std::to_string(i);
    types += (i > 1 ? "," : "") + std::string(i % 2 ? "uint8" : "int16");
  }
  EXPECT_EQ(a.i.extra, nullptr);
  EXPECT_EQ(gst_tensors_info_parse_dimensions_string(&a.i, dims.c_str()), 20u);
  EXPECT_EQ(gst_tensors_info_parse_types_string(&a.i, types.c_str()), 20u);
  a.i.num_tensors = 20;
  ASSERT_NE(a.i.extra, nullptr);
  EXPECT_EQ(a.i.extra[1].dimension[0], 18u);
  EXPECT_EQ(gst_tensors_info_get_nth_info(&a.i, 17), &a.i.extra[1]);
  EXPECT_EQ(gst_tensors_info_get_nth_info(&a.i, 255), &a.i.extra[239]);
  EXPECT_EQ(gst_tensors_info_get_nth_info(&a.i, 256), nullptr);
  EXPECT_EQ(take(gst_tensors_info_get_dimensions_string(&a.i)), dims);
  EXPECT_EQ(gst_tensors_info_get_size(&a.i, 19), 40u);  // int16 x 20
  EXPECT_TRUE(gst_tensors_info_validate(&a.i));
  Info b;
  gst_tensors_info_copy(&b.i, &a.i);
  ASSERT_NE(b.i.extra, nullptr);
  EXPECT_NE(b.i.extra, a.i.extra);
  EXPECT_TRUE(gst_tensors_info_is_equal(&a.i, &b.i));
  b.i.extra[3].type = _NNS_FLOAT32;
  EXPECT_FALSE(gst_tensors_info_is_equal(&a.i, &b.i));
  gst_tensors_info_free(&b.i);
  EXPECT_EQ(b.i.extra, nullptr);
  EXPECT_EQ(b.i.num_tensors, 0u);
}

TEST(CompatTensorsConfig, RateAndStrings) {
  Config a, b;
  EXPECT_EQ(a.c.rate_n, -1);
  EXPECT_EQ(a.c.rate_d, -1);
  a.c.info.num_tensors = 1;
  gst_tensors_info_parse_dimensions_string(&a.c.info, "3:4");
  gst_tensors_info_parse_types_string(&a.c.info, "uint8");
  EXPECT_FALSE(gst_tensors_config_validate(&a.c));
  a.c.rate_n = 30;
  a.c.rate_d = 1;
  EXPECT_TRUE(gst_tensors_config_validate(&a.c));
  gst_tensors_config_copy(&b.c, &a.c);
  b.c.rate_n = 60;
  b.c.rate_d = 2;
  EXPECT_TRUE(gst_tensors_config_is_equal(&a.c, &b.c));
  b.c.rate_n = 61;
  EXPECT_FALSE(gst_tensors_config_is_equal(&a.c, &b.c));
  EXPECT_EQ(take(gst_tensors_config_to_string(&a.c)),
            "Format = static, Num_Tensors = 1, Tensors = [{ uint8 (3:4) }], Framerate = 30/1");
}

TEST(CompatMeta, HeaderLayoutAndSizes) {
  GstTensorMetaInfo m;
  gst_tensor_meta_info_init(&m);
  EXPECT_EQ(m.magic, 0xfeedccedu);
  EXPECT_EQ(m.version, 0xDE001000u);
  EXPECT_EQ(m.media_type, static_cast<uint32_t>(_NNS_TENSOR));
  guint major = 9, minor = 9;
  EXPECT_TRUE(gst_tensor_meta_info_get_version(&m, &major, &minor));
  EXPECT_EQ(major, 1u);
  EXPECT_EQ(minor, 0u);
  EXPECT_EQ(gst_tensor_meta_info_get_header_size(&m), 128u);
  EXPECT_FALSE(gst_tensor_meta_info_validate(&m));  // no type yet

  GstTensorInfo t;
  gst_tensor_info_init(&t);
  t.type = _NNS_FLOAT32;
  gst_tensor_parse_dimension("5:2", t.dimension);
  ASSERT_TRUE(gst_tensor_info_convert_to_meta(&t, &m));
  EXPECT_EQ(gst_tensor_meta_info_get_data_size(&m), 40u);
  uint8_t header[128];
  std::memset(header, 0xAB, sizeof header);
  ASSERT_TRUE(gst_tensor_meta_info_update_header(&m, header));
  uint32_t words[22];
  std::memcpy(words, header, sizeof words);
  EXPECT_EQ(words[0], 0xfeedccedu);
  EXPECT_EQ(words[2], static_cast<uint32_t>(_NNS_FLOAT32));
  EXPECT_EQ(words[3], 5u);
  EXPECT_EQ(words[4], 2u);
  EXPECT_EQ(words[20], static_cast<uint32_t>(_NNS_TENSOR));
  EXPECT_EQ(header[127], 0);  // the whole 128 bytes are written
  GstTensorMetaInfo back;
  ASSERT_TRUE(gst_tensor_meta_info_parse_header(&back, header));
  GstTensorInfo t2;
  ASSERT_TRUE(gst_tensor_meta_info_convert(&back, &t2));
  EXPECT_TRUE(gst_tensor_info_is_equal(&t, &t2));

  back.format = _NNS_TENSOR_FORMAT_SPARSE;
  back.sparse_info.nnz = 3;
  EXPECT_EQ(gst_tensor_meta_info_get_data_size(&back), 24u);  // 3 x (float32 + uint32 index)
  back.media_type = static_cast<uint32_t>(_NNS_MEDIA_ANY);
  EXPECT_FALSE(gst_tensor_meta_info_validate(&back));
  header[0] = 0;  // no magic
  EXPECT_FALSE(gst_tensor_meta_info_parse_header(&back, header));
  EXPECT_EQ(gst_tensor_meta_info_get_header_size(&back), 0u);
}

TEST(CompatVersionLog, VersionAndLastError) {
  guint ma = 0, mi = 0, mc = 9;
  nnstreamer_version_fetch(&ma, &mi, &mc);
  EXPECT_EQ(ma, 2u);
  EXPECT_EQ(mi, 7u);
  EXPECT_EQ(mc, 0u);
  // NNStreamer's versionControl.getVer01: the string is "NNStreamer M.m.u" of those numbers.
  EXPECT_EQ(take(nnstreamer_version_string()), "NNStreamer " + std::to_string(ma) + "." +
                                                   std::to_string(mi) + "." + std::to_string(mc));
  _nnstreamer_error_clean();
  EXPECT_EQ(_nnstreamer_error(), nullptr);
  Info empty;
  EXPECT_FALSE(gst_tensors_info_validate(&empty.i));
  const char *e = _nnstreamer_error();
  ASSERT_NE(e, nullptr);
  EXPECT_NE(std::string(e).find("0 tensors"), std::string::npos) << e;
  EXPECT_EQ(_nnstreamer_error(), nullptr);  // reported once
  char *bt = _backtrace_to_string();
  ASSERT_NE(bt, nullptr);
  EXPECT_GT(std::strlen(bt), 0u);
  free(bt);
}

TEST(CompatConf, CustomValuesFromIniAndEnvironment) {
  std::string dir = nns::test::make_temp_dir();
  std::string ini = dir + "/nnstreamer.ini";
  std::ofstream(ini) << "[common]\nenable_envvar=True\n[mygroup]\nword=hello\nflag=yes\n";
  const char *old = g_getenv("NNSTREAMER_CONF");
  std::string saved = old ? old : "";
  g_setenv("NNSTREAMER_CONF", ini.c_str(), TRUE);
  g_setenv("NNSTREAMER_mygroup_other", "from-env", TRUE);
  ASSERT_TRUE(nnsconf_loadconf(TRUE));
  EXPECT_EQ(take(nnsconf_get_custom_value_string("mygroup", "word")), "hello");
  EXPECT_EQ(take(nnsconf_get_custom_value_string("mygroup", "other")), "from-env");
  EXPECT_EQ(nnsconf_get_custom_value_string("mygroup", "none"), nullptr);
  EXPECT_TRUE(nnsconf_get_custom_value_bool("mygroup", "flag", FALSE));
  EXPECT_TRUE(nnsconf_get_custom_value_bool("mygroup", "none", TRUE));
  EXPECT_STREQ(nnsconf_get_subplugin_name_prefix(NNSCONF_PATH_DECODERS), "libnnstreamer_decoder_");
  char dump[512];
  nnsconf_dump(dump, sizeof dump);
  EXPECT_NE(std::string(dump).find(ini), std::string::npos) << dump;
  g_unsetenv("NNSTREAMER_mygroup_other");
  if (old)
    g_setenv("NNSTREAMER_CONF", saved.c_str(), TRUE);
  else
    g_unsetenv("NNSTREAMER_CONF");
  nnsconf_loadconf(TRUE);
  std::filesystem::remove_all(dir);
}

// nnstreamer_plugin_api.h (GStreamer side) ---------------------------------------------------

std::string caps_text(GstCaps *caps) {
  std::string s = take(gst_caps_to_string(caps));
  gst_caps_unref(caps);
  return s;
}

TEST(CompatCaps, FromConfig) {
  Config c;
  c.c.info.num_tensors = 1;
  gst_tensors_info_parse_dimensions_string(&c.c.info, "3:4");
  gst_tensors_info_parse_types_string(&c.c.info, "uint8");
  c.c.rate_n = 0;
  c.c.rate_d = 1;
  EXPECT_EQ(caps_text(gst_tensors_caps_from_config(&c.c)),
            "other/tensors, format=(string)static, num_tensors=(int)1, framerate=(fraction)0/1, "
            "dimensions=(string)3:4, types=(string)uint8");
  EXPECT_EQ(caps_text(gst_tensor_caps_from_config(&c.c)),
            "other/tensor, framerate=(fraction)0/1, dimension=(string)3:4, type=(string)uint8");
  c.c.info.format = _NNS_TENSOR_FORMAT_FLEXIBLE;
  EXPECT_EQ(caps_text(gst_tensors_caps_from_config(&c.c)),
            "other/tensors, format=(string)flexible, framerate=(fraction)0/1");
  Config two;
  two.c.info.num_tensors = 2;
  EXPECT_EQ(gst_tensor_caps_from_config(&two.c), nullptr);  // other/tensor holds one tensor
  EXPECT_EQ(caps_text(gst_tensors_caps_from_config(&two.c)),
            "other/tensors, format=(string)static, num_tensors=(int)2, "
            "framerate=(fraction)[ 0/1, 2147483647/1 ]");
}

TEST(CompatCaps, ToConfig) {
  Config c;
  GstCaps *caps = gst_caps_from_string(
      "other/tensors,num_tensors=2,dimensions=\"3:4,5\",types=\"uint8,int16\",framerate=5/1");
  ASSERT_TRUE(gst_tensors_config_from_caps(&c.c, caps, TRUE));  // format implied: static
  EXPECT_EQ(c.c.info.format, _NNS_TENSOR_FORMAT_STATIC);
  EXPECT_EQ(c.c.info.info[1].type, _NNS_INT16);
  EXPECT_EQ(c.c.rate_n, 5);
  gst_caps_unref(caps);
  caps = gst_caps_from_string("other/tensors,format=flexible");
  ASSERT_TRUE(gst_tensors_config_from_caps(&c.c, caps, FALSE));
  EXPECT_EQ(c.c.info.format, _NNS_TENSOR_FORMAT_FLEXIBLE);
  EXPECT_EQ(c.c.rate_n, -1);
  EXPECT_FALSE(gst_tensors_config_from_caps(&c.c, caps, TRUE));  // no framerate: not valid
  gst_caps_unref(caps);
  caps = gst_caps_from_string("video/x-raw,format=RGB");
  EXPECT_FALSE(gst_tensors_config_from_caps(&c.c, caps, FALSE));
  EXPECT_EQ(gst_structure_get_media_type(gst_caps_get_structure(caps, 0)), _NNS_VIDEO);
  EXPECT_FALSE(gst_structure_is_tensor_stream(gst_caps_get_structure(caps, 0)));
  gst_caps_unref(caps);
}

TEST(CompatCaps, DimensionsCompareAsDimensions) {
  GstCaps *a = gst_caps_from_string("other/tensor,dimension=(string)3:4,type=uint8");
  GstCaps *b = gst_caps_from_string("other/tensor,dimension=(string)3:4:1:1,type=uint8");
  GstCaps *c = gst_caps_from_string("other/tensor,dimension=(string)3:4:1:1,type=int8");
  EXPECT_FALSE(gst_caps_can_intersect(a, b));
  EXPECT_TRUE(gst_tensor_caps_can_intersect(a, b));
  EXPECT_FALSE(gst_tensor_caps_can_intersect(a, c));
  gst_tensor_caps_update_dimension(a, b);
  EXPECT_STREQ(gst_structure_get_string(gst_caps_get_structure(a, 0), "dimension"), "3:4:1:1");
  EXPECT_TRUE(gst_caps_can_intersect(a, b));
  gst_caps_unref(a);
  gst_caps_unref(b);
  gst_caps_unref(c);
}

TEST(CompatBuffer, HeaderOnMemory) {
  GstMemory *payload = gst_allocator_alloc(nullptr, 8, nullptr);
  {
    GstMapInfo map;
    ASSERT_TRUE(gst_memory_map(payload, &map, GST_MAP_WRITE));
    std::memset(map.data, 7, map.size);
    gst_memory_unmap(payload, &map);
  }
  GstTensorMetaInfo m;
  gst_tensor_meta_info_init(&m);
  m.type = _NNS_INT16;
  m.dimension[0] = 4;
  GstMemory *with = gst_tensor_meta_info_append_header(&m, payload);
  ASSERT_NE(with, nullptr);
  EXPECT_EQ(gst_memory_get_sizes(with, nullptr, nullptr), 136u);
  GstTensorMetaInfo back;
  EXPECT_TRUE(gst_tensor_meta_info_parse_memory(&back, with));
  EXPECT_EQ(back.type, static_cast<uint32_t>(_NNS_INT16));
  EXPECT_FALSE(gst_tensor_meta_info_parse_memory(&back, payload));  // 8 bytes, no header
  // A memory with a header describes itself when appended.
  GstBuffer *buf = gst_buffer_new();
  EXPECT_TRUE(gst_tensor_buffer_append_memory(buf, with, nullptr));
  EXPECT_FALSE(gst_tensor_buffer_append_memory(buf, payload, nullptr));  // consumed anyway
  EXPECT_EQ(gst_tensor_buffer_get_count(buf), 1u);
  EXPECT_EQ(gst_tensor_buffer_get_nth_memory(buf, 1), nullptr);
  gst_buffer_unref(buf);
}

TEST(CompatBuffer, AllocInitAlignsTheDefaultAllocator) {
  gst_tensor_alloc_init(255);  // GStreamer alignment mask: 256 bytes
  for (int i = 0; i < 4; ++i) {
    GstMemory *m = gst_allocator_alloc(nullptr, 100 + i, nullptr);
    GstMapInfo map;
    ASSERT_TRUE(gst_memory_map(m, &map, GST_MAP_READ));
    EXPECT_EQ(reinterpret_cast<uintptr_t>(map.data) % 256, 0u) << i;
    gst_memory_unmap(m, &map);
    gst_memory_unref(m);
  }
  GstAllocator *def = gst_allocator_find(nullptr);
  EXPECT_STREQ(G_OBJECT_TYPE_NAME(def), "NnsCompatTensorAllocator");
  gst_object_unref(def);
  gst_tensor_alloc_init(0);  // back to the system allocator
  def = gst_allocator_find(nullptr);
  GstAllocator *sys = gst_allocator_find(GST_ALLOCATOR_SYSMEM);
  EXPECT_EQ(def, sys);
  gst_object_unref(def);
  gst_object_unref(sys);
}

}  // namespace

// libnnstreamer-decoder-util.so / libnnstreamer-converter-util.so ------------------------------
#include "compat/ext_util.h"

namespace {

TEST(CompatDecoderUtil, LabelsFromFile) {
  std::string dir = nns::test::make_temp_dir();
  std::string path = dir + "/labels.txt";
  std::ofstream(path) << "cat\nbird\nox\n";
  imglabel_t l{};
  loadImageLabels(path.c_str(), &l);
  ASSERT_EQ(l.total_labels, 3u);  // the last newline does not make a fourth, empty label
  EXPECT_STREQ(l.labels[1], "bird");
  EXPECT_EQ(l.max_word_length, 4u);
  std::ofstream(path) << "a\n\nb";
  loadImageLabels(path.c_str(), &l);  // replaces the old labels
  ASSERT_EQ(l.total_labels, 3u);
  EXPECT_STREQ(l.labels[1], "");
  EXPECT_EQ(l.max_word_length, 1u);  // the old labels' lengths are forgotten
  _free_labels(&l);
  EXPECT_EQ(l.labels, nullptr);
  EXPECT_EQ(l.total_labels, 0u);
  loadImageLabels((dir + "/missing.txt").c_str(), &l);
  EXPECT_EQ(l.labels, nullptr);
  EXPECT_EQ(l.total_labels, 0u);
  std::filesystem::remove_all(dir);
}

TEST(CompatDecoderUtil, SpriteFromRasters) {
  static uint8_t glyphs[95][13] = {};
  glyphs['A' - 32][0] = 0x80;   // bottom row, leftmost pixel
  glyphs['A' - 32][12] = 0x01;  // top row, rightmost pixel
  glyphs['*' - 32][5] = 0xFF;
  auto *sprite = new singleLineSprite_t[1];
  initSingleLineSprite(*sprite, glyphs, 0xFF00FF00u);
  EXPECT_EQ((*sprite)['A'][12][0], 0xFF00FF00u);
  EXPECT_EQ((*sprite)['A'][12][1], 0u);
  EXPECT_EQ((*sprite)['A'][0][7], 0xFF00FF00u);
  for (int k = 0; k < 8; ++k) {
    EXPECT_EQ((*sprite)[200][7][k], 0xFF00FF00u) << k;  // non-ASCII: the '*' glyph
    EXPECT_EQ((*sprite)[10][7][k], 0xFF00FF00u) << k;
  }
  EXPECT_EQ((*sprite)['B'][7][0], 0u);
  delete[] sprite;
}

TEST(CompatExtUtil, FramerateAndConverterConfig) {
  GstCaps *caps = gst_caps_new_empty_simple("video/x-raw");
  Config c;
  setFramerateFromConfig(caps, &c.c);  // rate unset: nothing
  EXPECT_FALSE(gst_structure_has_field(gst_caps_get_structure(caps, 0), "framerate"));
  c.c.rate_n = 15;
  c.c.rate_d = 2;
  setFramerateFromConfig(caps, &c.c);
  EXPECT_EQ(caps_text(caps), "video/x-raw, framerate=(fraction)15/2");

  caps = gst_caps_from_string("application/octet-stream");
  ASSERT_TRUE(tcu_get_out_config(caps, &c.c));
  EXPECT_EQ(take(gst_tensors_config_to_string(&c.c)),
            "Format = static, Num_Tensors = 1, Tensors = [{ uint8 (1:1:1:1) }], Framerate = 0/1");
  gst_caps_unref(caps);
  caps = gst_caps_from_string("audio/x-raw,framerate=25/1");
  ASSERT_TRUE(tcu_get_out_config(caps, &c.c));
  EXPECT_EQ(c.c.rate_n, 25);
  EXPECT_EQ(c.c.rate_d, 1);
  gst_caps_unref(caps);
  EXPECT_FALSE(tcu_get_out_config(nullptr, &c.c));
}

}  // namespace

// NNStreamer's `rasters` glyph table, exported when the bounding_boxes font is in the tree.
#if __has_include("decoder/bounding_boxes/font_8x13.h")
#include "decoder/bounding_boxes/font_8x13.h"

extern "C" const uint8_t rasters[95][13];

namespace {

TEST(CompatDecoderUtil, RastersAreTheLabelFontBottomRowFirst) {
  for (int c = 0; c < 95; ++c)
    for (int r = 0; r < 13; ++r)
      ASSERT_EQ(rasters[c][r], nns::bbox::kFont8x13[c][12 - r])
          << "char " << c + 32 << " row " << r;
  auto *sprite = new singleLineSprite_t[1];
  initSingleLineSprite(*sprite, const_cast<uint8_t(*)[13]>(rasters), 1);
  for (int x = 0; x < 8; ++x)  // sprite row 0 is the top row of the glyph
    EXPECT_EQ((*sprite)['A'][0][x], (nns::bbox::kFont8x13['A' - 32][0] >> (7 - x)) & 1u) << x;
  delete[] sprite;
}

}  // namespace
#endif

// nnstreamer_plugin_api_filter.h's accelerator helpers, through libnnstreamer-single.so's exports.
TEST(CompatAccl, TypeStringAndParse) {
  EXPECT_EQ(get_accl_hw_type("npu.vivante"), ACCL_NPU_VIVANTE);
  EXPECT_EQ(get_accl_hw_type("Npu"), ACCL_NONE);
  EXPECT_EQ(get_accl_hw_type(nullptr), ACCL_NONE);
  EXPECT_STREQ(get_accl_hw_str(ACCL_NPU_SR), "npu.sr");
  EXPECT_STREQ(get_accl_hw_str(ACCL_AUTO), "auto");
  EXPECT_STREQ(get_accl_hw_str(static_cast<accl_hw>(0x7777)), "none");
  const char *sup[] = {ACCL_CPU_STR, ACCL_GPU_STR, nullptr};
  auto parse = [&](const char *in, const char *aut, const char *def) {
    parse_accl_args a{in, sup, aut, def};
    return parse_accl_hw_fill(a);
  };
  EXPECT_EQ(parse("true:cpu,gpu", nullptr, nullptr), ACCL_CPU);
  EXPECT_EQ(parse("true:gpu,cpu", nullptr, nullptr), ACCL_GPU);
  EXPECT_EQ(parse("true:!cpu", "gpu", nullptr), ACCL_GPU);
  EXPECT_EQ(parse("true:npu", nullptr, "gpu"), ACCL_CPU);  // unsupported: auto, the first one
  EXPECT_EQ(parse("false:gpu", nullptr, nullptr), ACCL_NONE);
  EXPECT_EQ(parse(nullptr, nullptr, "gpu"), ACCL_GPU);
  parse_accl_args empty{"true:cpu", nullptr, nullptr, nullptr};
  EXPECT_EQ(parse_accl_hw_fill(empty), ACCL_NONE);
}

// nnstreamer_internal.h: NNStreamer's framework detection table and the accelerator check.
TEST(CompatInternal, DetectFrameworkAsNNStreamer) {
  auto detect = [](std::vector<const char *> files, gboolean conf = FALSE) {
    gchar *fw = gst_tensor_filter_detect_framework(files.data(), files.size(), conf);
    std::string r = fw ? fw : "(null)";
    g_free(fw);
    return r;
  };
  EXPECT_EQ(detect({"m.tflite"}), "tensorflow-lite");
  EXPECT_EQ(detect({"/a/b/M.TFLite"}), "tensorflow-lite");
  EXPECT_EQ(detect({"m.pb"}), "tensorflow");
  EXPECT_EQ(detect({"m.pt"}), "pytorch");
  EXPECT_EQ(detect({"m.py"}), "python");
  EXPECT_EQ(detect({"m.circle"}), "nnfw");
  EXPECT_EQ(detect({"libfilter.so"}), "custom");
  EXPECT_EQ(detect({"m.xml"}), "openvino");
  EXPECT_EQ(detect({"m.bin"}), "openvino");
  EXPECT_EQ(detect({"m.nb"}), "vivante");
  EXPECT_EQ(detect({"m.gguf"}), "llamacpp");
  EXPECT_EQ(detect({"m.onnx"}), "(null)");  // not in NNStreamer's table
  EXPECT_EQ(detect({"model"}), "(null)");   // no extension
  EXPECT_EQ(detect({"a.pb", "b.pb"}), "caffe2");
  EXPECT_EQ(detect({"a.pb", "a.pb"}), "(null)");
  EXPECT_EQ(detect({"a.so", "b.nb"}), "vivante");
  EXPECT_EQ(detect({"a.nb", "b.so"}), "vivante");
  EXPECT_EQ(detect({"a.tflite", "b.tflite", "c.tflite"}), "(null)");
  std::string dir = nns::test::make_temp_dir();
  EXPECT_EQ(detect({dir.c_str()}), "nnfw");
  EXPECT_EQ(gst_tensor_filter_detect_framework(nullptr, 1, FALSE), nullptr);
  // load_conf: [filter] framework_priority_<ext>, its first available framework.
  std::string ini = dir + "/nnstreamer.ini";
  std::ofstream(ini) << "[common]\nenable_envvar=False\n[filter]\n"
                        "framework_priority_onnx=nosuch,custom-easy\n"
                        "framework_priority_tflite=nosuch\n";
  const char *old = g_getenv("NNSTREAMER_CONF");
  std::string saved = old ? old : "";
  g_setenv("NNSTREAMER_CONF", ini.c_str(), TRUE);
  nnsconf_loadconf(TRUE);
  EXPECT_EQ(detect({"m.onnx"}, TRUE), "custom-easy");
  EXPECT_EQ(detect({"m.onnx"}, FALSE), "(null)");
  EXPECT_EQ(detect({"m.tflite"}, TRUE), "tensorflow-lite");  // none available: the table
  if (old)
    g_setenv("NNSTREAMER_CONF", saved.c_str(), TRUE);
  else
    g_unsetenv("NNSTREAMER_CONF");
  nnsconf_loadconf(TRUE);
  std::filesystem::remove_all(dir);
}

TEST(CompatInternal, CheckHwAvailability) {
  // custom-easy is built in and has no accelerator check: the CPU only.
  EXPECT_TRUE(gst_tensor_filter_check_hw_availability("custom-easy", ACCL_CPU, nullptr));
  EXPECT_TRUE(gst_tensor_filter_check_hw_availability("custom-easy", ACCL_CPU_SIMD, nullptr));
  EXPECT_TRUE(gst_tensor_filter_check_hw_availability("custom-easy", ACCL_AUTO, "opt"));
  EXPECT_TRUE(gst_tensor_filter_check_hw_availability("custom-easy", ACCL_DEFAULT, nullptr));
  EXPECT_FALSE(gst_tensor_filter_check_hw_availability("custom-easy", ACCL_GPU, nullptr));
  EXPECT_FALSE(gst_tensor_filter_check_hw_availability("custom-easy", ACCL_NPU, nullptr));
  EXPECT_FALSE(gst_tensor_filter_check_hw_availability("no-such-framework", ACCL_AUTO, nullptr));
  EXPECT_FALSE(gst_tensor_filter_check_hw_availability(nullptr, ACCL_CPU, nullptr));
}
