// SPDX-License-Identifier: LGPL-2.1-only
// The python3 filter back end through its C ABI: dlopen build/subplugins/filters/
// libnnstreamer_filter_python3.so, open the scripts in tests/data/python, query shapes, invoke.
#include <signal.h>

#include <mutex>
#include <thread>

#include "filter_python3_util.h"

namespace {

using namespace nns::test::python3;

TEST(FilterPython3, Table) {
  REQUIRE_BACKEND();
  const nns_filter_backend_i *t = backend();
  EXPECT_EQ(t->api_version, NNS_FILTER_BACKEND_API_VERSION);
  EXPECT_STREQ(t->name, "python3");
  EXPECT_TRUE(t->flags & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE);
  ASSERT_NE(t->extensions, nullptr);
  EXPECT_STREQ(t->extensions[0], ".py");
  EXPECT_NE(t->free_output, nullptr);
}

TEST(FilterPython3, PassthroughGetDims) {
  REQUIRE_BACKEND();
  Filter f(script("passthrough.py"));
  ASSERT_EQ(f.rc, 0) << f.error();
  ASSERT_EQ(f.model_info(), 0) << f.error();
  ASSERT_EQ(f.in->num_tensors, 1u);
  EXPECT_EQ(dims_of(f.in->tensors[0]), (std::vector<uint32_t>{3, 280, 40, 1}));
  EXPECT_EQ(f.in->tensors[0].type, static_cast<uint32_t>(_NNS_UINT8));
  ASSERT_EQ(f.out->num_tensors, 1u);
  EXPECT_EQ(dims_of(f.out->tensors[0]), (std::vector<uint32_t>{3, 280, 40, 1}));
  // A getInputDim/getOutputDim script cannot take another input.
  auto other = make_desc({{{3, 10, 10, 1}, _NNS_UINT8}});
  EXPECT_EQ(f.set_input(*other), -ENOTSUP);

  std::vector<uint8_t> data(3 * 280 * 40);
  for (size_t i = 0; i < data.size(); i++) data[i] = static_cast<uint8_t>(i * 7 + 3);
  std::vector<GstTensorMemory> ins{{data.data(), data.size()}}, outs(1);
  ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
  ASSERT_EQ(outs[0].size, data.size());
  // The script returned the input array itself: the host gets a copy, not its own input memory.
  EXPECT_NE(outs[0].data, data.data());
  EXPECT_EQ(std::memcmp(outs[0].data, data.data(), data.size()), 0);
  f.release(outs);
}

TEST(FilterPython3, InputsAreZeroCopyReadOnly1D) {
  REQUIRE_BACKEND();
  Filter f(script("probe.py"));
  ASSERT_EQ(f.rc, 0) << f.error();
  alignas(16) uint8_t a[16] = {};
  alignas(16) float b[4] = {1, 2, 3, 4};
  std::vector<GstTensorMemory> ins{{a, sizeof a}, {b, sizeof b}}, outs(1);
  ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
  ASSERT_EQ(outs[0].size, 8 * sizeof(uint64_t));
  const auto *r = static_cast<const uint64_t *>(outs[0].data);
  EXPECT_EQ(r[0], reinterpret_cast<uint64_t>(a));  // same memory: no copy
  EXPECT_EQ(r[1], reinterpret_cast<uint64_t>(b));
  EXPECT_EQ(r[2], 0u);  // read-only
  EXPECT_EQ(r[3], 0u);
  EXPECT_EQ(r[4], 1016u);  // 1-D, 16 elements
  EXPECT_EQ(r[5], 1004u);  // 1-D, 4 elements
  EXPECT_EQ(r[7], 1u);
  f.release(outs);
}

TEST(FilterPython3, ScalerSetInputDimDownAndUp) {
  REQUIRE_BACKEND();
  // 3:8:4:1 uint8, pixel (x, y) channel c = 100*c + 10*y + x.
  std::vector<uint8_t> img(3 * 8 * 4);
  for (uint32_t y = 0; y < 4; y++)
    for (uint32_t x = 0; x < 8; x++)
      for (uint32_t c = 0; c < 3; c++)
        img[(y * 8 + x) * 3 + c] = static_cast<uint8_t>(100 * c + 10 * y + x);
  auto in = make_desc({{{3, 8, 4, 1}, _NNS_UINT8}});
  for (auto [w, h] : {std::pair<uint32_t, uint32_t>{4, 2}, {16, 8}}) {
    std::string custom = std::to_string(w) + "x" + std::to_string(h);
    Filter f(script("scaler.py"), custom.c_str());
    ASSERT_EQ(f.rc, 0) << f.error();
    EXPECT_EQ(f.model_info(), -ENOTSUP);  // setInputDim scripts have no fixed shapes
    ASSERT_EQ(f.set_input(*in), 0) << f.error();
    ASSERT_EQ(f.out->num_tensors, 1u);
    EXPECT_EQ(dims_of(f.out->tensors[0]), (std::vector<uint32_t>{3, w, h, 1}));
    EXPECT_EQ(f.out->tensors[0].type, static_cast<uint32_t>(_NNS_UINT8));
    std::vector<GstTensorMemory> ins{{img.data(), img.size()}}, outs(1);
    ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
    ASSERT_EQ(outs[0].size, 3u * w * h);
    const auto *o = static_cast<const uint8_t *>(outs[0].data);
    for (uint32_t y = 0; y < h; y++)
      for (uint32_t x = 0; x < w; x++)
        for (uint32_t c = 0; c < 3; c++) {
          uint32_t sx = x * 8 / w, sy = y * 4 / h;
          ASSERT_EQ(o[(y * w + x) * 3 + c], img[(sy * 8 + sx) * 3 + c])
              << custom << " " << x << "," << y;
        }
    f.release(outs);
  }
}

TEST(FilterPython3, ScalerRank3InputGetsRank4View) {
  REQUIRE_BACKEND();
  // Caps often give "3:8:4" (rank 3); scripts written for NNStreamer index dims[3].
  auto in = make_desc({{{3, 8, 4}, _NNS_UINT8}});
  Filter f(script("scaler.py"), "2x2");
  ASSERT_EQ(f.rc, 0) << f.error();
  ASSERT_EQ(f.set_input(*in), 0) << f.error();
  EXPECT_EQ(dims_of(f.out->tensors[0]), (std::vector<uint32_t>{3, 2, 2, 1}));
}

TEST(FilterPython3, SetInputDimAtOpenWhenInputGiven) {
  REQUIRE_BACKEND();
  auto in = make_desc({{{3, 8, 4, 1}, _NNS_UINT8}});
  Filter f(script("scaler.py"), "4x2", in.get());
  ASSERT_EQ(f.rc, 0) << f.error();
  std::vector<uint8_t> img(3 * 8 * 4, 9);
  std::vector<GstTensorMemory> ins{{img.data(), img.size()}}, outs(1);
  ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
  EXPECT_EQ(outs[0].size, 3u * 4 * 2);
  f.release(outs);
}

TEST(FilterPython3, InvokeBeforeInputKnown_n) {
  REQUIRE_BACKEND();
  Filter f(script("scaler.py"), "4x2");
  ASSERT_EQ(f.rc, 0) << f.error();
  uint8_t px[3] = {};
  std::vector<GstTensorMemory> ins{{px, 3}}, outs(1);
  EXPECT_NE(f.invoke(ins, outs), 0);
  EXPECT_NE(f.error().find("not known yet"), std::string::npos) << f.error();
  EXPECT_EQ(outs[0].data, nullptr);
}

TEST(FilterPython3, SetInputDimReturnsNone_n) {
  REQUIRE_BACKEND();
  Filter f(script("scaler.py"));
  ASSERT_EQ(f.rc, 0) << f.error();
  auto two = make_desc({{{3, 4, 4, 1}, _NNS_UINT8}, {{3, 4, 4, 1}, _NNS_UINT8}});
  EXPECT_NE(f.set_input(*two), 0);
  EXPECT_NE(f.error().find("setInputDim() returned None"), std::string::npos) << f.error();
  EXPECT_NE(f.error().find("3:4:4:1 uint8, 3:4:4:1 uint8"), std::string::npos) << f.error();
}

TEST(FilterPython3, MultiTensorMath) {
  REQUIRE_BACKEND();
  Filter f(script("add.py"));
  ASSERT_EQ(f.rc, 0) << f.error();
  ASSERT_EQ(f.model_info(), 0) << f.error();
  EXPECT_EQ(f.in->num_tensors, 2u);
  EXPECT_EQ(f.out->num_tensors, 2u);
  EXPECT_EQ(f.out->tensors[1].type, static_cast<uint32_t>(_NNS_FLOAT32));
  float a[4] = {1, 2, 3, 4}, b[4] = {0.5f, -1, 10, 2};
  std::vector<GstTensorMemory> ins{{a, sizeof a}, {b, sizeof b}}, outs(2);
  ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
  const float *s = static_cast<const float *>(outs[0].data),
              *p = static_cast<const float *>(outs[1].data);
  for (int i = 0; i < 4; i++) {
    EXPECT_EQ(s[i], a[i] + b[i]);
    EXPECT_EQ(p[i], a[i] * b[i]);
  }
  f.release(outs);
}

TEST(FilterPython3, EveryTensorType) {
  REQUIRE_BACKEND();
  const uint32_t types[] = {_NNS_INT32, _NNS_UINT32, _NNS_INT16,   _NNS_UINT16,
                            _NNS_INT8,  _NNS_UINT8,  _NNS_FLOAT64, _NNS_FLOAT32,
                            _NNS_INT64, _NNS_UINT64, _NNS_FLOAT16};
  const size_t sizes[] = {4, 4, 2, 2, 1, 1, 8, 4, 8, 8, 2};
  for (size_t k = 0; k < 11; k++) {
    auto in = make_desc({{{2, 3}, types[k]}});
    Filter f(script("identity.py"), "double");
    ASSERT_EQ(f.rc, 0) << f.error();
    ASSERT_EQ(f.set_input(*in), 0) << f.error();
    EXPECT_EQ(f.out->tensors[0].type, types[k]);
    EXPECT_EQ(dims_of(f.out->tensors[0]), (std::vector<uint32_t>{2, 3, 1, 1}));
    std::vector<uint8_t> buf(6 * sizes[k], 0);
    // Element value 1 in every type (float16 1.0 = 0x3c00).
    for (size_t e = 0; e < 6; e++) {
      uint8_t *p = &buf[e * sizes[k]];
      switch (types[k]) {
        case _NNS_FLOAT64: {
          double v = 1;
          std::memcpy(p, &v, 8);
          break;
        }
        case _NNS_FLOAT32: {
          float v = 1;
          std::memcpy(p, &v, 4);
          break;
        }
        case _NNS_FLOAT16: {
          uint16_t v = 0x3c00;
          std::memcpy(p, &v, 2);
          break;
        }
        default:
          p[0] = 1;
      }
    }
    std::vector<GstTensorMemory> ins{{buf.data(), buf.size()}}, outs(1);
    ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
    ASSERT_EQ(outs[0].size, buf.size());
    const uint8_t *o = static_cast<const uint8_t *>(outs[0].data);
    switch (types[k]) {
      case _NNS_FLOAT64: {
        double v;
        std::memcpy(&v, o, 8);
        EXPECT_EQ(v, 2.0);
        break;
      }
      case _NNS_FLOAT32: {
        float v;
        std::memcpy(&v, o, 4);
        EXPECT_EQ(v, 2.0f);
        break;
      }
      case _NNS_FLOAT16: {
        uint16_t v;
        std::memcpy(&v, o, 2);
        EXPECT_EQ(v, 0x4000);
        break;
      }
      default:
        EXPECT_EQ(o[0], 2) << k;
    }
    f.release(outs);
  }
}

TEST(FilterPython3, CustomSplitOnSpaces) {
  REQUIRE_BACKEND();
  Filter f(script("args.py"), "abc  de f");
  ASSERT_EQ(f.rc, 0) << f.error();
  ASSERT_EQ(f.model_info(), 0) << f.error();
  EXPECT_EQ(dims_of(f.out->tensors[0]), (std::vector<uint32_t>{3}));
  uint8_t x = 0;
  std::vector<GstTensorMemory> ins{{&x, 1}}, outs(1);
  ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
  const uint8_t *o = static_cast<const uint8_t *>(outs[0].data);
  EXPECT_EQ(o[0], 3);
  EXPECT_EQ(o[1], 2);
  EXPECT_EQ(o[2], 1);
  f.release(outs);
}

TEST(FilterPython3, TwoFiltersOnOneScriptHaveSeparateModules) {
  REQUIRE_BACKEND();
  Filter a(script("counter.py")), b(script("counter.py"));
  ASSERT_EQ(a.rc, 0) << a.error();
  ASSERT_EQ(b.rc, 0) << b.error();
  uint8_t x = 0;
  std::vector<GstTensorMemory> ins{{&x, 1}}, outs(1);
  int64_t last = 0;
  for (int i = 0; i < 3; i++) {
    ASSERT_EQ(a.invoke(ins, outs), 0) << a.error();
    last = *static_cast<const int64_t *>(outs[0].data);
    a.release(outs);
  }
  EXPECT_EQ(last, 3);
  ASSERT_EQ(b.invoke(ins, outs), 0) << b.error();
  EXPECT_EQ(*static_cast<const int64_t *>(outs[0].data), 1);
  b.release(outs);
}

TEST(FilterPython3, Reload) {
  REQUIRE_BACKEND();
  Filter f(script("passthrough.py"));
  ASSERT_EQ(f.rc, 0) << f.error();
  std::string path = script("add.py");
  const char *models[] = {path.c_str()};
  nns_filter_props p{};
  p.model_files = models;
  p.num_models = 1;
  auto none = make_desc({});
  p.input = p.output = none.get();
  ASSERT_EQ(backend()->reload(f.priv, &p, f.err, sizeof f.err), 0) << f.error();
  ASSERT_EQ(f.model_info(), 0) << f.error();
  EXPECT_EQ(f.in->num_tensors, 2u);
  // A broken script does not replace the working one.
  std::string bad = script("bad_syntax.py");
  models[0] = bad.c_str();
  EXPECT_NE(backend()->reload(f.priv, &p, f.err, sizeof f.err), 0);
  EXPECT_NE(f.error().find("SyntaxError"), std::string::npos) << f.error();
  float a[4] = {1, 2, 3, 4};
  std::vector<GstTensorMemory> ins{{a, sizeof a}, {a, sizeof a}}, outs(2);
  ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
  EXPECT_EQ(static_cast<const float *>(outs[1].data)[3], 16.0f);
  f.release(outs);
}

TEST(FilterPython3, InvokeFromOtherThreads) {
  REQUIRE_BACKEND();
  Filter f(script("probe.py"));
  ASSERT_EQ(f.rc, 0) << f.error();
  uint8_t a[16] = {};
  float b[4] = {};
  std::vector<GstTensorMemory> ins{{a, sizeof a}, {b, sizeof b}};
  std::vector<std::vector<GstTensorMemory>> kept;
  std::vector<uint64_t> tids;
  for (int t = 0; t < 3; t++) {
    std::thread th([&] {
      std::vector<GstTensorMemory> outs(1);
      ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
      tids.push_back(static_cast<const uint64_t *>(outs[0].data)[6]);
      kept.push_back(outs);
    });
    th.join();
  }
  // Outputs are released from yet another thread, as a sink thread would.
  std::thread rel([&] {
    for (auto &o : kept) f.release(o);
  });
  rel.join();
  ASSERT_EQ(tids.size(), 3u);
}

TEST(FilterPython3, ConcurrentReleaseWhileInvoking) {
  REQUIRE_BACKEND();
  Filter f(script("output_cases.py"), "kept");
  ASSERT_EQ(f.rc, 0) << f.error();
  uint8_t in[8] = {10, 11, 12, 13, 14, 15, 16, 17};
  std::vector<GstTensorMemory> ins{{in, 8}};
  std::vector<std::vector<GstTensorMemory>> queue;
  std::mutex m;
  bool done = false;
  std::thread rel([&] {
    for (;;) {
      std::vector<GstTensorMemory> o;
      {
        std::lock_guard<std::mutex> l(m);
        if (queue.empty()) {
          if (done) return;
        } else {
          o = queue.back();
          queue.pop_back();
        }
      }
      if (!o.empty())
        f.release(o);
      else
        std::this_thread::yield();
    }
  });
  for (int i = 0; i < 300; i++) {
    std::vector<GstTensorMemory> outs(2);
    ASSERT_EQ(f.invoke(ins, outs), 0) << f.error();
    ASSERT_EQ(static_cast<const uint8_t *>(outs[0].data)[3], 3);
    ASSERT_EQ(static_cast<const uint8_t *>(outs[1].data)[0], 14);
    std::lock_guard<std::mutex> l(m);
    queue.push_back(outs);
  }
  {
    std::lock_guard<std::mutex> l(m);
    done = true;
  }
  rel.join();
}

TEST(FilterPython3, HostSignalHandlersUntouched) {
  REQUIRE_BACKEND();
  struct sigaction before {
  }, after{};
  sigaction(SIGINT, nullptr, &before);
  Filter f(script("passthrough.py"));  // initializes Python in this process if nothing did yet
  ASSERT_EQ(f.rc, 0) << f.error();
  sigaction(SIGINT, nullptr, &after);
  EXPECT_EQ(after.sa_handler, before.sa_handler);
}

TEST(FilterPython3, InvokeDynamicShapesFromArrays) {
  REQUIRE_BACKEND();
  EXPECT_TRUE(backend()->flags & NNS_FILTER_FLAG_DYNAMIC);
  Filter f(script("dynamic.py"));
  ASSERT_EQ(f.rc, 0) << f.error();
  for (auto [w, h] : {std::pair<uint32_t, uint32_t>{2, 3}, {4, 1}}) {
    // Input w:h float32 (numpy shape (h, w)), values 0, 1, 2, ...
    std::vector<float> x(w * h);
    for (size_t i = 0; i < x.size(); i++) x[i] = static_cast<float>(i);
    auto in = make_desc({{{w, h}, _NNS_FLOAT32}});
    auto out = make_desc({});
    std::vector<GstTensorMemory> ins{{x.data(), x.size() * sizeof(float)}}, outs(2);
    ASSERT_EQ(backend()->invoke_dynamic(f.priv, in.get(), ins.data(), out.get(), outs.data(), f.err,
                                        sizeof f.err),
              0)
        << f.error();
    ASSERT_EQ(out->num_tensors, 2u);
    EXPECT_EQ(out->tensors[0].type, static_cast<uint32_t>(_NNS_FLOAT32));
    EXPECT_EQ(dims_of(out->tensors[0]), (std::vector<uint32_t>{h, w}));  // transposed
    EXPECT_EQ(out->tensors[1].type, static_cast<uint32_t>(_NNS_INT32));
    EXPECT_EQ(dims_of(out->tensors[1]), (std::vector<uint32_t>{2}));
    ASSERT_EQ(outs[0].size, x.size() * sizeof(float));
    const float *t = static_cast<const float *>(outs[0].data);
    for (uint32_t r = 0; r < w; r++)  // transposed: w rows of h
      for (uint32_t c = 0; c < h; c++) EXPECT_EQ(t[r * h + c], 2 * x[c * w + r]);
    const int32_t *shape = static_cast<const int32_t *>(outs[1].data);
    EXPECT_EQ(shape[0], static_cast<int32_t>(h));  // the script saw the numpy shape (h, w)
    EXPECT_EQ(shape[1], static_cast<int32_t>(w));
    f.release(outs);
  }
}

TEST(FilterPython3, InvokeDynamicBadOutputs_n) {
  REQUIRE_BACKEND();
  for (auto [custom, want] : {std::pair<const char *, const char *>{
                                  "bad_type", "invoke() output 0 type is numpy type '<U4'"},
                              {"empty", "invoke() output 0 has no elements"}}) {
    Filter f(script("dynamic.py"), custom);
    ASSERT_EQ(f.rc, 0) << f.error();
    float x[2] = {1, 2};
    auto in = make_desc({{{2}, _NNS_FLOAT32}});
    auto out = make_desc({});
    std::vector<GstTensorMemory> ins{{x, sizeof x}}, outs(2);
    EXPECT_NE(backend()->invoke_dynamic(f.priv, in.get(), ins.data(), out.get(), outs.data(), f.err,
                                        sizeof f.err),
              0);
    EXPECT_NE(f.error().find(want), std::string::npos) << f.error();
    EXPECT_EQ(outs[0].data, nullptr);
  }
}

}  // namespace
