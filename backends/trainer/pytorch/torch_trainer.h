// SPDX-License-Identifier: LGPL-2.1-only
// The training itself, GStreamer- and ABI-free: a TorchScript module, a loss and an optimizer
// (from a JSON config), mini-batches filled one sample at a time, per-epoch figures, and the
// trained module saved as TorchScript (loadable by tensor_filter framework=pytorch).
#pragma once

#include <torch/script.h>
#include <torch/torch.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace nns::trainer {

struct TrainConfig {
  std::string model;                   // TorchScript file
  std::string loss = "cross_entropy";  // or "mse"
  std::string optimizer = "sgd";       // or "adam"
  double learning_rate = 0.01, momentum = 0.0, weight_decay = 0.0;
  int64_t batch_size = 1;
  int64_t seed = 0;
  int64_t num_threads = 0;  // libtorch intra-op threads of the training thread; 0: leave
};

// Reads the model-config file: a JSON object (keys as TrainConfig; "model" relative to the file)
// or a TorchScript file itself (then every other setting is the default). Throws
// std::runtime_error naming the file and the bad key.
TrainConfig read_config(const std::string &path);

struct SampleShape {
  std::vector<int64_t> shape;  // per-sample torch shape (no batch dimension)
  c10::ScalarType type;
  std::size_t bytes;
};

struct EpochStats {
  double train_loss = 0, train_acc = 0, valid_loss = 0, valid_acc = 0;
};

class TorchTrainer {
 public:
  // `load_path` (model-load-path) replaces the config's model when not empty.
  TorchTrainer(const TrainConfig &cfg, const std::string &load_path,
               std::vector<SampleShape> inputs, std::vector<SampleShape> labels,
               int64_t num_training, int64_t num_validation, int64_t epochs);
  // One sample: input then label tensors (bytes as negotiated). Returns true when this sample
  // completed an epoch (stats() then holds its figures).
  bool push(const std::vector<const void *> &tensors);
  const EpochStats &stats() const { return last_; }
  int64_t epochs_done() const { return epochs_done_; }
  bool finished() const { return epochs_done_ >= epochs_; }
  void save(const std::string &path);  // eval mode, TorchScript

 private:
  void flush(bool training);
  torch::Tensor forward(const std::vector<torch::Tensor> &inputs);

  TrainConfig cfg_;
  torch::jit::Module module_;
  std::vector<torch::Tensor> params_;
  std::unique_ptr<torch::optim::Optimizer> opt_;
  std::vector<SampleShape> in_shapes_, label_shapes_;
  std::vector<torch::Tensor> in_batch_, label_batch_;  // [batch, ...] each, filled row by row
  int64_t fill_ = 0;
  int64_t num_training_, num_validation_, epochs_;
  int64_t in_epoch_ = 0, epochs_done_ = 0;
  double loss_sum_ = 0, correct_ = 0, vloss_sum_ = 0, vcorrect_ = 0;
  EpochStats last_;
};

}  // namespace nns::trainer
