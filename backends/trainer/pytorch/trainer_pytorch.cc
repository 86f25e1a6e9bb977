// SPDX-License-Identifier: LGPL-2.1-only
// tensor_trainer sub-plugin "pytorch" (NNStreamer's GstTensorTrainerFramework V1): trains a
// TorchScript model on the streamed samples with libtorch and saves it as TorchScript at the end
// (torch_trainer.h). model-config: a JSON file {"model": "net.pt", "loss": "cross_entropy",
// "optimizer": "sgd", "learning_rate": 0.1, "momentum": 0.9, "batch_size": 32, "seed": 0}
// or a TorchScript file (then SGD, lr 0.01, batch 1, cross entropy).
// docs/backends/trainer_pytorch.md.
#include <exception>
#include <memory>
#include <mutex>
#include <string>

#include "nnstreamer_plugin_api_trainer.h"
#include "torch_trainer.h"

#define NNS_EXPORT __attribute__((visibility("default")))

extern "C" {
// Resolved from the host (nnstreamer-cpp's plugin or NNStreamer's); weak so the object also
// loads where the host finds the table through nnstreamer_trainer_subplugin() instead.
int nnstreamer_trainer_probe(GstTensorTrainerFramework *ttsp) __attribute__((weak));
int nnstreamer_trainer_exit(GstTensorTrainerFramework *ttsp) __attribute__((weak));
void nnstreamer_trainer_notify_event(GstTensorTrainerEventNotifier *notifier,
                                     GstTensorTrainerEventType type, void *data)
    __attribute__((weak));
}

namespace {

thread_local std::string g_last_error;

struct Priv {
  std::unique_ptr<nns::trainer::TorchTrainer> trainer;
  GstTensorTrainerEventNotifier *notifier = nullptr;
  std::string save_path;
  std::mutex lock;  // push_data and getStatus may come from different threads
};

int fail(const std::string &msg) {
  g_last_error = msg;
  return -1;
}

c10::ScalarType torch_type(tensor_type t) {
  switch (t) {
    case _NNS_INT32:
      return torch::kInt32;
    case _NNS_INT16:
      return torch::kInt16;
    case _NNS_INT8:
      return torch::kInt8;
    case _NNS_UINT8:
      return torch::kUInt8;
    case _NNS_FLOAT64:
      return torch::kFloat64;
    case _NNS_FLOAT32:
      return torch::kFloat32;
    case _NNS_INT64:
      return torch::kInt64;
    case _NNS_FLOAT16:
      return torch::kFloat16;
    default:
      throw std::runtime_error("tensor type " + std::to_string(static_cast<int>(t)) +
                               " has no torch equivalent (uint16/32/64)");
  }
}

// NNStreamer dims (innermost first) -> torch per-sample shape: outermost 1s dropped, reversed.
nns::trainer::SampleShape shape_of(const GstTensorInfo &info) {
  nns::trainer::SampleShape s;
  int rank = 0;
  for (int d = 0; d < NNS_TENSOR_RANK_LIMIT && info.dimension[d] > 0; ++d) rank = d + 1;
  while (rank > 1 && info.dimension[rank - 1] == 1) --rank;
  std::size_t count = 1;
  for (int d = rank - 1; d >= 0; --d) {
    s.shape.push_back(info.dimension[d]);
    count *= info.dimension[d];
  }
  s.type = torch_type(info.type);
  s.bytes = count * c10::elementSize(s.type);
  return s;
}

const GstTensorInfo *info_at(const GstTensorsInfo &in, unsigned i) {
  if (i < NNS_TENSOR_MEMORY_MAX) return &in.info[i];
  return in.extra ? &in.extra[i - NNS_TENSOR_MEMORY_MAX] : nullptr;
}

int pt_get_info(const GstTensorTrainerFramework *, const GstTensorTrainerProperties *, void *,
                GstTensorTrainerFrameworkInfo *info) {
  info->name = "pytorch";
  return 0;
}

int pt_create(const GstTensorTrainerFramework *, const GstTensorTrainerProperties *prop,
              void **private_data) {
  try {
    auto cfg = nns::trainer::read_config(prop->model_config);
    std::vector<nns::trainer::SampleShape> ins, labels;
    if (prop->input_meta.num_tensors < prop->num_inputs + prop->num_labels)
      return fail("a sample has " + std::to_string(prop->input_meta.num_tensors) +
                  " tensors, fewer than num-inputs + num-labels (flexible streams are not "
                  "supported by the pytorch trainer)");
    for (unsigned i = 0; i < prop->num_inputs + prop->num_labels; ++i) {
      const GstTensorInfo *t = info_at(prop->input_meta, i);
      if (!t) return fail("tensor " + std::to_string(i) + " is missing from input_meta");
      (i < prop->num_inputs ? ins : labels).push_back(shape_of(*t));
    }
    auto p = std::make_unique<Priv>();
    p->save_path = prop->model_save_path ? prop->model_save_path : "";
    p->trainer = std::make_unique<nns::trainer::TorchTrainer>(
        cfg, prop->model_load_path ? prop->model_load_path : "", ins, labels,
        prop->num_training_samples, prop->num_validation_samples, prop->num_epochs);
    *private_data = p.release();
    return 0;
  } catch (const std::exception &e) {
    return fail(e.what());
  }
}

int pt_destroy(const GstTensorTrainerFramework *, const GstTensorTrainerProperties *,
               void **private_data) {
  delete static_cast<Priv *>(*private_data);
  *private_data = nullptr;
  return 0;
}

int pt_start(const GstTensorTrainerFramework *, const GstTensorTrainerProperties *,
             GstTensorTrainerEventNotifier *notifier, void *private_data) {
  auto *p = static_cast<Priv *>(private_data);
  if (!p) return fail("start before create");
  p->notifier = notifier;
  return 0;
}

int pt_stop(const GstTensorTrainerFramework *, const GstTensorTrainerProperties *, void **) {
  return 0;  // training runs inside push_data: nothing runs in the background to stop
}

int pt_push(const GstTensorTrainerFramework *, const GstTensorTrainerProperties *prop,
            void *private_data, const GstTensorMemory *input) {
  auto *p = static_cast<Priv *>(private_data);
  try {
    std::vector<const void *> t;
    for (unsigned i = 0; i < prop->num_inputs + prop->num_labels; ++i) t.push_back(input[i].data);
    bool epoch_done, finished;
    {
      std::lock_guard<std::mutex> l(p->lock);
      epoch_done = p->trainer->push(t);
      finished = epoch_done && p->trainer->finished();
      if (finished && !p->save_path.empty()) p->trainer->save(p->save_path);
    }
    if (epoch_done && p->notifier && nnstreamer_trainer_notify_event)
      nnstreamer_trainer_notify_event(p->notifier, TRAINER_EVENT_EPOCH_COMPLETION, nullptr);
    if (finished && p->notifier && nnstreamer_trainer_notify_event)
      nnstreamer_trainer_notify_event(p->notifier, TRAINER_EVENT_TRAINING_COMPLETION, nullptr);
    return 0;
  } catch (const std::exception &e) {
    return fail(std::string("training step failed: ") + e.what());
  }
}

int pt_status(const GstTensorTrainerFramework *, GstTensorTrainerProperties *prop,
              void *private_data) {
  auto *p = static_cast<Priv *>(private_data);
  if (!p) return fail("getStatus before create");
  std::lock_guard<std::mutex> l(p->lock);
  const auto &s = p->trainer->stats();
  prop->epoch_count = static_cast<unsigned>(p->trainer->epochs_done());
  prop->training_loss = s.train_loss;
  prop->training_accuracy = s.train_acc;
  prop->validation_loss = s.valid_loss;
  prop->validation_accuracy = s.valid_acc;
  return 0;
}

GstTensorTrainerFramework g_table = {GST_TENSOR_TRAINER_FRAMEWORK_V1,
                                     pt_create,
                                     pt_destroy,
                                     pt_start,
                                     pt_stop,
                                     pt_push,
                                     pt_status,
                                     pt_get_info};

}  // namespace

extern "C" {

NNS_EXPORT const GstTensorTrainerFramework *nnstreamer_trainer_subplugin(void) {
  return &g_table;
}

// Why the last call on this thread failed (nnstreamer-cpp reads it for its bus error).
NNS_EXPORT const char *nns_trainer_subplugin_last_error(void) {
  return g_last_error.c_str();
}

__attribute__((constructor)) static void pt_register(void) {
  if (nnstreamer_trainer_probe) nnstreamer_trainer_probe(&g_table);
}

__attribute__((destructor)) static void pt_unregister(void) {
  if (nnstreamer_trainer_exit) nnstreamer_trainer_exit(&g_table);
}

}  // extern "C"
