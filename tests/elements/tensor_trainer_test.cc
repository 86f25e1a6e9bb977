// SPDX-License-Identifier: LGPL-2.1-only
// tensor_trainer with the C test sub-plugin "counting" (tests/trainer/counting_trainer.c, built
// against the 2.x trainer ABI, loaded from a trainers folder): the per-epoch output values, the
// completion message and file, events sent late from another thread, and the bus errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>

#include "elements/stream_util.h"
#include "support/harness.h"

namespace fs = std::filesystem;
using nns::test::make_buffer;
using nns::test::Pipe;

namespace {

// Before main(): test_main.cc only sets NNSTREAMER_TRAINERS when it is unset.
const bool kEnv = [] {
  setenv("NNSTREAMER_TRAINERS", NNS_TEST_TRAINERS_DIR, 1);
  return true;
}();

struct Dir {
  fs::path d = nns::test::make_temp_dir();
  ~Dir() {
    std::error_code ec;
    fs::remove_all(d, ec);
  }
  std::string file(const std::string &name, const std::string &text) const {
    std::ofstream((d / name).string()) << text;
    return (d / name).string();
  }
  std::string path(const std::string &name) const { return (d / name).string(); }
};

const char *kCaps =
    "other/tensors,format=static,num_tensors=2,dimensions=(string)2.1,"
    "types=(string)float32.float32,framerate=(fraction)0/1";

std::vector<std::vector<uint8_t>> sample(float first) {
  float in[2] = {first, -first};
  float label = 1.0f;
  return {
      std::vector<uint8_t>(reinterpret_cast<uint8_t *>(in), reinterpret_cast<uint8_t *>(in) + 8),
      std::vector<uint8_t>(reinterpret_cast<uint8_t *>(&label),
                           reinterpret_cast<uint8_t *>(&label) + 4)};
}

std::vector<double> stats(GstBuffer *b) {
  auto bytes = nns::test::tensor_bytes(b, 0);
  std::vector<double> v(bytes.size() / 8);
  std::memcpy(v.data(), bytes.data(), v.size() * 8);
  return v;
}

struct TrainRun {
  nns::test::RunResult result;
  std::vector<std::vector<double>> outputs;
  std::string completion;  // the element message, as a string
};

TrainRun train(const std::string &props, int samples, bool eos = true) {
  Pipe p(nns::test::appsrc("in", kCaps) + "! tensor_trainer name=t framework=counting " + props +
         " ! appsink name=out sync=false");
  p.collect("out");
  TrainRun r;
  std::mutex m;
  GstBus *bus = gst_element_get_bus(p.pipeline());
  struct Ctx {
    TrainRun *r;
    std::mutex *m;
  } ctx{&r, &m};
  gst_bus_set_sync_handler(
      bus,
      [](GstBus *, GstMessage *msg, gpointer data) -> GstBusSyncReply {
        auto *c = static_cast<Ctx *>(data);
        const GstStructure *s = gst_message_get_structure(msg);
        if (GST_MESSAGE_TYPE(msg) == GST_MESSAGE_ELEMENT && s &&
            gst_structure_has_name(s, "nnstreamer-trainer-complete")) {
          gchar *str = gst_structure_to_string(s);
          std::lock_guard<std::mutex> l(*c->m);
          c->r->completion = str;
          g_free(str);
        }
        return GST_BUS_PASS;
      },
      &ctx, nullptr);
  gst_element_set_state(p.pipeline(), GST_STATE_PLAYING);
  for (int k = 0; k < samples; ++k) p.push("in", make_buffer(sample(static_cast<float>(k)), k));
  if (eos) p.eos("in");
  r.result = p.run(20);
  gst_bus_set_sync_handler(bus, nullptr, nullptr, nullptr);
  gst_object_unref(bus);
  for (GstBuffer *b : p.out()) r.outputs.push_back(stats(b));
  return r;
}

void expect_stats(const std::vector<double> &got, std::vector<double> want) {
  ASSERT_EQ(got.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    if (std::isinf(want[i]))
      EXPECT_TRUE(std::isinf(got[i]) && got[i] < 0) << "value " << i << " = " << got[i];
    else
      EXPECT_DOUBLE_EQ(got[i], want[i]) << "value " << i;
  }
}

void expect_two_epochs(const TrainRun &r, const Dir &d) {
  ASSERT_TRUE(r.result.eos) << r.result.error_text;
  const double inf = -INFINITY;
  // After the first sample of each epoch and at each epoch's end, as NNStreamer.
  ASSERT_EQ(r.outputs.size(), 4u);
  expect_stats(r.outputs[0], {inf, inf, inf, inf});
  expect_stats(r.outputs[1], {1.0, 3, 3.5, 1});  // mean(0,1,2), 3 samples, mean(3,4), 1 epoch
  expect_stats(r.outputs[2], {1.0, 3, 3.5, 1});
  expect_stats(r.outputs[3], {6.0, 3, 8.5, 2});  // mean(5,6,7), mean(8,9)
  std::ifstream f(d.path("model.txt"));
  std::string line;
  std::getline(f, line);
  EXPECT_EQ(line, "10 samples, 2 epochs");
  EXPECT_NE(r.completion.find("epochs=(uint)2"), std::string::npos) << r.completion;
  EXPECT_NE(r.completion.find("validation-loss=(double)8.5"), std::string::npos) << r.completion;
  EXPECT_NE(r.completion.find("model.txt"), std::string::npos) << r.completion;
}

std::string props(const Dir &d, const std::string &config) {
  return "model-config=" + config + " model-save-path=" + d.path("model.txt") +
         " num-inputs=1 num-labels=1 num-training-samples=3 num-validation-samples=2 epochs=2";
}

}  // namespace

TEST(TensorTrainer, EpochFiguresCompletionAndModel) {
  Dir d;
  expect_two_epochs(train(props(d, d.file("cfg", "sync")), 10), d);
}

TEST(TensorTrainer, EventsFromAnotherThreadLater) {
  Dir d;
  expect_two_epochs(train(props(d, d.file("cfg", "async")), 10), d);
}

TEST(TensorTrainer, EarlyEndOfStreamIsAnError) {
  Dir d;
  TrainRun r = train(props(d, d.file("cfg", "sync")), 7);
  ASSERT_TRUE(r.result.error);
  EXPECT_NE(r.result.error_text.find("after 7 of 10 samples"), std::string::npos)
      << r.result.error_text;
  EXPECT_NE(r.result.error_text.find("model.txt was not written"), std::string::npos)
      << r.result.error_text;
}

TEST(TensorTrainer, SettingErrorsNameTheProblem) {
  Dir d;
  const std::string cfg = d.file("cfg", "sync");
  auto error_of = [&](const std::string &p) {
    Pipe pipe(nns::test::appsrc("in", kCaps) + "! tensor_trainer " + p + " ! fakesink");
    gst_element_set_state(pipe.pipeline(), GST_STATE_PLAYING);
    pipe.push("in", make_buffer(sample(1), 0));
    pipe.eos("in");
    return pipe.run(10).error_text;
  };
  const std::string common =
      " model-save-path=" + d.path("m") + " num-training-samples=3 num-validation-samples=2 ";
  std::string e = error_of("framework=nosuch model-config=" + cfg + common);
  EXPECT_NE(e.find("framework 'nosuch'"), std::string::npos) << e;
  EXPECT_NE(e.find("counting"), std::string::npos) << e;  // the available ones are listed
  e = error_of("framework=counting model-config=" + d.path("missing.cfg") + common);
  EXPECT_NE(e.find("missing.cfg"), std::string::npos) << e;
  e = error_of("framework=counting model-config=" + d.file("bad", "fail-create") + common);
  EXPECT_NE(e.find("asks create() to fail"), std::string::npos) << e;
  e = error_of("framework=counting model-config=" + cfg + common + "num-inputs=2");
  EXPECT_NE(e.find("num-inputs + num-labels = 2 + 1"), std::string::npos) << e;
  e = error_of("framework=counting model-config=" + cfg + " num-training-samples=3");
  EXPECT_NE(e.find("model-save-path"), std::string::npos) << e;
}

TEST(TensorTrainer, PropertyDefaultsAsUpstream) {
  GstElement *t = gst_element_factory_make("tensor_trainer", nullptr);
  ASSERT_NE(t, nullptr);
  gchar *fw = nullptr, *load = nullptr;
  guint inputs = 0, labels = 0, train = 1, valid = 1, epochs = 0;
  g_object_get(t, "framework", &fw, "model-load-path", &load, "num-inputs", &inputs, "num-labels",
               &labels, "num-training-samples", &train, "num-validation-samples", &valid, "epochs",
               &epochs, nullptr);
  EXPECT_STREQ(fw, "");
  EXPECT_EQ(load, nullptr);
  EXPECT_EQ(inputs, 1u);
  EXPECT_EQ(labels, 1u);
  EXPECT_EQ(train, 0u);
  EXPECT_EQ(valid, 0u);
  EXPECT_EQ(epochs, 1u);
  g_free(fw);
  g_free(load);
  gst_object_unref(t);
}
