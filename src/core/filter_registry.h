// SPDX-License-Identifier: LGPL-2.1-only
// Filter back-end registry (GStreamer-free, shared by tensor_filter and the single-shot API).
//
// A framework name resolves to a back end table (nns_filter_backend_i) that is either built
// in (custom, custom-easy, cpp, or one an application adds) or loaded from
// libnnstreamer_filter_<name>.so in the configured folders. Loaded modules are cached for
// the life of the process (never dlclose()d: runtimes such as ONNX Runtime or libtorch do not
// survive being unloaded).
//
// framework=auto picks a back end from the model file extension: nnstreamer.ini's
// framework_priority_<ext> first, then NNStreamer's table (.tflite -> tensorflow-lite,
// .pt -> pytorch, .onnx -> onnxruntime then opencv, .so -> custom, ...). Aliases such as
// tensorflow-lite resolve through the ini's [<alias>] subplugin_priority=, then our TFLite back
// end (libnnstreamer_filter_tensorflow2-lite.so, for every tflite alias), then
// framework_priority_tflite (default: armnn), and [filter-aliases] <alias>=<name>.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "nns_filter_backend.h"

namespace nns {
namespace compat2x {
struct Filter2x;
}

// What the registry needs from the configuration (nnstreamer.ini + environment).
class FilterConf {
 public:
  virtual ~FilterConf() = default;
  // Folders searched for libnnstreamer_filter_<name>.so, in order.
  virtual std::vector<std::string> filter_dirs() const = 0;
  // framework_priority_<ext> (ext without the dot, lower case); empty when not set.
  virtual std::vector<std::string> framework_priority(const std::string &ext) const = 0;
  // Any ini value, "" when absent.
  virtual std::string value(const std::string &group, const std::string &key) const = 0;
};

// The process configuration (nns::Conf::get(): nnstreamer.ini + NNSTREAMER_* environment).
// Call nns::Conf::reload() after changing NNSTREAMER_CONF to make filters see the new file.
std::unique_ptr<FilterConf> current_filter_conf();

struct BackendRef {
  const nns_filter_backend_i *iface = nullptr;
  std::string origin;  // "built-in", the .so path, or where an NNStreamer 2.x sub-plugin came from
  explicit operator bool() const { return iface != nullptr; }
};

class FilterRegistry {
 public:
  static FilterRegistry &get();

  // Adds an in-process back end (replaces one of the same name). The table must stay valid
  // until remove_builtin(). Throws Error(kSettings) when the table is incomplete or has an
  // api_version outside NNS_FILTER_BACKEND_API_VERSION_MIN..NNS_FILTER_BACKEND_API_VERSION
  // (older tables are used through a full copy whose newer fields are NULL).
  void add_builtin(const nns_filter_backend_i *iface);
  void remove_builtin(const std::string &name);

  // The back end called exactly `name`: built in, an NNStreamer 2.x sub-plugin registered
  // with nnstreamer_filter_probe(), or libnnstreamer_filter_<name>.so from conf.filter_dirs()
  // (our entry point, or a 2.x sub-plugin whose constructor registers `name`). When both kinds
  // provide `name`, [filter] subplugin_abi_priority decides (prefers_2x()). Returns an empty
  // ref when nothing provides it; throws Error(kLibrary) when a file exists but cannot be used
  // (dlopen error, no entry point and no registration, api_version mismatch, a rejected 2.x
  // probe), naming the file and the reason.
  BackendRef find(const std::string &name, const FilterConf &conf);
  // The NNStreamer 2.x sub-plugin `name` (registered, or loaded from the folders), also
  // through [<name>] subplugin_priority and [filter-aliases]; nullptr if none.
  const compat2x::Filter2x *find_2x(const std::string &name, const FilterConf &conf);
  // [filter] subplugin_abi_priority: "nnstreamer-cpp" (default) or "nnstreamer-2".
  static bool prefers_2x(const FilterConf &conf);

  // Resolves framework= (a name, an alias, or "auto"/"" with the model files). Throws
  // Error(kNotFound): "framework 'X' is not available: no libnnstreamer_filter_X.so in
  // <dirs>" (listing every candidate tried), or a detection error for auto.
  BackendRef resolve(const std::string &framework, const std::vector<std::string> &models,
                     const FilterConf &conf);

  // Candidate framework names for framework=auto, best first (may name unavailable ones).
  static std::vector<std::string> auto_candidates(const std::vector<std::string> &models,
                                                  const FilterConf &conf);
  // Candidate names for an explicit framework name (the name, then its alias targets).
  static std::vector<std::string> name_candidates(const std::string &framework,
                                                  const FilterConf &conf);

  // Loads one back-end file (cached by path); throws Error(kLibrary) as find() does.
  // `name`: the framework the file is expected to provide (its file name part).
  struct Loaded {
    const nns_filter_backend_i *iface = nullptr;
    bool is_2x = false;  // an NNStreamer 2.x sub-plugin (bridged)
  };
  Loaded load_file(const std::string &path, const std::string &name);

  // Every usable name: built-ins plus libnnstreamer_filter_*.so in the folders (not loaded).
  std::vector<std::string> available(const FilterConf &conf);

 private:
  FilterRegistry();
  // Older tables as full ones (copies kept in upgraded_); mu_ held.
  const nns_filter_backend_i *upgrade(const nns_filter_backend_i *t);
  std::mutex mu_;
  std::vector<std::unique_ptr<nns_filter_backend_i>> upgraded_;
  std::unordered_map<std::string, const nns_filter_backend_i *> builtin_;
  std::unordered_map<std::string, Loaded> loaded_;  // by path
};

// Checks a table before use; throws Error(kLibrary) naming `origin`.
void validate_backend_table(const nns_filter_backend_i *iface, const std::string &origin);

// Built-in back ends (src/core/filter_custom*.cc, filter_cpp.cc).
const nns_filter_backend_i *builtin_custom_backend();
const nns_filter_backend_i *builtin_custom_easy_backend();
const nns_filter_backend_i *builtin_cpp_backend();

}  // namespace nns
