// SPDX-License-Identifier: LGPL-2.1-only
#include "torch_trainer.h"

#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace nns::trainer {

namespace {

[[noreturn]] void bad(const std::string &path, const std::string &what) {
  throw std::runtime_error("model-config " + path + ": " + what);
}

std::string dir_of(const std::string &path) {
  auto slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

}  // namespace

TrainConfig read_config(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) bad(path, "cannot be read");
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string text = ss.str();
  TrainConfig c;
  // A TorchScript archive is a zip file ("PK"): the model itself, default settings.
  if (text.size() >= 2 && text[0] == 'P' && text[1] == 'K') {
    c.model = path;
    return c;
  }
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception &e) {
    bad(path, std::string("neither a TorchScript file nor JSON (") + e.what() + ")");
  }
  if (!j.is_object()) bad(path, "the JSON is not an object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    const std::string &k = it.key();
    const auto &v = it.value();
    auto num = [&](double lo) {
      if (!v.is_number() || v.get<double>() < lo)
        bad(path, "\"" + k + "\" must be a number >= " + std::to_string(lo) + ", got " + v.dump());
      return v.get<double>();
    };
    if (k == "model") {
      if (!v.is_string()) bad(path, "\"model\" must be a file name");
      std::string m = v.get<std::string>();
      c.model = !m.empty() && m[0] == '/' ? m : dir_of(path) + "/" + m;
    } else if (k == "loss") {
      c.loss = v.is_string() ? v.get<std::string>() : "";
      if (c.loss != "cross_entropy" && c.loss != "mse")
        bad(path, "\"loss\" must be \"cross_entropy\" or \"mse\", got " + v.dump());
    } else if (k == "optimizer") {
      c.optimizer = v.is_string() ? v.get<std::string>() : "";
      if (c.optimizer != "sgd" && c.optimizer != "adam")
        bad(path, "\"optimizer\" must be \"sgd\" or \"adam\", got " + v.dump());
    } else if (k == "learning_rate") {
      c.learning_rate = num(0);
    } else if (k == "momentum") {
      c.momentum = num(0);
    } else if (k == "weight_decay") {
      c.weight_decay = num(0);
    } else if (k == "batch_size") {
      c.batch_size = static_cast<int64_t>(num(1));
    } else if (k == "seed") {
      c.seed = static_cast<int64_t>(num(0));
    } else if (k == "num_threads") {
      c.num_threads = static_cast<int64_t>(num(0));
    } else {
      bad(path, "unknown key \"" + k +
                    "\" (known: model, loss, optimizer, learning_rate, momentum, weight_decay, "
                    "batch_size, seed, num_threads)");
    }
  }
  if (c.model.empty()) bad(path, "no \"model\" (the TorchScript file to train)");
  return c;
}

TorchTrainer::TorchTrainer(const TrainConfig &cfg, const std::string &load_path,
                           std::vector<SampleShape> inputs, std::vector<SampleShape> labels,
                           int64_t num_training, int64_t num_validation, int64_t epochs,
                           std::string save_path, EpochCallback on_epoch)
    : cfg_(cfg),
      in_shapes_(std::move(inputs)),
      label_shapes_(std::move(labels)),
      num_training_(num_training),
      num_validation_(num_validation),
      epochs_(epochs),
      save_path_(std::move(save_path)),
      on_epoch_(std::move(on_epoch)) {
  torch::manual_seed(static_cast<uint64_t>(cfg_.seed));
  const std::string from = load_path.empty() ? cfg_.model : load_path;
  try {
    module_ = torch::jit::load(from);
  } catch (const std::exception &e) {
    throw std::runtime_error("cannot load the TorchScript model " + from + ": " + e.what());
  }
  module_.train(true);
  for (const auto &p : module_.parameters()) {
    p.requires_grad_(true);
    params_.push_back(p);
  }
  if (params_.empty())
    throw std::runtime_error("the model " + from + " has no parameters to train");
  if (cfg_.optimizer == "adam")
    opt_ = std::make_unique<torch::optim::Adam>(
        params_, torch::optim::AdamOptions(cfg_.learning_rate).weight_decay(cfg_.weight_decay));
  else
    opt_ = std::make_unique<torch::optim::SGD>(params_, torch::optim::SGDOptions(cfg_.learning_rate)
                                                            .momentum(cfg_.momentum)
                                                            .weight_decay(cfg_.weight_decay));
  auto batch_of = [&](const SampleShape &s) {
    std::vector<int64_t> shape{cfg_.batch_size};
    shape.insert(shape.end(), s.shape.begin(), s.shape.end());
    return torch::empty(shape, torch::TensorOptions().dtype(s.type));
  };
  for (auto &b : batches_) {
    for (const auto &s : in_shapes_) b.in.push_back(batch_of(s));
    for (const auto &s : label_shapes_) b.label.push_back(batch_of(s));
  }
  thread_ = std::thread([this] { worker(); });
}

TorchTrainer::~TorchTrainer() {
  {
    std::lock_guard<std::mutex> l(lock_);
    stop_ = true;
  }
  cond_.notify_all();
  if (thread_.joinable()) thread_.join();
}

torch::Tensor TorchTrainer::forward(const std::vector<torch::Tensor> &inputs) {
  std::vector<torch::jit::IValue> args(inputs.begin(), inputs.end());
  torch::jit::IValue out = module_.forward(args);
  if (out.isTensor()) return out.toTensor();
  if (out.isTuple() && !out.toTuple()->elements().empty() &&
      out.toTuple()->elements()[0].isTensor())
    return out.toTuple()->elements()[0].toTensor();
  throw std::runtime_error("the model's forward() returns neither a tensor nor a tuple of them");
}

// One optimizer step (training) or evaluation (validation) on a batch; worker thread.
void TorchTrainer::step(Batch &b) {
  const int64_t n = b.fill;
  if (n == 0) return;
  std::vector<torch::Tensor> ins;
  for (auto &t : b.in) ins.push_back(t.narrow(0, 0, n));
  torch::Tensor label = b.label[0].narrow(0, 0, n).reshape({n, -1});
  module_.train(b.training);
  std::optional<torch::NoGradGuard> no_grad;
  if (!b.training) no_grad.emplace();
  if (b.training) opt_->zero_grad();
  torch::Tensor out = forward(ins).reshape({n, -1});
  torch::Tensor target;  // class indices, for cross entropy and accuracy
  if (label.size(1) == out.size(1) && out.size(1) > 1)
    target = label.argmax(1);
  else
    target = label.reshape({n}).to(torch::kLong);
  torch::Tensor loss = cfg_.loss == "mse" ? torch::mse_loss(out, label.to(out.scalar_type()))
                                          : torch::nn::functional::cross_entropy(out, target);
  if (b.training) {
    loss.backward();
    opt_->step();
  }
  const double correct = out.size(1) > 1 ? out.argmax(1).eq(target).sum().item<double>() : 0.0;
  (b.training ? loss_sum_ : vloss_sum_) += loss.item<double>() * static_cast<double>(n);
  (b.training ? correct_ : vcorrect_) += correct;
}

void TorchTrainer::worker() {
  // libtorch's thread count is per calling thread: set it in the thread that trains.
  if (cfg_.num_threads > 0) at::set_num_threads(static_cast<int>(cfg_.num_threads));
  for (;;) {
    int idx;
    {
      std::unique_lock<std::mutex> l(lock_);
      cond_.wait(l, [&] { return stop_ || !queue_.empty(); });
      if (stop_) return;
      idx = queue_.front();
      queue_.pop_front();
    }
    Batch &b = batches_[idx];
    std::string err;
    bool epoch_end = b.end_of_epoch, finished = false;
    try {
      step(b);
      if (epoch_end) {
        auto per = [](double v, int64_t n) { return n > 0 ? v / static_cast<double>(n) : 0.0; };
        EpochStats s{per(loss_sum_, num_training_), per(correct_, num_training_),
                     per(vloss_sum_, num_validation_), per(vcorrect_, num_validation_)};
        loss_sum_ = correct_ = vloss_sum_ = vcorrect_ = 0;
        int64_t done;
        {
          std::lock_guard<std::mutex> l(lock_);
          last_ = s;
          done = ++epochs_done_;
        }
        finished = done >= epochs_;
        if (finished && !save_path_.empty()) {
          module_.eval();
          module_.save(save_path_);
        }
      }
    } catch (const std::exception &e) {
      err = std::string("training step failed: ") + e.what();
    }
    {
      std::lock_guard<std::mutex> l(lock_);
      b.fill = 0;
      b.busy = false;
      if (!err.empty() && error_.empty()) error_ = err;
    }
    cond_.notify_all();
    if (epoch_end && err.empty() && on_epoch_) on_epoch_(finished);
  }
}

// Hands the batch being filled to the worker and switches to the other one (waiting until the
// worker is done with it).
void TorchTrainer::hand_over(bool end_of_epoch) {
  std::unique_lock<std::mutex> l(lock_);
  Batch &b = batches_[cur_];
  b.end_of_epoch = end_of_epoch;
  b.busy = true;
  queue_.push_back(cur_);
  cond_.notify_all();
  cur_ ^= 1;
  cond_.wait(l, [&] { return !batches_[cur_].busy || !error_.empty(); });
  if (!error_.empty()) throw std::runtime_error(error_);
}

void TorchTrainer::push(const std::vector<const void *> &tensors) {
  {
    std::lock_guard<std::mutex> l(lock_);
    if (!error_.empty()) throw std::runtime_error(error_);
  }
  if (pushed_epochs_ >= epochs_) return;
  const bool training = in_epoch_ < num_training_;
  Batch *b = &batches_[cur_];
  // The last partial training batch goes before the first validation sample.
  if (!training && b->fill > 0 && b->training) {
    hand_over(false);
    b = &batches_[cur_];
  }
  b->training = training;
  std::size_t k = 0;
  for (std::size_t i = 0; i < in_shapes_.size(); ++i, ++k)
    std::memcpy(static_cast<char *>(b->in[i].data_ptr()) + b->fill * in_shapes_[i].bytes,
                tensors[k], in_shapes_[i].bytes);
  for (std::size_t i = 0; i < label_shapes_.size(); ++i, ++k)
    std::memcpy(static_cast<char *>(b->label[i].data_ptr()) + b->fill * label_shapes_[i].bytes,
                tensors[k], label_shapes_[i].bytes);
  ++b->fill;
  const bool epoch_end = ++in_epoch_ == num_training_ + num_validation_;
  if (epoch_end) {
    in_epoch_ = 0;
    ++pushed_epochs_;
  }
  if (b->fill == cfg_.batch_size || epoch_end) hand_over(epoch_end);
}

EpochStats TorchTrainer::stats() const {
  std::lock_guard<std::mutex> l(lock_);
  return last_;
}

int64_t TorchTrainer::epochs_done() const {
  std::lock_guard<std::mutex> l(lock_);
  return epochs_done_;
}

bool TorchTrainer::finished() const {
  return epochs_done() >= epochs_;
}

}  // namespace nns::trainer
