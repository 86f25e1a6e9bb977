// SPDX-License-Identifier: LGPL-2.1-only
// tensor_trainer's per-sample overhead above the training alone (issue target: <= 5%).
// Data: 1500 samples of a float32 64 input and a one-hot 10 label (random, seed 1) in a data
// repository; model: an MLP 64 -> 64 -> 10 in TorchScript (made with /usr/bin/python3 + torch),
// SGD batch 16. Two ways, interleaved, best of --runs:
//   direct   : the pytorch trainer sub-plugin (.so) called through its C ABI in a loop
//              (create, start, push_data for every sample from the mapped file)
//   pipeline : datareposrc ! tensor_trainer framework=pytorch ! fakesink
// Overhead = pipeline / direct - 1.
//
// usage: trainer_bench [--epochs E] [--runs R] [--hidden H (64: the digits demo's MLP)]
//        [--threads T (libtorch threads; 0: its default)]
#include <dlfcn.h>
#include <fcntl.h>
#include <gst/gst.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "core/c_tensor_info.h"
#include "gst/plugin_init.h"
#include "nnstreamer_plugin_api_trainer.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kSamples = 1500, kTrain = 1200, kValid = 300;

double pipeline(const std::string &dir, int epochs) {
  const std::string desc =
      "datareposrc location=" + dir + "/d.dat json=" + dir +
      "/d.json is-shuffle=false epochs=" + std::to_string(epochs) +
      " ! tensor_trainer framework=pytorch model-config=" + dir +
      "/cfg.json model-save-path=" + dir + "/p.pt num-inputs=1 num-labels=1 " +
      "num-training-samples=1200 num-validation-samples=300 epochs=" + std::to_string(epochs) +
      " ! fakesink";
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p || err) return -1;
  GstBus *bus = gst_element_get_bus(p);
  auto t0 = Clock::now();
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  double s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!m || GST_MESSAGE_TYPE(m) != GST_MESSAGE_EOS) {
    std::fprintf(stderr, "trainer_bench: the pipeline failed\n");
    s = -1;
  }
  if (m) gst_message_unref(m);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(bus);
  gst_object_unref(p);
  return s;
}

double direct(const GstTensorTrainerFramework *fw, const std::string &dir, int epochs,
              const uint8_t *data) {
  GstTensorTrainerProperties prop;
  std::memset(&prop, 0, sizeof prop);
  nns::TensorsInfo info;
  info.tensors = {{"", nns::TensorType::kFloat32, nns::make_dims({64, 1})},
                  {"", nns::TensorType::kFloat32, nns::make_dims({10, 1})}};
  nns::gst_info_init(&prop.input_meta);
  nns::to_c(info, &prop.input_meta);
  const std::string cfg = dir + "/cfg.json", save = dir + "/d.pt";
  prop.model_config = cfg.c_str();
  prop.model_save_path = save.c_str();
  prop.num_inputs = prop.num_labels = 1;
  prop.num_training_samples = kTrain;
  prop.num_validation_samples = kValid;
  prop.num_epochs = static_cast<unsigned>(epochs);
  void *priv = nullptr;
  auto t0 = Clock::now();
  if (fw->create(fw, &prop, &priv) != 0) return -1;
  GstTensorTrainerEventNotifier notifier{GST_TENSOR_TRAINER_FRAMEWORK_V1, nullptr};
  fw->start(fw, &prop, &notifier, priv);
  GstTensorMemory mem[2];
  for (int e = 0; e < epochs; ++e) {
    for (int i = 0; i < kSamples; ++i) {
      mem[0] = {const_cast<uint8_t *>(data + i * 296), 256};
      mem[1] = {const_cast<uint8_t *>(data + i * 296 + 256), 40};
      if (fw->push_data(fw, &prop, priv, mem) != 0) return -1;
    }
  }
  fw->getStatus(fw, &prop, priv);
  fw->destroy(fw, &prop, &priv);
  double s = std::chrono::duration<double>(Clock::now() - t0).count();
  nns::gst_info_clear(&prop.input_meta);
  return s;
}

}  // namespace

int main(int argc, char **argv) {
  int epochs = 5, runs = 5, hidden = 64, threads = 0;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--epochs")) epochs = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--hidden")) hidden = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--threads")) threads = std::atoi(argv[i + 1]);
  }
  gst_init(&argc, &argv);
  setenv("NNSTREAMER_TRAINERS", NNS_BUILD_DIR "/subplugins/trainers", 1);
  nns_register_static();
  char tmpl[] = "/tmp/nns-trainer-bench-XXXXXX";
  if (!mkdtemp(tmpl)) return 1;
  const std::string dir = tmpl;
  // Data: input 64 floats in [0, 1), label one-hot of (sum > 32 ? 1 : 0) + 2 * (i % 5).
  std::vector<uint8_t> bytes(kSamples * 296);
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(0, 1);
  for (int i = 0; i < kSamples; ++i) {
    float x[64], y[10] = {0};
    float sum = 0;
    for (float &v : x) sum += (v = u(rng));
    y[(sum > 32 ? 1 : 0) + 2 * (i % 5)] = 1;
    std::memcpy(&bytes[i * 296], x, 256);
    std::memcpy(&bytes[i * 296 + 256], y, 40);
  }
  std::ofstream(dir + "/d.dat", std::ios::binary)
      .write(reinterpret_cast<const char *>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  std::ofstream(dir + "/d.json") << "{\"gst_caps\":\"other/tensors, format=(string)static, "
                                    "framerate=(fraction)0/1, num_tensors=(int)2, "
                                    "dimensions=(string)64:1.10:1, types=(string)float32.float32\","
                                    "\"total_samples\":1500,\"sample_size\":296}";
  std::ofstream(dir + "/cfg.json")
      << "{\"model\":\"mlp.pt\",\"optimizer\":\"sgd\","
         "\"learning_rate\":0.05,\"batch_size\":16,\"seed\":1,\"num_threads\":"
      << threads << "}";
  {
    std::ofstream py(dir + "/make.py");
    py << "import torch\n"
          "class M(torch.nn.Module):\n"
          "    def __init__(self):\n"
          "        super().__init__()\n"
          "        self.a = torch.nn.Linear(64, "
       << hidden
       << ")\n"
          "        self.b = torch.nn.Linear("
       << hidden
       << ", 10)\n"
          "    def forward(self, x):\n"
          "        return self.b(torch.relu(self.a(x)))\n"
          "torch.manual_seed(3)\n"
          "torch.jit.script(M()).save('"
       << dir << "/mlp.pt')\n";
  }
  const std::string make = "/usr/bin/python3 " + dir + "/make.py";
  if (std::system(make.c_str()) != 0) {
    std::fprintf(stderr, "trainer_bench: cannot make the model (python3-torch)\n");
    return 1;
  }
  void *h = dlopen(NNS_BUILD_DIR "/subplugins/trainers/libnnstreamer_trainer_pytorch.so", RTLD_NOW);
  auto entry = h ? reinterpret_cast<const GstTensorTrainerFramework *(*)()>(
                       dlsym(h, "nnstreamer_trainer_subplugin"))
                 : nullptr;
  if (!entry) {
    std::fprintf(stderr, "trainer_bench: cannot load the pytorch trainer: %s\n", dlerror());
    return 1;
  }
  double best_d = 1e9, best_p = 1e9;
  for (int r = 0; r < runs; ++r) {
    double d = direct(entry(), dir, epochs, bytes.data()), p = pipeline(dir, epochs);
    if (d < 0 || p < 0) return 1;
    best_d = std::min(best_d, d);
    best_p = std::min(best_p, p);
  }
  const double n = static_cast<double>(epochs) * kSamples;
  std::printf("samples: %d x %d epochs (MLP 64-%d-10, SGD batch 16), best of %d runs\n", kSamples,
              epochs, hidden, runs);
  std::printf("direct (sub-plugin C ABI)    %7.2f us/sample\n", best_d / n * 1e6);
  std::printf("pipeline (datareposrc ! tensor_trainer ! fakesink) %7.2f us/sample\n",
              best_p / n * 1e6);
  std::printf("overhead: %+.1f%% (target <= 5%%)\n", (best_p / best_d - 1) * 100);
  std::filesystem::remove_all(dir);
  return 0;
}
