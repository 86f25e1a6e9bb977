// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer.ini reader and sub-plugin search paths (GStreamer-free), same grammar and
// precedence as NNStreamer:
//   - file: $NNSTREAMER_CONF if it names a regular file, else /etc/nnstreamer.ini;
//   - [common] enable_envvar= (default false) lets NNSTREAMER_FILTERS / _DECODERS /
//     _CONVERTERS / _CUSTOMFILTERS / _TRAINERS and NNSTREAMER_<group>_<key> override the file;
//     when no file exists at all, environment variables are honoured (nothing disables them);
//   - [common] enable_symlink= (default false) lets symlinked sub-plugin files be listed;
//   - sub-plugin folders, searched in order: env var, the ini key ([filter] filters=,
//     [decoder] decoders=, [converter] converters=, [filter] customfilters=,
//     [trainer] trainers=), then /usr/lib/nnstreamer/<kind>/ and our install folder.
//   Folder values may list several folders separated by ':'.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nns {

enum class SubpluginKind { kFilter, kDecoder, kConverter, kCustomFilter, kTrainer };

std::string_view kind_dir_name(SubpluginKind k);  // "filters", "decoders", ...
// File-name prefix of a sub-plugin: "libnnstreamer_filter_"; "" for custom filters.
std::string_view kind_prefix(SubpluginKind k);
constexpr std::string_view kSubpluginSuffix = ".so";

struct SubpluginFile {
  std::string name;  // "onnxruntime"
  std::string path;  // "/usr/lib/nnstreamer/filters/libnnstreamer_filter_onnxruntime.so"
};

class Conf {
 public:
  using EnvFn = std::function<const char *(const char *)>;

  // The process-wide configuration, loaded on first use from the environment.
  static const Conf &get();
  // Re-reads the file and environment; later get() calls see the new values. References
  // obtained before stay valid (old configurations are kept alive).
  static void reload();
  // Loads a configuration explicitly (tests). `path` "" means: no file. `env` reads variables.
  static Conf load(const std::string &path, EnvFn env);
  // Parses ini text into group -> key -> value (keys and groups as written, values trimmed).
  static std::map<std::string, std::map<std::string, std::string>> parse_ini(std::string_view text);

  const std::string &path() const { return path_; }  // "" when no file was read
  bool env_enabled() const { return env_enabled_; }
  bool symlinks_enabled() const { return symlinks_; }

  // Folders searched for sub-plugins of `k`, in priority order, without duplicates.
  std::vector<std::string> subplugin_dirs(SubpluginKind k) const;
  // Sub-plugin files found in those folders (first folder wins for a repeated name).
  std::vector<SubpluginFile> subplugins(SubpluginKind k) const;
  // Path of the sub-plugin called `name`, if any folder has it.
  std::optional<std::string> find_subplugin(SubpluginKind k, std::string_view name) const;

  // NNSTREAMER_<group>_<key> (when env is enabled), else the ini value.
  std::optional<std::string> value(std::string_view group, std::string_view key) const;
  // Same, read as a boolean (1/0, true/false, yes/no, on/off; first letters count).
  bool bool_value(std::string_view group, std::string_view key, bool def) const;
  // [filter] framework_priority_<ext> split on ','; `ext` with or without the leading dot.
  std::vector<std::string> framework_priority(std::string_view ext) const;

 private:
  std::string path_;
  bool env_enabled_ = false;
  bool symlinks_ = false;
  std::map<std::string, std::map<std::string, std::string>> ini_;
  EnvFn env_;
};

// Parses NNStreamer's boolean spellings; `def` when empty or unrecognised.
bool parse_bool(std::string_view s, bool def);

}  // namespace nns
