// SPDX-License-Identifier: LGPL-2.1-only
// A real recurrent model through a pipeline cycle: the hidden state of a GRU cell goes
//   tensor_reposrc -> tensor_filter (GRU cell) -> tee -> tensor_reposink -> (slot) -> ...
// and every step's output must match torch.nn.GRUCell run step by step (tests/data/flow/
// gru_cell.py generates the weights, the input sequence and the reference at build time).
//
// Two versions:
//  - BackEnd/*: the full RNN pipeline. x_t comes from an appsrc, h_t from tensor_reposrc;
//    tensor_mux sync-mode=nosync pairs them; tensor_filter runs the torch-exported cell
//    (framework=pytorch with gru_cell.pt, framework=onnxruntime with gru_cell.onnx); the new
//    state goes to tensor_reposink and to the test. Skipped when the back end is not built.
//  - CustomEasy: the cell is a custom-easy filter computing torch's GRUCell equations in C++
//    with torch's weights, taking x_t from the sequence itself (no mux): the repository loop
//    alone.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "elements/flow_harness.h"
#include "tensor_filter_custom_easy.h"

namespace {

using nns::test::AppPipeline;

struct GruData {
  int I = 0, H = 0, T = 0;
  std::vector<float> w_ih, w_hh, b_ih, b_hh, x, ref;
  int step = 0;  // invocations so far (= index of x_t)
};

bool load(const std::string &path, GruData *d) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return false;
  int32_t dims[3];
  f.read(reinterpret_cast<char *>(dims), sizeof dims);
  d->I = dims[0];
  d->H = dims[1];
  d->T = dims[2];
  auto rd = [&](std::vector<float> *v, std::size_t n) {
    v->resize(n);
    f.read(reinterpret_cast<char *>(v->data()), n * sizeof(float));
  };
  rd(&d->w_ih, 3 * d->H * d->I);
  rd(&d->w_hh, 3 * d->H * d->H);
  rd(&d->b_ih, 3 * d->H);
  rd(&d->b_hh, 3 * d->H);
  rd(&d->x, d->T * d->I);
  rd(&d->ref, d->T * d->H);
  return static_cast<bool>(f);
}

float sigmoid(float v) {
  return 1.0f / (1.0f + std::exp(-v));
}

// torch.nn.GRUCell: gates r, z, n (rows 0..H-1, H..2H-1, 2H..3H-1 of the weights).
int gru_invoke(void *data, const GstTensorFilterProperties *, const GstTensorMemory *input,
               GstTensorMemory *output) {
  auto *d = static_cast<GruData *>(data);
  if (d->step >= d->T) return -1;
  const float *h = static_cast<const float *>(input[0].data);
  const float *x = d->x.data() + d->step * d->I;
  float *out = static_cast<float *>(output[0].data);
  const int H = d->H, I = d->I;
  std::vector<float> gi(3 * H), gh(3 * H);
  for (int r = 0; r < 3 * H; ++r) {
    float a = d->b_ih[r], b = d->b_hh[r];
    for (int k = 0; k < I; ++k) a += d->w_ih[r * I + k] * x[k];
    for (int k = 0; k < H; ++k) b += d->w_hh[r * H + k] * h[k];
    gi[r] = a;
    gh[r] = b;
  }
  for (int j = 0; j < H; ++j) {
    float r = sigmoid(gi[j] + gh[j]);
    float z = sigmoid(gi[H + j] + gh[H + j]);
    float n = std::tanh(gi[2 * H + j] + r * gh[2 * H + j]);
    out[j] = (1.0f - z) * n + z * h[j];
  }
  ++d->step;
  return 0;
}

TEST(TensorRepoGru, RecurrentStateThroughTheRepositoryMatchesTorch) {
  GruData d;
  std::string path = std::string(NNS_FLOW_DATA_DIR) + "/gru_cell.bin";
  if (!load(path, &d)) NNS_SKIP_UNLESS_CI(path << " missing (python3-torch not installed?)");
  GstTensorsInfo info{};
  info.num_tensors = 1;
  info.info[0].type = _NNS_FLOAT32;
  info.info[0].dimension[0] = static_cast<uint32_t>(d.H);
  info.info[0].dimension[1] = 1;
  info.format = _NNS_TENSOR_FORMAT_STATIC;
  ASSERT_EQ(NNS_custom_easy_register("flow_gru_cell", gru_invoke, &d, &info, &info), 0);
  std::string caps = "other/tensors,format=static,num_tensors=1,dimensions=(string)" +
                     std::to_string(d.H) + ":1,types=(string)float32,framerate=(fraction)0/1";
  // reposrc emits h_0 (zeros) .. h_{T-1}; the filter turns each into the next state.
  {
    AppPipeline p("tensor_reposrc slot-index=61 num-buffers=" + std::to_string(d.T) + " caps=\"" +
                  caps +
                  "\" ! tensor_filter framework=custom-easy model=flow_gru_cell ! tee name=t "
                  "t. ! queue ! tensor_reposink slot-index=61 t. ! queue ! appsink name=out");
    auto r = p.run(20);
    ASSERT_TRUE(r.eos) << r.error_text << (r.timed_out ? " (timed out: deadlock?)" : "");
    auto out = p.frames("out");
    ASSERT_EQ(out.size(), static_cast<std::size_t>(d.T));
    double max_err = 0;
    for (int t = 0; t < d.T; ++t) {
      auto h = nns::test::values_of<float>(out[t].mems.at(0));
      ASSERT_EQ(h.size(), static_cast<std::size_t>(d.H));
      for (int j = 0; j < d.H; ++j) {
        double e = std::fabs(h[j] - d.ref[t * d.H + j]);
        max_err = std::max(max_err, e);
        EXPECT_NEAR(h[j], d.ref[t * d.H + j], 1e-5) << "step " << t + 1 << " unit " << j;
      }
    }
    EXPECT_EQ(d.step, d.T);
    RecordProperty("max_abs_error", std::to_string(max_err));
  }
  EXPECT_EQ(NNS_custom_easy_unregister("flow_gru_cell"), 0);
}

// The full RNN pipeline with a real back end.
struct BackEnd {
  const char *framework, *model;
  bool needs_shapes;  // TorchScript records no shapes: give input=/output=
};

void run_backend_cycle(const BackEnd &be) {
  GruData d;
  std::string dir = NNS_FLOW_DATA_DIR;
  if (!load(dir + "/gru_cell.bin", &d))
    NNS_SKIP_UNLESS_CI("gru_cell.bin missing (no python3-torch?)");
  std::string model = dir + "/" + be.model;
  if (!std::ifstream(model)) NNS_SKIP_UNLESS_CI(model << " missing");
  // The build tree's back ends (nnstreamer.ini of the build tree points tensor_filter there).
  std::string lib = std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_" +
                    be.framework + ".so";
  if (!std::ifstream(lib)) GTEST_SKIP() << lib << " not built";
  auto caps = [](int n) {
    return "other/tensors,format=static,num_tensors=1,dimensions=(string)" + std::to_string(n) +
           ":1,types=(string)float32,framerate=(fraction)0/1";
  };
  std::string props;
  if (be.needs_shapes)
    props = "input=" + std::to_string(d.I) + ":1," + std::to_string(d.H) +
            ":1 inputtype=float32,float32 output=" + std::to_string(d.H) + ":1 outputtype=float32";
  AppPipeline p(
      "appsrc name=x ! mux.sink_0 "
      "tensor_reposrc slot-index=71 caps=\"" +
      caps(d.H) +
      "\" ! mux.sink_1 "
      "tensor_mux name=mux sync-mode=nosync ! "
      "tensor_filter framework=" +
      std::string(be.framework) + " model=" + model + " " + props +
      " ! tee name=t "
      "t. ! queue ! tensor_reposink slot-index=71 "
      "t. ! queue ! appsink name=out");
  ASSERT_NE(p.pipeline(), nullptr);
  p.set_caps("x", caps(d.I));
  for (int t = 0; t < d.T; ++t) {
    std::vector<float> x(d.x.begin() + t * d.I, d.x.begin() + (t + 1) * d.I);
    p.push("x",
           nns::test::Frame({nns::test::bytes_of(x)}, static_cast<GstClockTime>(t) * GST_MSECOND));
  }
  p.eos("x");
  auto r = p.run(30);
  ASSERT_TRUE(r.eos) << r.error_text << (r.timed_out ? " (timed out: deadlock?)" : "");
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), static_cast<std::size_t>(d.T));
  for (int t = 0; t < d.T; ++t) {
    auto h = nns::test::values_of<float>(out[t].mems.at(0));
    ASSERT_EQ(h.size(), static_cast<std::size_t>(d.H));
    for (int j = 0; j < d.H; ++j)
      EXPECT_NEAR(h[j], d.ref[t * d.H + j], 1e-5) << be.framework << " step " << t + 1;
  }
}

TEST(TensorRepoGruBackEnd, PytorchMuxFilterRepositoryCycleMatchesTorch) {
  run_backend_cycle({"pytorch", "gru_cell.pt", true});
}

TEST(TensorRepoGruBackEnd, OnnxruntimeMuxFilterRepositoryCycleMatchesTorch) {
  run_backend_cycle({"onnxruntime", "gru_cell.onnx", false});
}

}  // namespace
