// SPDX-License-Identifier: LGPL-2.1-only
// tensor_trainer's sub-plugins: NNStreamer's GstTensorTrainerFramework tables registered with
// nnstreamer_trainer_probe(), in-process or from libnnstreamer_trainer_<name>.so in the
// `trainers=` folders of nnstreamer.ini / NNSTREAMER_TRAINERS (loaded on demand).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "gst/subplugin_registry.h"
#include "nnstreamer_plugin_api_trainer.h"

namespace nns::gst {

class TrainerRegistry {
 public:
  static TrainerRegistry &instance();
  bool add(const GstTensorTrainerFramework *fw);
  bool remove(std::string_view name);
  const GstTensorTrainerFramework *find(std::string_view name);
  std::vector<std::string> names();
  std::string load_error(std::string_view name);
  // The sub-plugin's own account of its last failure (optional export
  // nns_trainer_subplugin_last_error of the file `fw` came from), or "".
  std::string last_error(const GstTensorTrainerFramework *fw);

 private:
  TrainerRegistry();
  SubpluginRegistry reg_;
};

// The registered name of a table (getFrameworkInfo), "" when it has none.
std::string trainer_name(const GstTensorTrainerFramework *fw);

}  // namespace nns::gst
