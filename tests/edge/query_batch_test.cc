// SPDX-License-Identifier: LGPL-2.1-only
// tensor_query_serversrc max-batch / batch-timeout (docs/elements/tensor_query_serversrc.md):
// requests of several clients stacked into one buffer of N slots, run through a real ONNX
// Runtime model, split back by tensor_query_serversink. Models generated here with
// /usr/bin/python3 + onnx: Y = X W + B, X float32 [N,8] with N free, fixed 8, or fixed 1.
// The batching server runs in this process (its stats are read), the unbatched reference
// server in another; clients here, over loopback sockets.
#include <cmath>
#include <fstream>

#include "edge_test_util.h"
#include "support/harness.h"

using namespace edge_test;

namespace {

const char *kInCaps =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)8:1,types=(string)float32,"
    "framerate=(fraction)0/1";

const char *kGen = R"PY(
import sys, numpy as np, onnx
from onnx import helper, numpy_helper, TensorProto
out = sys.argv[1]
rng = np.random.default_rng(21)
W = rng.uniform(-1, 1, (8, 4)).astype(np.float32)
B = rng.uniform(-1, 1, (4,)).astype(np.float32)
for name, n in (("dyn", "N"), ("fixed8", 8), ("fixed1", 1)):
    X = helper.make_tensor_value_info("X", TensorProto.FLOAT, [n, 8])
    Y = helper.make_tensor_value_info("Y", TensorProto.FLOAT, [n, 4])
    g = helper.make_graph([helper.make_node("MatMul", ["X", "W"], ["XW"]),
                           helper.make_node("Add", ["XW", "B"], ["Y"])], name, [X], [Y],
                          [numpy_helper.from_array(W, "W"), numpy_helper.from_array(B, "B")])
    m = helper.make_model(g, opset_imports=[helper.make_opsetid("", 13)])
    m.ir_version = 7
    onnx.checker.check_model(m)
    onnx.save(m, out + "/" + name + ".onnx")
# Sums over the batch: Y [1,8] whatever N (an answer that cannot be split).
X = helper.make_tensor_value_info("X", TensorProto.FLOAT, ["N", 8])
Y = helper.make_tensor_value_info("Y", TensorProto.FLOAT, [1, 8])
g = helper.make_graph([helper.make_node("ReduceSum", ["X", "axes"], ["Y"], keepdims=1)], "sum0",
                      [X], [Y], [numpy_helper.from_array(np.array([0], np.int64), "axes")])
m = helper.make_model(g, opset_imports=[helper.make_opsetid("", 13)])
m.ir_version = 7
onnx.save(m, out + "/sum0.onnx")
W.tofile(out + "/W.raw")
B.tofile(out + "/B.raw")
# The same model as .tflite (tests/data/tflite_writer.py, python3-flatbuffers): x [1,8],
# FULLY_CONNECTED with weights [4,8] (out, in): a batch of 1 in the file, re-translated at N.
try:
    sys.path.insert(0, sys.argv[2])
    import tflite_writer as tw
    g = tw.Graph()
    x = g.tensor("x", (1, 8), np.float32)
    y = g.tensor("y", (1, 4), np.float32)
    g.op(tw.FULLY_CONNECTED, [x, g.const("w", W.T.copy()), g.const("b", B)], [y],
         [(0, "i8", tw.ACT_NONE)])
    g.inputs, g.outputs = [x], [y]
    open(out + "/lin.tflite", "wb").write(g.serialize("query batch test"))
    # The batch baked in: a RESHAPE to [1,4] after it (fails when re-translated at N > 1).
    g = tw.Graph()
    x = g.tensor("x", (1, 8), np.float32)
    h = g.tensor("h", (1, 4), np.float32)
    y = g.tensor("y", (1, 4), np.float32)
    g.op(tw.FULLY_CONNECTED, [x, g.const("w", W.T.copy()), g.const("b", B)], [h],
         [(0, "i8", tw.ACT_NONE)])
    g.op(tw.RESHAPE, [h], [y], [(0, "vi32", [1, 4])])
    g.inputs, g.outputs = [x], [y]
    open(out + "/fixed1.tflite", "wb").write(g.serialize("query batch test, fixed batch"))
except ImportError:
    pass
)PY";

using nns::test::read_file;

std::string g_dir;  // generated models, "" when they could not be made

// The same Y = X W + B as a TorchScript module (traced at batch 8; Linear takes any batch).
const char *kGenTorch = R"PY(
import sys, numpy as np, torch
d = sys.argv[1]
W = torch.from_numpy(np.fromfile(d + "/W.raw", dtype=np.float32).reshape(8, 4))
B = torch.from_numpy(np.fromfile(d + "/B.raw", dtype=np.float32))
class M(torch.nn.Module):
    def __init__(self):
        super().__init__()
        self.register_buffer("w", W)
        self.register_buffer("b", B)
    def forward(self, x):
        return x @ self.w + self.b
torch.jit.trace(M().eval(), torch.zeros(8, 8)).save(d + "/lin.pt")
)PY";

std::string filter(const std::string &model, int n) {
  return "tensor_filter framework=onnxruntime model=" + g_dir + "/" + model +
         ".onnx input=8:" + std::to_string(n) + " inputtype=float32 ! ";
}

std::string server_desc(uint16_t port, int max_batch, guint64 timeout_us,
                        const std::string &model) {
  const int n = model == "fixed1" ? 1 : max_batch;
  return "tensor_query_serversrc name=src host=127.0.0.1 port=" + std::to_string(port) +
         " max-batch=" + std::to_string(max_batch) +
         " batch-timeout=" + std::to_string(timeout_us) +
         " ! other/tensors,format=static,num_tensors=1,dimensions=(string)8:" + std::to_string(n) +
         ",types=float32,framerate=0/1 ! " + filter(model, n) + "tensor_query_serversink";
}

std::string client_desc(uint16_t port) {
  return "tensor_query_client dest-host=127.0.0.1 dest-port=" + std::to_string(port) +
         " host=127.0.0.1 port=0 timeout=5000 max-request=4";
}

std::vector<uint8_t> input(int client, int n) {
  std::vector<float> v(8);
  for (int j = 0; j < 8; ++j) v[j] = std::sin(static_cast<float>(client * 131 + n * 17 + j));
  std::vector<uint8_t> b(sizeof(float) * 8);
  memcpy(b.data(), v.data(), b.size());
  return b;
}

// Y = X W + B computed here.
std::vector<float> local_model(const std::vector<uint8_t> &x) {
  const auto w = read_file(g_dir + "/W.raw"), bias = read_file(g_dir + "/B.raw");
  std::vector<float> X(8), W(32), B(4), Y(4);
  memcpy(X.data(), x.data(), 32);
  memcpy(W.data(), w.data(), 128);
  memcpy(B.data(), bias.data(), 16);
  for (int o = 0; o < 4; ++o) {
    double s = B[o];
    for (int i = 0; i < 8; ++i) s += static_cast<double>(X[i]) * W[i * 4 + o];
    Y[o] = static_cast<float>(s);
  }
  return Y;
}

// A server pipeline in this process.
struct LocalServer {
  GstElement *pipe = nullptr;
  explicit LocalServer(const std::string &desc) {
    GError *err = nullptr;
    pipe = gst_parse_launch(desc.c_str(), &err);
    if (err) {
      ADD_FAILURE() << err->message;
      g_error_free(err);
    }
    gst_element_set_state(pipe, GST_STATE_PLAYING);
  }
  ~LocalServer() {
    gst_element_set_state(pipe, GST_STATE_NULL);
    gst_object_unref(pipe);
  }
  GstStructure *stats() {
    GstElement *src = gst_bin_get_by_name(GST_BIN(pipe), "src");
    GstStructure *s = nullptr;
    g_object_get(src, "stats", &s, nullptr);
    gst_object_unref(src);
    return s;
  }
  std::string error(GstClockTime t) {
    GstBus *bus = gst_element_get_bus(pipe);
    GstMessage *m = gst_bus_timed_pop_filtered(bus, t, GST_MESSAGE_ERROR);
    std::string out;
    if (m) {
      GError *e = nullptr;
      gst_message_parse_error(m, &e, nullptr);
      out = e->message;
      g_error_free(e);
      gst_message_unref(m);
    }
    gst_object_unref(bus);
    return out;
  }
};

// `clients` clients send `frames` inputs each to the server on `port`, all at once; returns
// each client's answers in order.
std::vector<std::vector<std::vector<uint8_t>>> ask(uint16_t port, int clients, int frames) {
  std::vector<std::unique_ptr<AppPipeline>> cs;
  for (int c = 0; c < clients; ++c) {
    cs.push_back(std::make_unique<AppPipeline>(client_desc(port), kInCaps));
    cs.back()->play();
  }
  std::vector<std::thread> th;
  for (int c = 0; c < clients; ++c)
    th.emplace_back([&, c] {
      for (int n = 0; n < frames; ++n) cs[c]->push(input(c, n), n * GST_MSECOND);
      cs[c]->eos();
    });
  for (auto &t : th) t.join();
  std::vector<std::vector<std::vector<uint8_t>>> out(clients);
  for (int c = 0; c < clients; ++c) {
    std::vector<uint8_t> got;
    while (static_cast<int>(out[c].size()) < frames && cs[c]->pull(&got, nullptr, 10 * GST_SECOND))
      out[c].push_back(got);
    EXPECT_EQ(static_cast<int>(out[c].size()), frames)
        << "client " << c << joined(cs[c]->messages(GST_MESSAGE_ERROR))
        << joined(cs[c]->messages(GST_MESSAGE_WARNING));
  }
  return out;
}

void expect_model(const std::vector<std::vector<std::vector<uint8_t>>> &answers) {
  for (std::size_t c = 0; c < answers.size(); ++c)
    for (std::size_t n = 0; n < answers[c].size(); ++n) {
      ASSERT_EQ(answers[c][n].size(), 16u);
      const auto want = local_model(input(static_cast<int>(c), static_cast<int>(n)));
      float got[4];
      memcpy(got, answers[c][n].data(), 16);
      for (int o = 0; o < 4; ++o)
        ASSERT_NEAR(got[o], want[o], 1e-5) << "client " << c << " frame " << n << " out " << o;
    }
}

// 8 clients x `frames` to an unbatched server (`ref`, another process) and to a batching one
// (`batched`, here): answers byte for byte equal, equal to the model computed here, and the
// requests were really batched.
void expect_batched_as_unbatched(const std::string &ref_desc, uint16_t ref_port,
                                 const std::string &batched_desc, uint16_t batched_port,
                                 int frames) {
  Child ref(ref_desc, "qb_ref");
  LocalServer batched(batched_desc);
  ASSERT_TRUE(ref.wait_port(ref_port)) << ref.log();
  const auto want = ask(ref_port, 8, frames);
  const auto got = ask(batched_port, 8, frames);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t c = 0; c < got.size(); ++c) EXPECT_EQ(got[c], want[c]) << "client " << c;
  expect_model(got);
  GstStructure *st = batched.stats();
  const guint64 batches = stat(st, "batches"), requests = stat(st, "batched");
  gst_structure_free(st);
  EXPECT_EQ(requests, 8u * static_cast<guint64>(frames));
  EXPECT_LT(batches * 2, requests) << "fewer than 2 requests per batch on average";
}

class QueryBatch : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const std::string dir = nns::test::make_temp_dir();
    const std::string script = dir + "/gen.py";
    std::ofstream(script) << kGen;
    const std::string cmd = "/usr/bin/python3 " + script + " " + dir + " " + NNS_SOURCE_DIR +
                            "/tests/data > " + dir + "/gen.log 2>&1";
    if (std::system(cmd.c_str()) == 0) g_dir = dir;
  }
  void SetUp() override {
    if (g_dir.empty()) NNS_SKIP_UNLESS_CI("/usr/bin/python3 with onnx cannot generate the models");
  }
};

}  // namespace

TEST(EdgeChild, Run) {
  edge_test::run_child();
}

// A model with a free batch dimension, run at N=8 (input=8:8): the answers of 8 clients are
// byte for byte those of an unbatched server (another process, same model at N=1), equal to
// the model computed here, and the requests were really batched.
TEST_F(QueryBatch, DynamicBatchModelAnswersAsUnbatched) {
  const uint16_t p1 = free_port(), p8 = free_port();
  expect_batched_as_unbatched(server_desc(p1, 1, 0, "dyn"), p1, server_desc(p8, 8, 20000, "dyn"),
                              p8, 40);
}

// PyTorch back end: a TorchScript module run at batch 8 (input=8:8), 8 clients.
TEST_F(QueryBatch, PytorchModelAtBatchEight) {
  const std::string so =
      std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_pytorch.so";
  if (!std::ifstream(so)) GTEST_SKIP() << "pytorch back end not built (" << so << ")";
  const std::string script = g_dir + "/gen_torch.py";
  std::ofstream(script) << kGenTorch;
  if (std::system(
          ("/usr/bin/python3 " + script + " " + g_dir + " > " + g_dir + "/gen_torch.log 2>&1")
              .c_str()) != 0)
    NNS_SKIP_UNLESS_CI("/usr/bin/python3 with torch cannot write the TorchScript model");
  const uint16_t port = free_port();
  LocalServer batched(
      "tensor_query_serversrc name=src host=127.0.0.1 port=" + std::to_string(port) +
      " max-batch=8 batch-timeout=20000 ! other/tensors,format=static,num_tensors=1,"
      "dimensions=(string)8:8,types=float32,framerate=0/1 ! tensor_filter framework=pytorch "
      "model=" +
      g_dir +
      "/lin.pt input=8:8 inputtype=float32 output=4:8 outputtype=float32 ! "
      "tensor_query_serversink");
  const auto got = ask(port, 8, 20);
  expect_model(got);
  GstStructure *st = batched.stats();
  const guint64 batches = stat(st, "batches"), requests = stat(st, "batched");
  gst_structure_free(st);
  EXPECT_EQ(requests, 8u * 20u);
  EXPECT_LT(batches * 2, requests);
}

// TFLite back end (the model file has a batch of 1; input=8:8 re-translates it at batch 8):
// 8 clients' answers byte for byte those of an unbatched server running the file as is.
TEST_F(QueryBatch, TfliteModelAtBatchEightAnswersAsUnbatched) {
  const std::string so =
      std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_tensorflow2-lite.so";
  if (!std::ifstream(so)) GTEST_SKIP() << "tflite back end not built (" << so << ")";
  if (!std::ifstream(g_dir + "/lin.tflite"))
    NNS_SKIP_UNLESS_CI("/usr/bin/python3 with flatbuffers cannot write the .tflite model");
  auto server = [&](uint16_t port, int n) {
    const std::string d = std::to_string(n);
    return "tensor_query_serversrc name=src host=127.0.0.1 port=" + std::to_string(port) +
           " max-batch=" + d +
           " batch-timeout=20000 ! "
           "other/tensors,format=static,num_tensors=1,dimensions=(string)8:" +
           d +
           ",types=float32,framerate=0/1 ! tensor_filter framework=tensorflow-lite model=" + g_dir +
           "/lin.tflite" + (n > 1 ? " input=8:" + d + " inputtype=float32" : "") +
           " ! tensor_query_serversink";
  };
  const uint16_t p1 = free_port(), p8 = free_port();
  expect_batched_as_unbatched(server(p1, 1), p1, server(p8, 8), p8, 30);
}

// A model with a fixed batch of 8.
TEST_F(QueryBatch, FixedBatchOfEightModel) {
  const uint16_t port = free_port();
  LocalServer batched(server_desc(port, 8, 20000, "fixed8"));
  const auto got = ask(port, 6, 30);  // 6 clients: slots 7-8 stay padding
  expect_model(got);
  GstStructure *st = batched.stats();
  EXPECT_EQ(stat(st, "batched"), 6u * 30u);
  gst_structure_free(st);
}

// A model whose batch is fixed to 1 cannot take max-batch=4: refused at negotiation, naming
// the model and its input.
TEST_F(QueryBatch, FixedBatchOneModelRefusesMaxBatch) {
  // The caps say batch 1 (as the model), or say 4 (as max-batch; the model cannot take them).
  for (int caps_n : {1, 4}) {
    LocalServer s(
        "tensor_query_serversrc host=127.0.0.1 port=0 max-batch=4 ! "
        "other/tensors,format=static,num_tensors=1,dimensions=(string)8:" +
        std::to_string(caps_n) + ",types=float32,framerate=0/1 ! " + filter("fixed1", 1) +
        "tensor_query_serversink");
    const std::string err = s.error(5 * GST_SECOND);
    if (caps_n == 1) {  // serversrc's check
      EXPECT_NE(err.find("max-batch=4: the input of tensorfilter"), std::string::npos) << err;
      EXPECT_NE(err.find("fixed1.onnx', input 'X' 8:1) cannot take a batch"), std::string::npos)
          << err;
      EXPECT_NE(err.find("outermost dimension must be 4 (the batch), got 1"), std::string::npos)
          << err;
    } else {  // tensor_filter's check of the batch caps 8:4 against the model's input
      EXPECT_NE(err.find("max-batch=4 (tensor_query_serversrc 'tensorqueryserversrc"),
                std::string::npos)
          << err;
      EXPECT_NE(err.find("got a model that fixes it to 1 (the stream 8:4 fails); use max-batch=1"),
                std::string::npos)
          << err;
      EXPECT_NE(err.find("fixed1.onnx': the input stream has 1 tensor(s): [0] float32 8:4, but"),
                std::string::npos)
          << err;
      EXPECT_NE(err.find("float32 8:1 'X'"), std::string::npos) << err;
    }
  }
}

// A .tflite file whose graph fixes its batch (a RESHAPE to [1,4]): input=8:8 cannot be
// re-translated, and the error is the max-batch refusal naming the model's input, with the
// engine's reshape message as the detail. The same refusal for a fixed-batch .onnx given
// input=8:8.
TEST_F(QueryBatch, FixedBatchTfliteModelIsRefusedNamingItsInput) {
  const std::string so =
      std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_tensorflow2-lite.so";
  if (!std::ifstream(so)) GTEST_SKIP() << "tflite back end not built (" << so << ")";
  if (!std::ifstream(g_dir + "/fixed1.tflite"))
    NNS_SKIP_UNLESS_CI("/usr/bin/python3 with flatbuffers cannot write the .tflite model");
  struct Case {
    std::string framework, model, input_name;
  };
  for (const Case &c :
       {Case{"tensorflow-lite", "fixed1.tflite", "x"}, Case{"onnxruntime", "fixed1.onnx", "X"}}) {
    LocalServer s(
        "tensor_query_serversrc name=src host=127.0.0.1 port=0 max-batch=8 ! "
        "other/tensors,format=static,num_tensors=1,dimensions=(string)8:8,types=float32,"
        "framerate=0/1 ! tensor_filter name=f framework=" +
        c.framework + " model=" + g_dir + "/" + c.model +
        " input=8:8 inputtype=float32 ! tensor_query_serversink");
    const std::string err = s.error(5 * GST_SECOND);
    EXPECT_NE(err.find("f: max-batch=8 (tensor_query_serversrc 'src'): the input of f ("),
              std::string::npos)
        << err;
    EXPECT_NE(err.find(c.model + "', input 0 '" + c.input_name +
                       "' float32 8:1) cannot take a batch: expected a batch dimension (the "
                       "outermost) that can grow to 8, got a model that fixes it to 1 "
                       "(input=8:8 fails); use max-batch=1"),
              std::string::npos)
        << err;
    EXPECT_NE(err.find("Detail: framework '"), std::string::npos) << err;
    if (c.model == "fixed1.tflite") {  // ONNX Runtime's reshape error, kept
      EXPECT_NE(err.find("Input shape:{8,4}, requested shape:{1,4}"), std::string::npos) << err;
    }
  }
}

// The same refusal from the PyTorch back end (TorchScript declares no shapes: its probe run at
// input=8:8 fails in a reshape to [1,4]).
TEST_F(QueryBatch, FixedBatchPytorchModelIsRefused) {
  const std::string so =
      std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_pytorch.so";
  if (!std::ifstream(so)) GTEST_SKIP() << "pytorch back end not built (" << so << ")";
  const std::string script = g_dir + "/gen_torch_fixed.py";
  std::ofstream(script) << "import sys, torch\n"
                           "class M(torch.nn.Module):\n"
                           "    def forward(self, x):\n"
                           "        return (x[:, :4] * 2.0).reshape(1, 4)\n"
                           "torch.jit.trace(M().eval(), torch.zeros(1, 8)).save(sys.argv[1])\n";
  if (std::system(("/usr/bin/python3 " + script + " " + g_dir + "/fixed1.pt > " + g_dir +
                   "/gen_torch_fixed.log 2>&1")
                      .c_str()) != 0)
    NNS_SKIP_UNLESS_CI("/usr/bin/python3 with torch cannot write the TorchScript model");
  LocalServer s(
      "tensor_query_serversrc name=src host=127.0.0.1 port=0 max-batch=8 ! "
      "other/tensors,format=static,num_tensors=1,dimensions=(string)8:8,types=float32,"
      "framerate=0/1 ! tensor_filter name=f framework=pytorch model=" +
      g_dir + "/fixed1.pt input=8:8 inputtype=float32 ! tensor_query_serversink");
  const std::string err = s.error(10 * GST_SECOND);
  EXPECT_NE(err.find("f: max-batch=8 (tensor_query_serversrc 'src'): the input of f (framework "
                     "'pytorch', model '"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("fixed1.pt') cannot take a batch: expected a batch dimension (the "
                     "outermost) that can grow to 8, got a model that does not run at 8 (the "
                     "back end declares no input shapes) (input=8:8 fails); use max-batch=1"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("shape '[1, 4]' is invalid for input of size 32"), std::string::npos) << err;
}

// A model that does not keep the batch outermost in its answer (sums over it): refused at
// negotiation by tensor_query_serversink, naming the answer tensor and the model, before any
// request (not answers split into garbage).
TEST_F(QueryBatch, AnswerWithoutTheBatchIsAnError) {
  LocalServer s(
      "tensor_query_serversrc host=127.0.0.1 port=0 max-batch=8 ! "
      "other/tensors,format=static,num_tensors=1,dimensions=(string)8:8,types=float32,"
      "framerate=0/1 ! " +
      filter("sum0", 8) + "tensor_query_serversink");
  const std::string err = s.error(10 * GST_SECOND);
  EXPECT_NE(err.find("max-batch=8: a batch of 8 requests (tensor_query_serversrc max-batch) "
                     "cannot be split: answer tensor 0 is float32 8:1 (from tensor_filter '"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("sum0.onnx'), its outermost dimension must be the batch (8); use a model "
                     "that keeps the batch outermost in its outputs, or max-batch=1"),
            std::string::npos)
      << err;
}

// batch-timeout bounds how long a lone request waits for company.
TEST_F(QueryBatch, TimeoutBoundsALoneRequest) {
  for (guint64 timeout_us : {0ull, 100000ull}) {
    const uint16_t port = free_port();
    LocalServer s(server_desc(port, 8, timeout_us, "dyn"));
    AppPipeline c(client_desc(port), kInCaps);
    c.play();
    std::vector<uint8_t> got;
    c.push(input(0, 0), 0);  // connects and warms up
    ASSERT_TRUE(c.pull(&got)) << joined(c.messages(GST_MESSAGE_ERROR));
    double worst = 0, best = 1e9;
    for (int n = 1; n <= 3; ++n) {
      const auto t0 = std::chrono::steady_clock::now();
      c.push(input(0, n), n * GST_MSECOND);
      ASSERT_TRUE(c.pull(&got));
      const double ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      worst = std::max(worst, ms);
      best = std::min(best, ms);
    }
    const double bound = static_cast<double>(timeout_us) / 1000.0;
    RecordProperty("lone_request_ms_timeout_" + std::to_string(timeout_us), std::to_string(worst));
    EXPECT_GE(best, bound) << "a lone request left before batch-timeout";
    EXPECT_LT(worst, bound + 150.0)
        << "a lone request waited well past batch-timeout=" << timeout_us << " us";
  }
}

// batch-timeout counts from when the server is free for a request that was already waiting:
// b arrives while a's batch is computed (identity sleeps 500 ms), and c, sent when a's answer
// came, still joins b's batch (400 ms of margin for c's connection under load). (Counting from b's
// arrival, b left alone at once: lockstep clients then split into groups that never meet, every
// batch half padding.)
TEST_F(QueryBatch, RequestWaitingWhileBusyWaitsForCompany) {
  const uint16_t port = free_port();
  LocalServer s("tensor_query_serversrc name=src host=127.0.0.1 port=" + std::to_string(port) +
                " max-batch=2 batch-timeout=400000 ! other/tensors,format=static,num_tensors=1,"
                "dimensions=(string)8:2,types=float32,framerate=0/1 ! " +
                filter("dyn", 2) + "identity sleep-time=500000 ! tensor_query_serversink");
  AppPipeline a(client_desc(port), kInCaps), b(client_desc(port), kInCaps),
      c(client_desc(port), kInCaps);
  a.play();
  b.play();
  c.play();
  std::vector<uint8_t> got;
  a.push(input(0, 0), 0);  // alone: leaves after 400 ms, computed until ~900 ms
  std::this_thread::sleep_for(500ms);
  b.push(input(1, 0), 0);  // waits while a's batch is computed
  ASSERT_TRUE(a.pull(&got)) << joined(a.messages(GST_MESSAGE_ERROR));
  c.push(input(2, 0), 0);  // the server is free now: c joins b
  ASSERT_TRUE(b.pull(&got)) << joined(b.messages(GST_MESSAGE_ERROR));
  ASSERT_TRUE(c.pull(&got)) << joined(c.messages(GST_MESSAGE_ERROR));
  GstStructure *st = s.stats();
  const guint64 batches = stat(st, "batches"), requests = stat(st, "batched");
  gst_structure_free(st);
  EXPECT_EQ(requests, 3u);
  EXPECT_EQ(batches, 2u) << "b left without waiting for c: batch-timeout counted from b's arrival";
}
