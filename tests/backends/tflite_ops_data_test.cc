// SPDX-License-Identifier: LGPL-2.1-only
// One-op models for the tflite back end's data-movement, reduction and log-softmax operators
// (SPLIT, SPLIT_V, PACK, UNPACK, GATHER_ND, TILE, SLICE, MIRROR_PAD, SUM, REDUCE_MAX,
// REDUCE_MIN, REDUCE_PROD, LOG_SOFTMAX), each against a scalar reference written here: float
// within 1e-5 relative; the same op on uint8 and int8 tensors within one quantization step of
// the reference on the dequantized input (data movement with equal input and output
// quantization must be exact).
#include <functional>

#include "backends/tflite_op_util.h"

namespace nns::test {
namespace {

using namespace tflite_ops;
using B = tflite::BuiltinOperator;

// A tensor type with its quantization (scale 0: float32).
struct Ty {
  TT type = TT::TensorType_FLOAT32;
  float scale = 0;
  int zp = 0;
  bool quant() const { return scale != 0; }
  int lo() const { return type == TT::TensorType_INT8 ? -128 : 0; }
  int hi() const { return type == TT::TensorType_INT8 ? 127 : 255; }
};
const Ty kF32{};

int tensor(TfliteBuilder &t, const std::string &name, const Ty &ty,
           const std::vector<int32_t> &shape) {
  if (!ty.quant()) return t.tensor(name, ty.type, shape);
  return t.tensor(name, ty.type, shape, nullptr, 0, {ty.scale}, {ty.zp});
}
int ints(TfliteBuilder &t, const std::string &name, const std::vector<int32_t> &shape,
         const std::vector<int32_t> &v) {
  return t.constant(name, TT::TensorType_INT32, shape, v);
}

// Builds the one-op model for input type `in` and output type `out`.
using Make = std::function<std::vector<uint8_t>(const Ty &in, const Ty &out)>;
using Ref = std::function<std::vector<std::vector<float>>(const std::vector<float> &)>;

std::vector<uint8_t> quantize(const std::vector<float> &x, const Ty &ty) {
  std::vector<uint8_t> q(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    float v = std::clamp(std::round(x[i] / ty.scale) + static_cast<float>(ty.zp),
                         static_cast<float>(ty.lo()), static_cast<float>(ty.hi()));
    q[i] = static_cast<uint8_t>(static_cast<int>(v));
  }
  return q;
}
std::vector<float> dequantize(const std::vector<uint8_t> &q, const Ty &ty) {
  std::vector<float> x(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) {
    int v = ty.type == TT::TensorType_INT8 ? static_cast<int8_t>(q[i]) : q[i];
    x[i] = ty.scale * static_cast<float>(v - ty.zp);
  }
  return x;
}

// Float run, then (when `in_q`/`out_q` are given) the uint8 and int8 variants.
void check(const Make &make, const Ref &ref, const std::vector<float> &x, float in_scale = 0,
           float out_scale = 0, int max_steps = 1, int u8_out_zp = 128) {
  {
    SCOPED_TRACE("float32");
    auto want = ref(x);
    auto got = run(make(kF32, kF32), {bytes_of(x)});
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t k = 0; k < want.size(); ++k) expect_near(values_of<float>(got[k]), want[k]);
  }
  if (in_scale == 0) return;
  for (TT type : {TT::TensorType_UINT8, TT::TensorType_INT8}) {
    SCOPED_TRACE(tflite::EnumNameTensorType(type));
    const bool s = type == TT::TensorType_INT8;
    Ty in{type, in_scale, s ? -3 : 125};
    Ty out{type, out_scale, s ? u8_out_zp - 128 : u8_out_zp};
    auto xq = quantize(x, in);
    auto want = ref(dequantize(xq, in));
    auto got = run(make(in, out), {xq});
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t k = 0; k < want.size(); ++k) {
      auto wq = quantize(want[k], out);
      ASSERT_EQ(got[k].size(), wq.size()) << "output " << k;
      for (std::size_t i = 0; i < wq.size(); ++i) {
        int g = s ? static_cast<int8_t>(got[k][i]) : got[k][i];
        int w = s ? static_cast<int8_t>(wq[i]) : wq[i];
        EXPECT_LE(std::abs(g - w), max_steps) << "output " << k << " at " << i;
      }
    }
  }
}

// Row-major helpers over a shape.
std::vector<int> strides_of(const std::vector<int> &shape) {
  std::vector<int> s(shape.size(), 1);
  for (int i = static_cast<int>(shape.size()) - 2; i >= 0; --i) s[i] = s[i + 1] * shape[i + 1];
  return s;
}
int count(const std::vector<int> &shape) {
  int n = 1;
  for (int d : shape) n *= d;
  return n;
}
std::vector<int> index_of(int flat, const std::vector<int> &shape) {
  std::vector<int> idx(shape.size());
  for (int i = static_cast<int>(shape.size()) - 1; i >= 0; --i) {
    idx[i] = flat % shape[i];
    flat /= shape[i];
  }
  return idx;
}
int flat_of(const std::vector<int> &idx, const std::vector<int> &shape) {
  auto s = strides_of(shape);
  int f = 0;
  for (std::size_t i = 0; i < idx.size(); ++i) f += idx[i] * s[i];
  return f;
}

// out[i] = x[map(i)] over an output shape.
std::vector<float> gather_by(const std::vector<float> &x, const std::vector<int> &in_shape,
                             const std::vector<int> &out_shape,
                             const std::function<std::vector<int>(std::vector<int>)> &map) {
  std::vector<float> y(static_cast<std::size_t>(count(out_shape)));
  for (int i = 0; i < count(out_shape); ++i)
    y[i] = x[flat_of(map(index_of(i, out_shape)), in_shape)];
  return y;
}

const std::vector<int> kShape{2, 3, 4};
std::vector<int32_t> i32(const std::vector<int> &v) {
  return {v.begin(), v.end()};
}

TEST(TfliteOpsData, Split) {
  REQUIRE_TFLITE();
  // [2,3,4] split in 2 along axis 2 (given as -1).
  auto make = [](const Ty &in, const Ty &out) {
    TfliteBuilder t;
    int ax = ints(t, "axis", {}, {-1});
    int xi = tensor(t, "x", in, {2, 3, 4});
    int a = tensor(t, "a", out, {2, 3, 2}), b = tensor(t, "b", out, {2, 3, 2});
    t.op(B::BuiltinOperator_SPLIT, {ax, xi}, {a, b}, tflite::BuiltinOptions_SplitOptions,
         tflite::CreateSplitOptions(t.fb(), 2).Union());
    return t.finish({xi}, {a, b});
  };
  auto ref = [](const std::vector<float> &x) {
    std::vector<std::vector<float>> r;
    for (int part = 0; part < 2; ++part)
      r.push_back(gather_by(x, kShape, {2, 3, 2}, [&](std::vector<int> i) {
        i[2] += 2 * part;
        return i;
      }));
    return r;
  };
  check(make, ref, ramp(24), 0.05f, 0.05f, 0);
}

TEST(TfliteOpsData, SplitV) {
  REQUIRE_TFLITE();
  // [2,3,4] split along axis 1 into sizes 1 and 2.
  auto make = [](const Ty &in, const Ty &out) {
    TfliteBuilder t;
    int xi = tensor(t, "x", in, {2, 3, 4});
    int sz = ints(t, "sizes", {2}, {1, 2}), ax = ints(t, "axis", {}, {1});
    int a = tensor(t, "a", out, {2, 1, 4}), b = tensor(t, "b", out, {2, 2, 4});
    t.op(B::BuiltinOperator_SPLIT_V, {xi, sz, ax}, {a, b}, tflite::BuiltinOptions_SplitVOptions,
         tflite::CreateSplitVOptions(t.fb(), 2).Union());
    return t.finish({xi}, {a, b});
  };
  auto ref = [](const std::vector<float> &x) {
    return std::vector<std::vector<float>>{
        gather_by(x, kShape, {2, 1, 4}, [](std::vector<int> i) { return i; }),
        gather_by(x, kShape, {2, 2, 4}, [](std::vector<int> i) {
          i[1] += 1;
          return i;
        })};
  };
  check(make, ref, ramp(24), 0.05f, 0.05f, 0);
}

TEST(TfliteOpsData, PackAxis1) {
  REQUIRE_TFLITE();
  // Two [3,4] inputs packed on axis 1 -> [3,2,4]; the test feeds one input twice shifted.
  auto make = [](const Ty &in, const Ty &out) {
    TfliteBuilder t;
    int xi = tensor(t, "x", in, {3, 4});
    std::vector<float> c = ramp(12, 0.03f, 0.2f);
    int ci = in.quant() ? t.constant("c", in.type, {3, 4}, quantize(c, in), {in.scale}, {in.zp})
                        : t.constant("c", TT::TensorType_FLOAT32, {3, 4}, c);
    int yi = tensor(t, "y", out, {3, 2, 4});
    t.op(B::BuiltinOperator_PACK, {xi, ci}, {yi}, tflite::BuiltinOptions_PackOptions,
         tflite::CreatePackOptions(t.fb(), 2, 1).Union());
    return t.finish({xi}, {yi});
  };
  auto ref = [](const std::vector<float> &x) {
    std::vector<float> c = ramp(12, 0.03f, 0.2f), y;
    for (int r = 0; r < 3; ++r) {
      y.insert(y.end(), x.begin() + 4 * r, x.begin() + 4 * r + 4);
      y.insert(y.end(), c.begin() + 4 * r, c.begin() + 4 * r + 4);
    }
    return std::vector<std::vector<float>>{y};
  };
  // The constant is quantized in the model, so the quantized reference uses its stored values.
  check(make, ref, ramp(12), 0.05f, 0.05f, 1);
}

TEST(TfliteOpsData, UnpackAxis1) {
  REQUIRE_TFLITE();
  auto make = [](const Ty &in, const Ty &out) {
    TfliteBuilder t;
    int xi = tensor(t, "x", in, {2, 3, 4});
    std::vector<int> outs;
    for (int k = 0; k < 3; ++k) outs.push_back(tensor(t, "y" + std::to_string(k), out, {2, 4}));
    t.op(B::BuiltinOperator_UNPACK, {xi}, outs, tflite::BuiltinOptions_UnpackOptions,
         tflite::CreateUnpackOptions(t.fb(), 3, 1).Union());
    return t.finish({xi}, outs);
  };
  auto ref = [](const std::vector<float> &x) {
    std::vector<std::vector<float>> r;
    for (int k = 0; k < 3; ++k)
      r.push_back(gather_by(x, kShape, {2, 4}, [&](std::vector<int> i) {
        return std::vector<int>{i[0], k, i[1]};
      }));
    return r;
  };
  check(make, ref, ramp(24), 0.05f, 0.05f, 0);
}

TEST(TfliteOpsData, GatherNd) {
  REQUIRE_TFLITE();
  // params [2,3,4], indices [3,2] -> [3,4] rows x[i0][i1][:].
  const std::vector<int> idx{1, 2, 0, 0, 1, 0};
  auto make = [&](const Ty &in, const Ty &out) {
    TfliteBuilder t;
    int xi = tensor(t, "x", in, {2, 3, 4});
    int ii = ints(t, "idx", {3, 2}, i32(idx));
    int yi = tensor(t, "y", out, {3, 4});
    t.op(B::BuiltinOperator_GATHER_ND, {xi, ii}, {yi});
    return t.finish({xi}, {yi});
  };
  auto ref = [&](const std::vector<float> &x) {
    return std::vector<std::vector<float>>{gather_by(x, kShape, {3, 4}, [&](std::vector<int> i) {
      return std::vector<int>{idx[2 * i[0]], idx[2 * i[0] + 1], i[1]};
    })};
  };
  check(make, ref, ramp(24), 0.05f, 0.05f, 0);
}

TEST(TfliteOpsData, Tile) {
  REQUIRE_TFLITE();
  auto make = [](const Ty &in, const Ty &out) {
    TfliteBuilder t;
    int xi = tensor(t, "x", in, {2, 3, 4});
    int mi = ints(t, "m", {3}, {2, 1, 3});
    int yi = tensor(t, "y", out, {4, 3, 12});
    t.op(B::BuiltinOperator_TILE, {xi, mi}, {yi});
    return t.finish({xi}, {yi});
  };
  auto ref = [](const std::vector<float> &x) {
    return std::vector<std::vector<float>>{gather_by(x, kShape, {4, 3, 12}, [](std::vector<int> i) {
      return std::vector<int>{i[0] % 2, i[1], i[2] % 4};
    })};
  };
  check(make, ref, ramp(24), 0.05f, 0.05f, 0);
}

TEST(TfliteOpsData, SliceWithMinusOneSize) {
  REQUIRE_TFLITE();
  // begin [1,1,0], size [1,-1,3] -> [1,2,3].
  auto make = [](const Ty &in, const Ty &out) {
    TfliteBuilder t;
    int xi = tensor(t, "x", in, {2, 3, 4});
    int bi = ints(t, "b", {3}, {1, 1, 0}), si = ints(t, "s", {3}, {1, -1, 3});
    int yi = tensor(t, "y", out, {1, 2, 3});
    t.op(B::BuiltinOperator_SLICE, {xi, bi, si}, {yi});
    return t.finish({xi}, {yi});
  };
  auto ref = [](const std::vector<float> &x) {
    return std::vector<std::vector<float>>{gather_by(x, kShape, {1, 2, 3}, [](std::vector<int> i) {
      return std::vector<int>{i[0] + 1, i[1] + 1, i[2]};
    })};
  };
  check(make, ref, ramp(24), 0.05f, 0.05f, 0);
}

// MIRROR_PAD on [2,3,4] with paddings [[1,1],[2,0],[0,3]]: REFLECT excludes the edge,
// SYMMETRIC repeats it.
void mirror_pad(int mode) {
  const std::vector<int> pb{1, 2, 0}, pa{1, 0, 3}, out_shape{4, 5, 7};
  auto make = [&](const Ty &in, const Ty &out) {
    TfliteBuilder t;
    int xi = tensor(t, "x", in, {2, 3, 4});
    int pi = ints(t, "p", {3, 2}, {pb[0], pa[0], pb[1], pa[1], pb[2], pa[2]});
    int yi = tensor(t, "y", out, i32(out_shape));
    t.op(B::BuiltinOperator_MIRROR_PAD, {xi, pi}, {yi}, tflite::BuiltinOptions_MirrorPadOptions,
         tflite::CreateMirrorPadOptions(t.fb(), static_cast<int8_t>(mode)).Union());
    return t.finish({xi}, {yi});
  };
  auto ref = [&](const std::vector<float> &x) {
    return std::vector<std::vector<float>>{gather_by(x, kShape, out_shape, [&](std::vector<int> i) {
      for (int a = 0; a < 3; ++a) {
        int j = i[a] - pb[a], n = kShape[a];
        if (j < 0) j = mode == 0 ? -j : -j - 1;
        if (j >= n) j = mode == 0 ? 2 * n - 2 - j : 2 * n - 1 - j;
        i[a] = j;
      }
      return i;
    })};
  };
  check(make, ref, ramp(24), 0.05f, 0.05f, 0);
}
TEST(TfliteOpsData, MirrorPadReflect) {
  REQUIRE_TFLITE();
  mirror_pad(0);
}
TEST(TfliteOpsData, MirrorPadSymmetric) {
  REQUIRE_TFLITE();
  mirror_pad(1);
}

// SYMMETRIC indices come from the input's shape: another input shape (set_input_info) gets its
// own. [1,3] declared, run as [1,5] with paddings [[0,0],[2,1]] -> [1,8].
TEST(TfliteOpsData, MirrorPadSymmetricFollowsTheInputShape) {
  REQUIRE_TFLITE();
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, 3});
  int pi = ints(t, "p", {2, 2}, {0, 0, 2, 1});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, 6});
  t.op(B::BuiltinOperator_MIRROR_PAD, {xi, pi}, {yi}, tflite::BuiltinOptions_MirrorPadOptions,
       tflite::CreateMirrorPadOptions(t.fb(), 1).Union());
  TempModel f(t.finish({xi}, {yi}));
  Props p;
  p.models = {f.path()};
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns_tensors_desc out{};
  ASSERT_EQ(inst.set_input_info(tensors_desc({tensor_desc(_NNS_FLOAT32, {5, 1})}), out), 0)
      << inst.error();
  ASSERT_EQ(out.tensors[0].dims[0], 8u);
  std::vector<float> x{1, 2, 3, 4, 5}, y(8);
  std::vector<GstTensorMemory> in{{x.data(), 20}}, o{{y.data(), 32}};
  ASSERT_EQ(inst.invoke(in, o), 0) << inst.error();
  EXPECT_EQ(y, (std::vector<float>{2, 1, 1, 2, 3, 4, 5, 5}));
}

// Reductions of [2,3,4] over axes {0,2} (keep_dims false -> [3]) and {1} (keep_dims true ->
// [2,1,4]).
void reduce(B code, float init, const std::function<float(float, float)> &f, float in_scale,
            float out_scale) {
  for (bool keep : {false, true}) {
    SCOPED_TRACE(keep ? "keep_dims" : "no keep_dims");
    const std::vector<int32_t> axes = keep ? std::vector<int32_t>{1} : std::vector<int32_t>{0, 2};
    const std::vector<int> out_shape = keep ? std::vector<int>{2, 1, 4} : std::vector<int>{3};
    auto make = [&](const Ty &in, const Ty &out) {
      TfliteBuilder t;
      int xi = tensor(t, "x", in, {2, 3, 4});
      int ai = ints(t, "axes", {static_cast<int32_t>(axes.size())}, axes);
      int yi = tensor(t, "y", out, i32(out_shape));
      t.op(code, {xi, ai}, {yi}, tflite::BuiltinOptions_ReducerOptions,
           tflite::CreateReducerOptions(t.fb(), keep).Union());
      return t.finish({xi}, {yi});
    };
    auto ref = [&](const std::vector<float> &x) {
      std::vector<float> y(static_cast<std::size_t>(count(out_shape)), init);
      for (int i = 0; i < 24; ++i) {
        auto idx = index_of(i, kShape);
        int o = keep ? flat_of({idx[0], 0, idx[2]}, out_shape) : idx[1];
        y[o] = f(y[o], x[i]);
      }
      return std::vector<std::vector<float>>{y};
    };
    check(make, ref, ramp(24, 0.1f, -0.9f), in_scale, out_scale, 1);
  }
}
TEST(TfliteOpsData, Sum) {
  REQUIRE_TFLITE();
  reduce(
      B::BuiltinOperator_SUM, 0.f, [](float a, float b) { return a + b; }, 0.02f, 0.1f);
}
TEST(TfliteOpsData, ReduceMax) {
  REQUIRE_TFLITE();
  reduce(
      B::BuiltinOperator_REDUCE_MAX, -1e30f, [](float a, float b) { return std::max(a, b); }, 0.02f,
      0.02f);
}
TEST(TfliteOpsData, ReduceMin) {
  REQUIRE_TFLITE();
  reduce(
      B::BuiltinOperator_REDUCE_MIN, 1e30f, [](float a, float b) { return std::min(a, b); }, 0.02f,
      0.02f);
}
TEST(TfliteOpsData, ReduceProd) {
  REQUIRE_TFLITE();
  reduce(
      B::BuiltinOperator_REDUCE_PROD, 1.f, [](float a, float b) { return a * b; }, 0.02f, 0.002f);
}

// LOG_SOFTMAX on the last axis; TFLite's quantized kernel requires output scale 16/256 with
// zero point 255 (uint8) / 127 (int8).
TEST(TfliteOpsData, LogSoftmax) {
  REQUIRE_TFLITE();
  auto make = [](const Ty &in, const Ty &out) {
    TfliteBuilder t;
    int xi = tensor(t, "x", in, {2, 3, 4});
    int yi = tensor(t, "y", out, {2, 3, 4});
    t.op(B::BuiltinOperator_LOG_SOFTMAX, {xi}, {yi}, tflite::BuiltinOptions_LogSoftmaxOptions,
         tflite::CreateLogSoftmaxOptions(t.fb()).Union());
    return t.finish({xi}, {yi});
  };
  auto ref = [](const std::vector<float> &x) {
    std::vector<float> y(x.size());
    for (std::size_t r = 0; r < x.size() / 4; ++r) {
      float m = *std::max_element(x.begin() + 4 * r, x.begin() + 4 * r + 4), s = 0;
      for (int i = 0; i < 4; ++i) s += std::exp(x[4 * r + i] - m);
      for (int i = 0; i < 4; ++i) y[4 * r + i] = x[4 * r + i] - m - std::log(s);
    }
    return std::vector<std::vector<float>>{y};
  };
  check(make, ref, ramp(24, 0.3f, -2.f), 0.05f, 16.f / 256.f, 1, 255);
}

}  // namespace
}  // namespace nns::test
