// SPDX-License-Identifier: LGPL-2.1-only
#include "core/nns_conf.h"

#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>

#include "core/tensor_info.h"

#ifndef NNS_DEFAULT_CONF
#define NNS_DEFAULT_CONF "/etc/nnstreamer.ini"
#endif
#ifndef NNS_INSTALL_SUBPLUGIN_DIR
#define NNS_INSTALL_SUBPLUGIN_DIR "/usr/local/lib/nnstreamer"
#endif

namespace nns {
namespace {

struct KindInfo {
  std::string_view dir;      // folder name under /usr/lib/nnstreamer
  std::string_view prefix;   // file-name prefix
  std::string_view env;      // environment variable
  std::string_view group;    // ini group
  std::string_view key;      // ini key
  std::string_view alt_key;  // accepted spelling as well ("" if none)
};

const KindInfo &kind_info(SubpluginKind k) {
  static const KindInfo kInfos[] = {
      {"filters", "libnnstreamer_filter_", "NNSTREAMER_FILTERS", "filter", "filters", ""},
      {"decoders", "libnnstreamer_decoder_", "NNSTREAMER_DECODERS", "decoder", "decoders", ""},
      {"converters", "libnnstreamer_converter_", "NNSTREAMER_CONVERTERS", "converter", "converters",
       ""},
      {"customfilters", "", "NNSTREAMER_CUSTOMFILTERS", "filter", "customfilters", ""},
      {"trainers", "libnnstreamer_trainer_", "NNSTREAMER_TRAINERS", "trainer", "trainers",
       "trainer"},
  };
  return kInfos[static_cast<int>(k)];
}

bool is_regular(const std::string &p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool is_symlink(const std::string &p) {
  struct stat st {};
  return ::lstat(p.c_str(), &st) == 0 && S_ISLNK(st.st_mode);
}

std::string read_text(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Normalises a folder for duplicate detection: no trailing '/'.
std::string norm_dir(std::string d) {
  while (d.size() > 1 && d.back() == '/') d.pop_back();
  return d;
}

std::mutex g_mutex;
std::vector<std::unique_ptr<Conf>> g_all;  // every configuration ever loaded (kept alive)
std::atomic<const Conf *> g_current{nullptr};

const char *process_env(const char *name) {
  return std::getenv(name);
}

const Conf &load_current() {
  std::string path;
  if (const char *e = std::getenv("NNSTREAMER_CONF"); e && is_regular(e))
    path = e;
  else if (is_regular(NNS_DEFAULT_CONF))
    path = NNS_DEFAULT_CONF;
  auto c = std::make_unique<Conf>(Conf::load(path, process_env));
  const Conf *p = c.get();
  g_all.push_back(std::move(c));
  g_current.store(p, std::memory_order_release);
  return *p;
}

}  // namespace

std::string_view kind_dir_name(SubpluginKind k) {
  return kind_info(k).dir;
}
std::string_view kind_prefix(SubpluginKind k) {
  return kind_info(k).prefix;
}

bool parse_bool(std::string_view s, bool def) {
  std::string t = trim(s);
  if (t.empty()) return def;
  char c = static_cast<char>(std::tolower(static_cast<unsigned char>(t[0])));
  if (c == '1' || c == 't' || c == 'y') return true;
  if (c == '0' || c == 'f' || c == 'n') return false;
  if (t.size() >= 2 && c == 'o') {
    char d = static_cast<char>(std::tolower(static_cast<unsigned char>(t[1])));
    if (d == 'n') return true;
    if (d == 'f') return false;
  }
  return def;
}

std::map<std::string, std::map<std::string, std::string>> Conf::parse_ini(std::string_view text) {
  std::map<std::string, std::map<std::string, std::string>> out;
  std::string group;
  std::size_t pos = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string line = trim(text.substr(pos, end - pos));
    pos = end + 1;
    if (line.empty() || line[0] == '#' || line[0] == ';') continue;
    if (line.front() == '[') {
      std::size_t close = line.find(']');
      group = trim(line.substr(1, close == std::string::npos ? std::string::npos : close - 1));
      continue;
    }
    std::size_t eq = line.find('=');
    if (eq == std::string::npos || group.empty()) continue;
    std::string key = trim(line.substr(0, eq));
    if (!key.empty()) out[group][key] = trim(line.substr(eq + 1));
  }
  return out;
}

Conf Conf::load(const std::string &path, EnvFn env) {
  Conf c;
  c.env_ = env ? std::move(env) : EnvFn([](const char *) -> const char * { return nullptr; });
  if (!path.empty() && is_regular(path)) {
    c.path_ = path;
    c.ini_ = parse_ini(read_text(path));
  }
  auto raw = [&](std::string_view g, std::string_view k) -> const std::string * {
    auto gi = c.ini_.find(std::string(g));
    if (gi == c.ini_.end()) return nullptr;
    auto ki = gi->second.find(std::string(k));
    return ki == gi->second.end() ? nullptr : &ki->second;
  };
  // Without any file nothing disables the environment, so honour it.
  const std::string *ev = raw("common", "enable_envvar");
  c.env_enabled_ = c.path_.empty() ? true : parse_bool(ev ? *ev : "", false);
  const std::string *sl = raw("common", "enable_symlink");
  c.symlinks_ = parse_bool(sl ? *sl : "", false);
  return c;
}

const Conf &Conf::get() {
  if (const Conf *p = g_current.load(std::memory_order_acquire)) return *p;
  std::lock_guard<std::mutex> lock(g_mutex);
  if (const Conf *p = g_current.load(std::memory_order_acquire)) return *p;
  return load_current();
}

void Conf::reload() {
  std::lock_guard<std::mutex> lock(g_mutex);
  load_current();
}

std::optional<std::string> Conf::value(std::string_view group, std::string_view key) const {
  if (env_enabled_) {
    std::string name = "NNSTREAMER_" + std::string(group) + "_" + std::string(key);
    if (const char *v = env_(name.c_str())) return std::string(v);
  }
  auto gi = ini_.find(std::string(group));
  if (gi == ini_.end()) return std::nullopt;
  auto ki = gi->second.find(std::string(key));
  if (ki == gi->second.end()) return std::nullopt;
  return ki->second;
}

bool Conf::bool_value(std::string_view group, std::string_view key, bool def) const {
  auto v = value(group, key);
  return v ? parse_bool(*v, def) : def;
}

std::vector<std::string> Conf::framework_priority(std::string_view ext) const {
  while (!ext.empty() && ext.front() == '.') ext.remove_prefix(1);
  auto v = value("filter", "framework_priority_" + std::string(ext));
  if (!v) return {};
  std::vector<std::string> out;
  for (auto &s : split(*v, ",")) {
    if (!s.empty()) out.push_back(s);
  }
  return out;
}

std::vector<std::string> Conf::subplugin_dirs(SubpluginKind k) const {
  const KindInfo &ki = kind_info(k);
  std::vector<std::string> out;
  auto add_list = [&](std::string_view list) {
    for (auto &d : split(list, ":")) {
      if (d.empty()) continue;
      std::string n = norm_dir(d);
      if (std::find(out.begin(), out.end(), n) == out.end()) out.push_back(n);
    }
  };
  if (env_enabled_) {
    if (const char *e = env_(std::string(ki.env).c_str())) add_list(e);
  }
  auto gi = ini_.find(std::string(ki.group));
  if (gi != ini_.end()) {
    auto it = gi->second.find(std::string(ki.key));
    if (it == gi->second.end() && !ki.alt_key.empty())
      it = gi->second.find(std::string(ki.alt_key));
    if (it != gi->second.end()) add_list(it->second);
  }
  add_list("/usr/lib/nnstreamer/" + std::string(ki.dir));
  add_list(std::string(NNS_INSTALL_SUBPLUGIN_DIR) + "/" + std::string(ki.dir));
  return out;
}

std::vector<SubpluginFile> Conf::subplugins(SubpluginKind k) const {
  namespace fs = std::filesystem;
  const std::string_view prefix = kind_prefix(k);
  std::vector<SubpluginFile> out;
  for (const auto &dir : subplugin_dirs(k)) {
    std::error_code ec;
    std::vector<SubpluginFile> here;
    for (const auto &entry : fs::directory_iterator(dir, ec)) {
      std::string file = entry.path().filename().string();
      if (file.size() <= prefix.size() + kSubpluginSuffix.size()) continue;
      if (file.compare(0, prefix.size(), prefix) != 0) continue;
      if (!file.ends_with(kSubpluginSuffix)) continue;
      std::string full = entry.path().string();
      if (!is_regular(full) || (!symlinks_ && is_symlink(full))) continue;
      std::string name =
          file.substr(prefix.size(), file.size() - prefix.size() - kSubpluginSuffix.size());
      bool seen = std::any_of(out.begin(), out.end(), [&](auto &s) { return s.name == name; });
      if (!seen) here.push_back({name, full});
    }
    std::sort(here.begin(), here.end(), [](auto &a, auto &b) { return a.name < b.name; });
    out.insert(out.end(), here.begin(), here.end());
  }
  return out;
}

std::optional<std::string> Conf::find_subplugin(SubpluginKind k, std::string_view name) const {
  if (name.empty() || name.find('/') != std::string_view::npos) return std::nullopt;
  std::string file =
      std::string(kind_prefix(k)) + std::string(name) + std::string(kSubpluginSuffix);
  for (const auto &dir : subplugin_dirs(k)) {
    std::string full = dir + "/" + file;
    if (!is_regular(full) || (!symlinks_ && is_symlink(full))) continue;
    return full;
  }
  return std::nullopt;
}

}  // namespace nns
