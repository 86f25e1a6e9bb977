// SPDX-License-Identifier: LGPL-2.1-only
#include "core/filter_registry.h"

#include <dlfcn.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>

#include "core/compat2x/filter2x.h"
#include "core/error.h"
#include "core/filter_compat_async.h"
#include "core/nns_conf.h"
#include "core/tensor_info.h"

namespace nns {
namespace {

constexpr const char *kPrefix = "libnnstreamer_filter_";
constexpr const char *kSuffix = ".so";

std::string lower(std::string s) {
  for (char &c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The registry's view of nns::Conf (nnstreamer.ini + environment).
class ConfView final : public FilterConf {
 public:
  explicit ConfView(const Conf &c) : c_(c) {}
  std::vector<std::string> filter_dirs() const override {
    return c_.subplugin_dirs(SubpluginKind::kFilter);
  }
  std::vector<std::string> framework_priority(const std::string &ext) const override {
    return c_.framework_priority(ext);
  }
  std::string value(const std::string &group, const std::string &key) const override {
    return c_.value(group, key).value_or("");
  }

 private:
  const Conf &c_;
};

bool is_file(const std::string &p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}
bool is_dir(const std::string &p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

std::string extension_of(const std::string &path) {
  auto slash = path.find_last_of('/');
  auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  return lower(path.substr(dot + 1));
}

void push_unique(std::vector<std::string> &v, const std::string &s) {
  if (!s.empty() && std::find(v.begin(), v.end(), s) == v.end()) v.push_back(s);
}

bool is_tflite_alias(const std::string &n) {
  return n == "tensorflow-lite" || n == "tensorflow1-lite" || n == "tensorflow2-lite" ||
         n == "tflite";
}

// NNStreamer's detection table (SPEC.md section 3) plus .onnx.
std::vector<std::string> defaults_for_ext(const std::string &ext) {
  static const std::map<std::string, std::vector<std::string>> table = {
      {"tflite", {"tensorflow-lite"}},
      {"pb", {"tensorflow"}},
      {"pt", {"pytorch"}},
      {"dlc", {"snpe"}},
      {"py", {"python3"}},
      {"graph", {"movidius-ncsdk2"}},
      {"ini", {"nntrainer"}},
      {"circle", {"nnfw"}},
      {"so", {"custom"}},
      {"dylib", {"custom"}},
      {"bin", {"openvino"}},
      {"xml", {"openvino"}},
      {"tvn", {"trix-engine"}},
      {"nb", {"vivante"}},
      {"gguf", {"llamacpp"}},
      {"onnx", {"onnxruntime", "opencv"}},
  };
  auto it = table.find(ext);
  return it == table.end() ? std::vector<std::string>{} : it->second;
}

}  // namespace

std::unique_ptr<FilterConf> current_filter_conf() {
  return std::make_unique<ConfView>(Conf::get());
}

void validate_backend_table(const nns_filter_backend_i *t, const std::string &origin) {
  if (!t) fail(ErrorKind::kLibrary, origin + ": nns_filter_backend_entry() returned NULL");
  if (t->api_version < NNS_FILTER_BACKEND_API_VERSION_MIN ||
      t->api_version > NNS_FILTER_BACKEND_API_VERSION)
    fail(ErrorKind::kLibrary,
         origin + " was built for filter back-end API version " + std::to_string(t->api_version) +
             ", but this nnstreamer-cpp needs version " +
             std::to_string(NNS_FILTER_BACKEND_API_VERSION_MIN) + " to " +
             std::to_string(NNS_FILTER_BACKEND_API_VERSION) + "; rebuild the back end");
  if (!t->name || !*t->name) fail(ErrorKind::kLibrary, origin + ": back end has no name");
  if (!t->open || !t->close || !t->invoke)
    fail(ErrorKind::kLibrary, origin + ": back end '" + t->name +
                                  "' lacks a mandatory function (open, close or invoke)");
}

const nns_filter_backend_i *FilterRegistry::upgrade(const nns_filter_backend_i *t) {
  if (t->api_version >= NNS_FILTER_BACKEND_API_VERSION) return t;
  // A version 1 table ends at check_accelerator: copy that much into a full table whose
  // newer fields are NULL, so the host may read every field of every table.
  auto full = std::make_unique<nns_filter_backend_i>();
  std::memset(full.get(), 0, sizeof *full);
  std::memcpy(full.get(), t, offsetof(nns_filter_backend_i, invoke_async));
  upgraded_.push_back(std::move(full));
  return upgraded_.back().get();
}

FilterRegistry &FilterRegistry::get() {
  static FilterRegistry *r = new FilterRegistry();  // never destroyed: back ends outlive exit
  return *r;
}

FilterRegistry::FilterRegistry() {
  for (auto *t : {builtin_custom_backend(), builtin_custom_easy_backend(), builtin_cpp_backend()})
    builtin_[t->name] = t;
}

void FilterRegistry::add_builtin(const nns_filter_backend_i *iface) {
  validate_backend_table(iface, "built-in back end");
  std::lock_guard lk(mu_);
  builtin_[iface->name] = upgrade(iface);
}

void FilterRegistry::remove_builtin(const std::string &name) {
  std::lock_guard lk(mu_);
  builtin_.erase(name);
}

FilterRegistry::Loaded FilterRegistry::load_file(const std::string &path, const std::string &name) {
  auto &reg2x = compat2x::Filter2xRegistry::get();
  std::lock_guard lk(mu_);
  if (auto it = loaded_.find(path); it != loaded_.end()) {
    if (!it->second.is_2x) return it->second;
    // A 2.x file whose sub-plugin later called nnstreamer_filter_exit() provides nothing.
    const compat2x::Filter2x *f = reg2x.find(name);
    return f ? Loaded{&f->iface, true} : Loaded{};
  }
  promote_filter_api();  // a 2.x constructor calls nnstreamer_filter_probe() of this library
  uint64_t mark = reg2x.mark();
  dlerror();
  void *h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    const char *e = dlerror();
    fail(ErrorKind::kLibrary, "cannot load " + path + ": " + (e ? e : "unknown dlopen error"));
  }
  auto probes = reg2x.since(mark);
  auto entry = reinterpret_cast<nns_filter_backend_entry_fn>(dlsym(h, NNS_FILTER_BACKEND_ENTRY));
  if (!entry) {
    // NNStreamer 2.x: the constructor registered the sub-plugin (or tried to).
    bool registered_any = false;
    for (auto &p : probes) registered_any = registered_any || p.accepted;
    if (const compat2x::Filter2x *f = reg2x.find(name);
        f && std::any_of(probes.begin(), probes.end(),
                         [&](auto &p) { return p.accepted && p.text == name; })) {
      reg2x.set_origin(name, path);
      loaded_[path] = Loaded{&f->iface, true};  // the handle stays open (the table lives there)
      return loaded_[path];
    }
    std::string why;
    for (auto &p : probes)
      if (!p.accepted) why += (why.empty() ? "" : "; ") + p.text;
    if (!registered_any) dlclose(h);
    if (!why.empty())
      fail(ErrorKind::kLibrary, path + ": the NNStreamer 2.x sub-plugin failed its probe: " + why);
    if (registered_any) {
      std::string got;
      for (auto &p : probes)
        if (p.accepted) got += (got.empty() ? "'" : ", '") + p.text + "'";
      fail(ErrorKind::kLibrary, path + " registered the NNStreamer 2.x sub-plugin " + got +
                                    ", not '" + name + "' as its file name says");
    }
    fail(ErrorKind::kLibrary, path + " is not a filter back end: it does not export " +
                                  NNS_FILTER_BACKEND_ENTRY +
                                  "() and registered no NNStreamer 2.x sub-plugin "
                                  "(nnstreamer_filter_probe) when loaded");
  }
  const nns_filter_backend_i *t = entry();
  try {
    validate_backend_table(t, path);
  } catch (...) {
    dlclose(h);
    throw;
  }
  t = upgrade(t);
  loaded_[path] = Loaded{t, false};  // the handle stays open for the life of the process
  return loaded_[path];
}

bool FilterRegistry::prefers_2x(const FilterConf &conf) {
  std::string v = lower(trim(conf.value("filter", "subplugin_abi_priority")));
  return v == "nnstreamer-2" || v == "nnstreamer2" || v == "2.x" || v == "2x";
}

BackendRef FilterRegistry::find(const std::string &name, const FilterConf &conf) {
  const bool want_2x = prefers_2x(conf);
  BackendRef ours, theirs;
  {
    std::lock_guard lk(mu_);
    if (auto it = builtin_.find(name); it != builtin_.end()) ours = {it->second, "built-in"};
  }
  if (const compat2x::Filter2x *f = compat2x::Filter2xRegistry::get().find(name))
    theirs = {&f->iface, f->origin};
  auto settled = [&] { return want_2x ? bool(theirs) : bool(ours); };
  if (!settled() && !name.empty() && name.find('/') == std::string::npos) {
    std::string first_error;
    for (const auto &dir : conf.filter_dirs()) {
      std::string path = dir + "/" + kPrefix + name + kSuffix;
      if (!is_file(path)) continue;
      Loaded l;
      try {
        l = load_file(path, name);
      } catch (const Error &e) {
        if (first_error.empty()) first_error = e.what();
        continue;
      }
      if (l.is_2x && !theirs) theirs = {l.iface, path};
      if (!l.is_2x && l.iface && !ours) ours = {l.iface, path};
      if (settled()) break;
    }
    if (!ours && !theirs && !first_error.empty()) fail(ErrorKind::kLibrary, first_error);
  }
  if (want_2x) return theirs ? theirs : ours;
  return ours ? ours : theirs;
}

const compat2x::Filter2x *FilterRegistry::find_2x(const std::string &name, const FilterConf &conf) {
  auto &reg2x = compat2x::Filter2xRegistry::get();
  auto one = [&](const std::string &n) -> const compat2x::Filter2x * {
    if (n.empty()) return nullptr;
    if (auto *f = reg2x.find(n)) return f;
    if (n.find('/') != std::string::npos) return nullptr;
    for (const auto &dir : conf.filter_dirs()) {
      std::string path = dir + "/" + kPrefix + n + kSuffix;
      if (!is_file(path)) continue;
      try {
        if (load_file(path, n).is_2x) return reg2x.find(n);
      } catch (const Error &) {
      }
    }
    return nullptr;
  };
  if (auto *f = one(name)) return f;
  for (const char *key : {"subplugin_priority", ""}) {
    std::string list = *key ? conf.value(name, key) : conf.value("filter-aliases", name);
    for (auto &n : split(list, ","))
      if (auto *f = one(trim(n))) return f;
  }
  return nullptr;
}

std::vector<std::string> FilterRegistry::name_candidates(const std::string &framework,
                                                         const FilterConf &conf) {
  std::vector<std::string> out;
  push_unique(out, framework);
  for (auto &n : split(conf.value(framework, "subplugin_priority"), ",")) push_unique(out, n);
  push_unique(out, trim(conf.value("filter-aliases", framework)));
  if (is_tflite_alias(framework)) {
    // Our TFLite back end is built as upstream's libnnstreamer_filter_tensorflow2-lite.so;
    // every alias reaches it first, armnn stays the fallback.
    push_unique(out, "tensorflow2-lite");
    for (auto &n : conf.framework_priority("tflite"))
      if (!is_tflite_alias(n)) push_unique(out, n);
    push_unique(out, "armnn");
  }
  return out;
}

std::vector<std::string> FilterRegistry::auto_candidates(const std::vector<std::string> &models,
                                                         const FilterConf &conf) {
  std::vector<std::string> base;
  if (models.size() == 1) {
    if (is_dir(models[0])) {
      base.push_back("nnfw");
    } else {
      std::string ext = extension_of(models[0]);
      if (!ext.empty()) {
        for (auto &n : conf.framework_priority(ext)) push_unique(base, n);
        for (auto &n : defaults_for_ext(ext)) push_unique(base, n);
      }
    }
  } else if (models.size() == 2) {
    std::string e0 = extension_of(models[0]), e1 = extension_of(models[1]);
    if (e0 == "pb" && e1 == "pb" && models[0] != models[1]) base.push_back("caffe2");
    if ((e0 == "so" && e1 == "nb") || (e0 == "nb" && e1 == "so")) base.push_back("vivante");
  }
  std::vector<std::string> out;
  for (auto &b : base)
    for (auto &n : name_candidates(b, conf)) push_unique(out, n);
  return out;
}

BackendRef FilterRegistry::resolve(const std::string &framework,
                                   const std::vector<std::string> &models, const FilterConf &conf) {
  std::string fw = trim(framework);
  bool is_auto = fw.empty() || lower(fw) == "auto";  // "AutO" too, as NNStreamer
  std::vector<std::string> cands;
  if (is_auto) {
    if (models.empty())
      fail(ErrorKind::kSettings,
           "framework=auto needs a model to detect the framework from; set model= or framework=");
    cands = auto_candidates(models, conf);
    if (cands.empty())
      fail(ErrorKind::kSettings, "framework=auto cannot tell which framework reads model '" +
                                     join(models, ",") +
                                     "' from its extension; set framework= explicitly");
  } else {
    cands = name_candidates(fw, conf);
  }
  for (const auto &c : cands)
    if (BackendRef r = find(c, conf)) return r;

  std::vector<std::string> files;
  for (auto &c : cands) files.push_back(std::string(kPrefix) + c + kSuffix);
  std::string dirs = join(conf.filter_dirs(), ", ");
  if (dirs.empty()) dirs = "(no folders configured)";
  std::string tried = files.size() == 1 ? "no " + files[0] : "none of " + join(files, ", ");
  if (is_auto)
    fail(ErrorKind::kNotFound,
         "framework=auto: model '" + join(models, ",") + "' needs " +
             (cands.size() == 1 ? "framework '" + cands[0] + "'" : "one of " + join(cands, ", ")) +
             ", which is not available: " + tried + " in " + dirs);
  fail(ErrorKind::kNotFound, "framework '" + fw + "' is not available: " + tried + " in " + dirs);
}

std::vector<std::string> FilterRegistry::available(const FilterConf &conf) {
  std::vector<std::string> out;
  {
    std::lock_guard lk(mu_);
    for (const char *n : {"custom", "custom-easy", "cpp"})
      if (builtin_.count(n)) out.push_back(n);
    std::vector<std::string> extra;
    for (auto &[n, t] : builtin_)
      if (n != "custom" && n != "custom-easy" && n != "cpp") extra.push_back(n);
    for (auto &n : compat2x::Filter2xRegistry::get().names()) extra.push_back(n);
    std::sort(extra.begin(), extra.end());
    for (auto &n : extra) push_unique(out, n);
  }
  std::vector<std::string> found;
  std::error_code ec;
  for (const auto &dir : conf.filter_dirs()) {
    for (auto it = std::filesystem::directory_iterator(dir, ec);
         !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
      std::string f = it->path().filename().string();
      std::size_t pl = std::char_traits<char>::length(kPrefix);
      if (f.size() > pl + 3 && f.compare(0, pl, kPrefix) == 0 &&
          f.compare(f.size() - 3, 3, kSuffix) == 0)
        found.push_back(f.substr(pl, f.size() - pl - 3));
    }
    ec.clear();
  }
  std::sort(found.begin(), found.end());
  for (auto &n : found) push_unique(out, n);
  return out;
}

}  // namespace nns
