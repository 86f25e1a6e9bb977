// SPDX-License-Identifier: LGPL-2.1-only
// The training itself, GStreamer- and ABI-free: a TorchScript module, a loss and an optimizer
// (from a JSON config), mini-batches filled one sample at a time, per-epoch figures, and the
// trained module saved as TorchScript (loadable by tensor_filter framework=pytorch).
#pragma once

#include <torch/script.h>
#include <torch/torch.h>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
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

// Training runs on a worker thread of its own: push() copies a sample into the batch being
// filled and returns; a full batch is handed to the worker (two batches alternate, so the
// stream fills one while the worker trains on the other). When the worker finishes an epoch's
// last batch it computes the epoch's figures and calls `on_epoch(finished)` from its thread;
// after the last epoch it saves the model first (then `finished` is true).
class TorchTrainer {
 public:
  using EpochCallback = std::function<void(bool finished)>;
  // `load_path` (model-load-path) replaces the config's model when not empty.
  TorchTrainer(const TrainConfig &cfg, const std::string &load_path,
               std::vector<SampleShape> inputs, std::vector<SampleShape> labels,
               int64_t num_training, int64_t num_validation, int64_t epochs, std::string save_path,
               EpochCallback on_epoch);
  ~TorchTrainer();  // stops the worker (an unfinished training is abandoned)
  TorchTrainer(const TorchTrainer &) = delete;
  TorchTrainer &operator=(const TorchTrainer &) = delete;
  // One sample: input then label tensors (bytes as negotiated). Throws if the worker failed.
  void push(const std::vector<const void *> &tensors);
  EpochStats stats() const;
  int64_t epochs_done() const;
  bool finished() const;

 private:
  struct Batch {
    std::vector<torch::Tensor> in, label;  // [batch, ...] each, filled row by row
    int64_t fill = 0;
    bool training = true, end_of_epoch = false;
    bool busy = false;  // handed to the worker
  };
  void hand_over(bool end_of_epoch);
  void worker();
  void step(Batch &b);
  torch::Tensor forward(const std::vector<torch::Tensor> &inputs);

  TrainConfig cfg_;
  torch::jit::Module module_;
  std::vector<torch::Tensor> params_;
  std::unique_ptr<torch::optim::Optimizer> opt_;
  std::vector<SampleShape> in_shapes_, label_shapes_;
  int64_t num_training_, num_validation_, epochs_;
  std::string save_path_;
  EpochCallback on_epoch_;
  // producer (streaming thread)
  Batch batches_[2];
  int cur_ = 0;
  int64_t in_epoch_ = 0, pushed_epochs_ = 0;
  // shared with the worker
  mutable std::mutex lock_;
  std::condition_variable cond_;
  std::deque<int> queue_;  // batches to train, in order
  bool stop_ = false;
  std::string error_;  // the worker's failure, reported by the next push()
  int64_t epochs_done_ = 0;
  EpochStats last_;
  // worker only
  double loss_sum_ = 0, correct_ = 0, vloss_sum_ = 0, vcorrect_ = 0;
  std::thread thread_;
};

}  // namespace nns::trainer
