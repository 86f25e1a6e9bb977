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
                           int64_t num_training, int64_t num_validation, int64_t epochs)
    : cfg_(cfg),
      in_shapes_(std::move(inputs)),
      label_shapes_(std::move(labels)),
      num_training_(num_training),
      num_validation_(num_validation),
      epochs_(epochs) {
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
  for (const auto &s : in_shapes_) in_batch_.push_back(batch_of(s));
  for (const auto &s : label_shapes_) label_batch_.push_back(batch_of(s));
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

void TorchTrainer::flush(bool training) {
  if (fill_ == 0) return;
  const int64_t n = fill_;
  fill_ = 0;
  std::vector<torch::Tensor> ins;
  for (auto &b : in_batch_) ins.push_back(b.narrow(0, 0, n));
  torch::Tensor label = label_batch_[0].narrow(0, 0, n).reshape({n, -1});
  module_.train(training);
  std::optional<torch::NoGradGuard> no_grad;
  if (!training) no_grad.emplace();
  if (training) opt_->zero_grad();
  torch::Tensor out = forward(ins).reshape({n, -1});
  torch::Tensor target;  // class indices, for cross entropy and accuracy
  if (label.size(1) == out.size(1) && out.size(1) > 1)
    target = label.argmax(1);
  else
    target = label.reshape({n}).to(torch::kLong);
  torch::Tensor loss = cfg_.loss == "mse" ? torch::mse_loss(out, label.to(out.scalar_type()))
                                          : torch::nn::functional::cross_entropy(out, target);
  if (training) {
    loss.backward();
    opt_->step();
  }
  const double correct = out.size(1) > 1 ? out.argmax(1).eq(target).sum().item<double>() : 0.0;
  (training ? loss_sum_ : vloss_sum_) += loss.item<double>() * static_cast<double>(n);
  (training ? correct_ : vcorrect_) += correct;
}

bool TorchTrainer::push(const std::vector<const void *> &tensors) {
  if (finished()) return false;
  // libtorch's thread count is per calling thread: set it in the thread that trains.
  if (cfg_.num_threads > 0 && at::get_num_threads() != cfg_.num_threads)
    at::set_num_threads(static_cast<int>(cfg_.num_threads));
  const bool training = in_epoch_ < num_training_;
  if (in_epoch_ == num_training_) flush(true);  // the last partial training batch
  std::size_t k = 0;
  for (std::size_t i = 0; i < in_shapes_.size(); ++i, ++k)
    std::memcpy(static_cast<char *>(in_batch_[i].data_ptr()) + fill_ * in_shapes_[i].bytes,
                tensors[k], in_shapes_[i].bytes);
  for (std::size_t i = 0; i < label_shapes_.size(); ++i, ++k)
    std::memcpy(static_cast<char *>(label_batch_[i].data_ptr()) + fill_ * label_shapes_[i].bytes,
                tensors[k], label_shapes_[i].bytes);
  if (++fill_ == cfg_.batch_size) flush(training);
  if (++in_epoch_ < num_training_ + num_validation_) return false;
  flush(training);
  auto per = [](double v, int64_t n) { return n > 0 ? v / static_cast<double>(n) : 0.0; };
  last_ = {per(loss_sum_, num_training_), per(correct_, num_training_),
           per(vloss_sum_, num_validation_), per(vcorrect_, num_validation_)};
  loss_sum_ = correct_ = vloss_sum_ = vcorrect_ = 0;
  in_epoch_ = 0;
  ++epochs_done_;
  return true;
}

void TorchTrainer::save(const std::string &path) {
  module_.eval();
  module_.save(path);
}

}  // namespace nns::trainer
