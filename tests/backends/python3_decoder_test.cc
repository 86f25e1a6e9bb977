// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=python3 option1=<file.py>: caps from getOutCaps (with the input
// framerate), exact output bytes (image, text, raw), zero-copy of bytes results, a round trip
// with the python3 converter, and the bus errors for broken scripts. Scripts:
// tests/data/python/convdec/.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/harness.h"

namespace {

using nns::test::HarnessPtr;
using nns::test::run_pipeline;

std::string script(const std::string &name) {
  return std::string(NNS_SOURCE_DIR) + "/tests/data/python/convdec/" + name;
}

bool available() {
  GstElementFactory *f = gst_element_factory_find("tensor_decoder");
  if (!f) return false;
  gst_object_unref(f);
  return std::filesystem::exists(std::string(NNS_BUILD_DIR) +
                                 "/subplugins/decoders/libnnstreamer_decoder_python3.so");
}

bool converter_available() {
  return std::filesystem::exists(std::string(NNS_BUILD_DIR) +
                                 "/subplugins/converters/libnnstreamer_converter_python3.so");
}

#define REQUIRE_PYTHON3_DECODER()                                                    \
  do {                                                                               \
    if (!available()) GTEST_SKIP() << "the python3 decoder sub-plugin is not built"; \
  } while (0)

GstBuffer *bytes_buffer(const std::vector<uint8_t> &v) {
  GstBuffer *b = gst_buffer_new_allocate(nullptr, v.size(), nullptr);
  gst_buffer_fill(b, 0, v.data(), v.size());
  return b;
}

std::vector<uint8_t> buffer_bytes(GstBuffer *b) {
  std::vector<uint8_t> v(gst_buffer_get_size(b));
  gst_buffer_extract(b, 0, v.data(), v.size());
  return v;
}

std::string current_caps(GstHarness *h) {
  GstCaps *c = gst_pad_get_current_caps(h->sinkpad);
  if (!c) return "";
  gchar *s = gst_caps_to_string(c);
  std::string r = s;
  g_free(s);
  gst_caps_unref(c);
  return r;
}

HarnessPtr decoder(const std::string &file, const std::string &in_caps) {
  HarnessPtr h(
      gst_harness_new_parse(("tensor_decoder mode=python3 option1=" + script(file)).c_str()));
  gst_harness_set_src_caps_str(h.get(), in_caps.c_str());
  return h;
}

TEST(Python3Decoder, RgbTensorToRgbaImage) {
  REQUIRE_PYTHON3_DECODER();
  auto h = decoder("dec_rgba.py",
                   "other/tensor,dimension=(string)3:4:2:1,type=(string)uint8,framerate=(fraction)"
                   "10/1");
  std::vector<uint8_t> in(24);
  for (size_t i = 0; i < in.size(); i++) in[i] = static_cast<uint8_t>(i * 10);
  ASSERT_EQ(gst_harness_push(h.get(), bytes_buffer(in)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(out, nullptr);
  std::vector<uint8_t> want;
  for (size_t p = 0; p < 8; p++) {
    for (int c = 0; c < 3; c++) want.push_back(in[p * 3 + c]);
    want.push_back(static_cast<uint8_t>(255 - in[p * 3 + 1]));
  }
  EXPECT_EQ(buffer_bytes(out), want);
  gst_buffer_unref(out);
  EXPECT_EQ(current_caps(h.get()),
            "video/x-raw, format=(string)RGBA, width=(int)4, height=(int)2, "
            "framerate=(fraction)10/1");
}

TEST(Python3Decoder, TensorsToTextWithShapesAndRate) {
  REQUIRE_PYTHON3_DECODER();
  auto h = decoder("dec_text.py",
                   "other/tensors,format=static,num_tensors=2,dimensions=(string)4:1:1:1.3,"
                   "types=(string)int32.uint8,framerate=(fraction)30/1");
  std::vector<int32_t> a = {1, 2, -3, 6};
  std::vector<uint8_t> in(16);
  std::memcpy(in.data(), a.data(), 16);
  GstBuffer *b = bytes_buffer(in);
  GstBuffer *b2 = bytes_buffer({2, 3, 4});
  gst_buffer_append_memory(b, gst_buffer_get_memory(b2, 0));
  gst_buffer_unref(b2);
  ASSERT_EQ(gst_harness_push(h.get(), b), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(out, nullptr);
  auto v = buffer_bytes(out);
  gst_buffer_unref(out);
  // in_info dims are padded to rank 4; the arrays have the tensors' element types.
  EXPECT_EQ(std::string(v.begin(), v.end()),
            "2 tensors @30/1: [4,1,1,1] int32 sum=6; [3,1,1,1] uint8 sum=9\n");
  EXPECT_EQ(current_caps(h.get()), "text/x-raw, format=(string)utf8, framerate=(fraction)30/1");
}

// Without getOutCaps: application/octet-stream; bytes results are the output memory itself.
TEST(Python3Decoder, NoGetOutCapsGivesOctetStream) {
  REQUIRE_PYTHON3_DECODER();
  auto h = decoder("dec_concat.py",
                   "other/tensor,dimension=(string)4,type=(string)uint8,framerate=(fraction)0/1");
  const std::vector<std::vector<uint8_t>> inputs = {
      {1, 2, 3, 4}, {201, 5, 6, 7}, {202, 8, 9, 10}, {203, 0, 0, 0}};
  for (const auto &in : inputs) {
    SCOPED_TRACE(std::to_string(in[0]));
    ASSERT_EQ(gst_harness_push(h.get(), bytes_buffer(in)), GST_FLOW_OK);
    GstBuffer *out = gst_harness_pull(h.get());
    ASSERT_NE(out, nullptr);
    if (in[0] == 203)
      EXPECT_EQ(gst_buffer_get_size(out), 0u);
    else
      EXPECT_EQ(buffer_bytes(out), in);
    if (in[0] == 1) {  // bytes: lent, read-only
      ASSERT_EQ(gst_buffer_n_memory(out), 1u);
      EXPECT_TRUE(GST_MEMORY_IS_READONLY(gst_buffer_peek_memory(out, 0)));
    }
    gst_buffer_unref(out);
  }
  EXPECT_EQ(current_caps(h.get()), "application/octet-stream, framerate=(fraction)0/1");
}

// tensor_converter custom-script -> tensor_decoder python3 -> the same JSON document.
TEST(Python3Decoder, RoundTripWithPython3Converter) {
  REQUIRE_PYTHON3_DECODER();
  if (!converter_available()) GTEST_SKIP() << "the python3 converter sub-plugin is not built";
  std::string dir = nns::test::make_temp_dir();
  const std::string doc = R"({"name":"round trip","values":[3,-1,2147483647]})";
  std::ofstream(dir + "/in.json") << doc;
  auto r =
      run_pipeline("filesrc location=" + dir +
                   "/in.json blocksize=-1 ! application/octet-stream ! "
                   "tensor_converter mode=custom-script:" +
                   script("conv_json.py") +
                   " ! other/tensors,num_tensors=2,framerate=10/1 ! "
                   "tensor_decoder mode=python3 option1=" +
                   script("dec_json.py") +
                   " ! application/json,framerate=10/1 ! filesink location=" + dir + "/out.json");
  ASSERT_TRUE(r.eos) << r.error_text;
  auto v = nns::test::read_file(dir + "/out.json");
  EXPECT_EQ(std::string(v.begin(), v.end()), doc);
}

// Raw bytes -> int32 view tensor (no copy) -> concatenated bytes: identical to the input.
TEST(Python3Decoder, RoundTripRawBytes) {
  REQUIRE_PYTHON3_DECODER();
  if (!converter_available()) GTEST_SKIP() << "the python3 converter sub-plugin is not built";
  std::string dir = nns::test::make_temp_dir();
  std::string data;
  for (int i = 0; i < 64; i++) data.push_back(static_cast<char>(i * 3 + 1));
  std::ofstream(dir + "/in.bin", std::ios::binary) << data;
  auto r = run_pipeline("filesrc location=" + dir +
                        "/in.bin blocksize=16 ! application/octet-stream ! "
                        "tensor_converter mode=custom-script:" +
                        script("conv_view.py") + " ! tensor_decoder mode=python3 option1=" +
                        script("dec_concat.py") + " ! filesink location=" + dir + "/out.bin");
  ASSERT_TRUE(r.eos) << r.error_text;
  auto v = nns::test::read_file(dir + "/out.bin");
  EXPECT_EQ(std::string(v.begin(), v.end()), data);
}

bool has_flexbuffers() {
  return system("/usr/bin/python3 -c 'from flatbuffers import flexbuffers' >/dev/null 2>&1") == 0;
}

// A real video stream: RGB frames -> tensors -> RGBA image caps from getOutCaps, usable by
// videoconvert; back to RGB it equals the original frames.
TEST(Python3Decoder, VideoThroughVideoconvert) {
  REQUIRE_PYTHON3_DECODER();
  std::string dir = nns::test::make_temp_dir();
  auto r = run_pipeline(
      "videotestsrc num-buffers=3 pattern=smpte ! video/x-raw,format=RGB,width=4,height=2,"
      "framerate=5/1 ! tee name=t ! queue ! tensor_converter ! tensor_decoder mode=python3 "
      "option1=" +
      script("dec_rgba.py") +
      " ! video/x-raw,format=RGBA,framerate=5/1 ! videoconvert ! video/x-raw,format=RGB ! "
      "filesink location=" +
      dir + "/decoded t. ! queue ! videoconvert ! video/x-raw,format=RGB ! filesink location=" +
      dir + "/direct");
  ASSERT_TRUE(r.eos) << r.error_text;
  auto decoded = nns::test::read_file(dir + "/decoded");
  auto direct = nns::test::read_file(dir + "/direct");
  ASSERT_EQ(direct.size(), 3u * 3 * 4 * 2);
  EXPECT_EQ(decoded, direct);
}

// tensor_decoder python3 -> other/flexbuf -> tensor_converter custom-script -> the same tensors
// (video frames, and two tensors with different types from tensor_mux).
TEST(Python3Decoder, FlexbufRoundTrip) {
  REQUIRE_PYTHON3_DECODER();
  if (!converter_available()) GTEST_SKIP() << "the python3 converter sub-plugin is not built";
  if (!has_flexbuffers()) GTEST_SKIP() << "python3-flatbuffers (flexbuffers) is not installed";
  std::string dir = nns::test::make_temp_dir();
  const std::string dec =
      "tensor_decoder mode=python3 option1=" + script("dec_flexbuf.py") +
      " ! other/flexbuf ! tensor_converter mode=custom-script:" + script("conv_flexbuf.py");
  auto r = run_pipeline(
      "videotestsrc num-buffers=3 pattern=13 ! video/x-raw,format=BGRx,width=16,height=8,"
      "framerate=5/1 ! tensor_converter ! tee name=t ! queue ! " +
      dec + " ! other/tensors,num_tensors=1,framerate=5/1 ! filesink location=" + dir +
      "/round t. ! queue ! filesink location=" + dir + "/direct");
  ASSERT_TRUE(r.eos) << r.error_text;
  auto direct = nns::test::read_file(dir + "/direct");
  ASSERT_EQ(direct.size(), 3u * 4 * 16 * 8);
  EXPECT_EQ(nns::test::read_file(dir + "/round"), direct);

  // Two tensors (uint8 video, int16 audio) through one flexbuf frame each.
  r = run_pipeline(
      "tensor_mux name=m sync-mode=nosync ! tee name=t ! queue ! " + dec +
      " ! filesink location=" + dir + "/round2 t. ! queue ! filesink location=" + dir +
      "/direct2 videotestsrc num-buffers=1 ! video/x-raw,format=GRAY8,width=4,height=4,"
      "framerate=5/1 ! tensor_converter ! m.sink_0 audiotestsrc num-buffers=1 "
      "samplesperbuffer=8 ! audio/x-raw,format=S16LE,rate=8000,channels=1 ! tensor_converter "
      "frames-per-tensor=8 ! m.sink_1");
  ASSERT_TRUE(r.eos) << r.error_text;
  auto direct2 = nns::test::read_file(dir + "/direct2");
  ASSERT_EQ(direct2.size(), 16u + 16u);
  EXPECT_EQ(nns::test::read_file(dir + "/round2"), direct2);
}

// Two converter+decoder pairs on their own streaming threads (GIL taken per call): both
// branches reproduce the input exactly.
TEST(Python3Decoder, ParallelBranches) {
  REQUIRE_PYTHON3_DECODER();
  if (!converter_available()) GTEST_SKIP() << "the python3 converter sub-plugin is not built";
  std::string dir = nns::test::make_temp_dir();
  std::string data;
  for (int i = 0; i < 64 * 40; i++) data.push_back(static_cast<char>((i * 7) & 0xff));
  std::ofstream(dir + "/in.bin", std::ios::binary) << data;
  std::string branch = " ! queue ! tensor_converter mode=custom-script:" + script("conv_view.py") +
                       " ! tensor_decoder mode=python3 option1=" + script("dec_concat.py") +
                       " ! filesink location=" + dir;
  auto r = run_pipeline("filesrc location=" + dir +
                        "/in.bin blocksize=64 ! application/octet-stream ! tee name=t t." + branch +
                        "/a t." + branch + "/b");
  ASSERT_TRUE(r.eos) << r.error_text;
  for (const char *f : {"/a", "/b"}) {
    auto v = nns::test::read_file(dir + f);
    EXPECT_EQ(std::string(v.begin(), v.end()), data) << f;
  }
}

// ---- Errors: the bus error names the option/script and carries the Python exception. ----

nns::test::RunResult run_with(const std::string &option1, uint8_t first_byte = 0) {
  std::string dir = nns::test::make_temp_dir();
  std::ofstream(dir + "/in.bin", std::ios::binary)
      << std::string(1, static_cast<char>(first_byte)) << std::string(3, '\0');
  return run_pipeline("filesrc location=" + dir +
                      "/in.bin blocksize=-1 ! application/octet-stream ! "
                      "tensor_converter input-dim=4 input-type=uint8 ! tensor_decoder "
                      "mode=python3" +
                      (option1.empty() ? std::string() : " option1=" + option1) + " ! fakesink");
}

void expect_error(const nns::test::RunResult &r, const std::vector<std::string> &parts) {
  ASSERT_TRUE(r.error) << "expected an error";
  EXPECT_NE(r.error_text.find("tensordecoder"), std::string::npos) << r.error_text;
  for (const auto &p : parts)
    EXPECT_NE(r.error_text.find(p), std::string::npos) << p << " not in:\n" << r.error_text;
}

TEST(Python3DecoderErrors, MissingScript) {
  REQUIRE_PYTHON3_DECODER();
  expect_error(run_with(script("no_such_decoder.py")), {"rejected option1=", "no_such_decoder.py"});
}

TEST(Python3DecoderErrors, NoOption1) {
  REQUIRE_PYTHON3_DECODER();
  expect_error(run_with(""), {"option1 (the Python script) is not set"});
}

TEST(Python3DecoderErrors, SyntaxError) {
  REQUIRE_PYTHON3_DECODER();
  expect_error(run_with(script("bad_syntax_conv.py")),
               {"rejected option1=", "bad_syntax_conv.py", "SyntaxError", "line 5"});
}

TEST(Python3DecoderErrors, ClassMissing) {
  REQUIRE_PYTHON3_DECODER();
  expect_error(run_with(script("dec_no_class.py")),
               {"option1", "dec_no_class.py", "defines no class CustomDecoder"});
}

TEST(Python3DecoderErrors, ConstructorRaises) {
  REQUIRE_PYTHON3_DECODER();
  expect_error(run_with(script("dec_raise_init.py")),
               {"CustomDecoder() raised", "RuntimeError: decoder constructor refuses"});
}

TEST(Python3DecoderErrors, GetOutCapsProblems) {
  REQUIRE_PYTHON3_DECODER();
  expect_error(run_with(script("dec_caps_raise.py")),
               {"getOutCaps() raised", "LookupError: no caps for you"});
  expect_error(run_with(script("dec_bad_caps.py")),
               {"getOutCaps() returned 'this is, not = caps ,,'", "not a usable caps string"});
  expect_error(run_with(script("dec_caps_type.py")),
               {"getOutCaps() returned int; expected a caps string"});
}

TEST(Python3DecoderErrors, DecodeProblems) {
  REQUIRE_PYTHON3_DECODER();
  expect_error(run_with(script("dec_cases.py"), 1), {"failed to decode a frame", "decode() raised",
                                                     "ZeroDivisionError", "dec_cases.py\", line"});
  expect_error(run_with(script("dec_cases.py"), 2), {"decode() returned str; expected bytes"});
  expect_error(run_with(script("dec_cases.py"), 3), {"decode() returned NoneType; expected bytes"});
}

}  // namespace
