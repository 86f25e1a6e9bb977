// SPDX-License-Identifier: LGPL-2.1-only
#include <strings.h>

#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "core/compat2x/filter2x.h"
#include "core/filter_registry.h"

namespace nns::compat2x {
namespace {

bool is_version(uint64_t v, uint64_t layout) {
  return (v & 0xFFFFFFFFFFFF0000ULL) == (GST_TENSOR_FILTER_FRAMEWORK_BASE | (layout << 16));
}

std::string hex64(uint64_t v) {
  char b[32];
  std::snprintf(b, sizeof b, "0x%016" PRIx64, v);
  return b;
}

}  // namespace

Filter2xRegistry &Filter2xRegistry::get() {
  static Filter2xRegistry *r = new Filter2xRegistry();  // tables outlive static destruction
  return *r;
}

std::string Filter2xRegistry::check(const GstTensorFilterFramework *fw,
                                    GstTensorFilterFrameworkInfo &info) const {
  if (!fw) return "nnstreamer_filter_probe() was given NULL";
  std::memset(&info, 0, sizeof info);
  if (is_version(fw->version, 0)) {
    if (!fw->name || !*fw->name) return "version 0 table without a name";
    std::string n = fw->name;
    if (!fw->invoke_NN) return "version 0 sub-plugin '" + n + "' has no invoke_NN";
    if (!(fw->getInputDimension && fw->getOutputDimension) && !fw->setInputDimension)
      return "version 0 sub-plugin '" + n +
             "' needs getInputDimension and getOutputDimension, or setInputDimension";
    info.name = fw->name;
    info.allow_in_place = fw->allow_in_place;
    info.allocate_in_invoke = fw->allocate_in_invoke;
    info.run_without_model = fw->run_without_model;
    info.verify_model_path = fw->verify_model_path;
    info.statistics = fw->statistics;
    return {};
  }
  if (is_version(fw->version, 1)) {
    if (!fw->invoke || !fw->getFrameworkInfo || !fw->getModelInfo || !fw->eventHandler)
      return "version 1 table lacks a mandatory callback (invoke, getFrameworkInfo, "
             "getModelInfo and eventHandler are mandatory)";
    GstTensorFilterProperties prop;
    std::memset(&prop, 0, sizeof prop);
    int rc = fw->getFrameworkInfo(fw, &prop, nullptr, &info);
    if (rc != 0) return "version 1 getFrameworkInfo() returned " + std::to_string(rc);
    if (!info.name || !*info.name) return "version 1 getFrameworkInfo() gave no name";
    return {};
  }
  return "version word " + hex64(fw->version) +
         " is not NNStreamer's filter sub-plugin ABI (0xdeafdead0000xxxx for version 0, "
         "0xdeafdead0001xxxx for version 1)";
}

void Filter2xRegistry::log(bool accepted, std::string text) {
  log_.push_back({++seq_, ProbeEvent{accepted, std::move(text)}});
  if (log_.size() > 256) log_.erase(log_.begin(), log_.begin() + 128);
}

bool Filter2xRegistry::probe(const GstTensorFilterFramework *fw, std::string *why) {
  GstTensorFilterFrameworkInfo info;
  std::string err = check(fw, info);
  std::lock_guard lk(mu_);
  auto reject = [&](std::string msg) {
    if (why) *why = msg;
    log(false, std::move(msg));
    return false;
  };
  if (!err.empty()) return reject(err);
  std::string name = info.name;
  if (strcasecmp(name.c_str(), "any") == 0 || strcasecmp(name.c_str(), "auto") == 0)
    return reject("the name '" + name + "' is reserved");
  for (auto &e : entries_)
    if (e->registered && e->name == name)
      return reject("a sub-plugin named '" + name + "' is already registered (" + e->origin + ")");
  // The same table probed again after nnstreamer_filter_exit() gets its old entry back.
  Filter2x *entry = nullptr;
  for (auto &e : entries_)
    if (!e->registered && e->fw == fw && e->name == name) entry = e.get();
  if (!entry) {
    auto e = std::make_unique<Filter2x>();
    e->fw = fw;
    e->name = name;
    e->version = is_version(fw->version, 1) ? 1 : 0;
    e->info = info;
    for (int i = 0; info.hw_list && i < info.num_hw; ++i) e->hw.push_back(info.hw_list[i]);
    e->info.hw_list = e->hw.empty() ? nullptr : e->hw.data();
    e->info.name = e->name.c_str();
    if (!bind_bridge(*e))
      return reject("too many NNStreamer 2.x filter sub-plugins (" + std::to_string(kBridgeSlots) +
                    " at most)");
    entries_.push_back(std::move(e));
    entry = entries_.back().get();
  }
  entry->origin = "registered in-process";
  entry->registered = true;
  log(true, name);
  return true;
}

void Filter2xRegistry::exit(const std::string &name) {
  std::lock_guard lk(mu_);
  for (auto &e : entries_)
    if (e->registered && e->name == name) e->registered = false;
}

const Filter2x *Filter2xRegistry::find(const std::string &name) {
  std::lock_guard lk(mu_);
  for (auto &e : entries_)
    if (e->registered && e->name == name) return e.get();
  return nullptr;
}

const Filter2x *Filter2xRegistry::of_bridge(const nns_filter_backend_i *iface) {
  std::lock_guard lk(mu_);
  for (auto &e : entries_)
    if (&e->iface == iface) return e.get();
  return nullptr;
}

std::vector<std::string> Filter2xRegistry::names() {
  std::lock_guard lk(mu_);
  std::vector<std::string> out;
  for (auto &e : entries_)
    if (e->registered) out.push_back(e->name);
  return out;
}

void Filter2xRegistry::set_origin(const std::string &name, const std::string &origin) {
  std::lock_guard lk(mu_);
  for (auto &e : entries_)
    if (e->registered && e->name == name) e->origin = origin;
}

uint64_t Filter2xRegistry::mark() {
  std::lock_guard lk(mu_);
  return seq_;
}

std::vector<Filter2xRegistry::ProbeEvent> Filter2xRegistry::since(uint64_t mark) {
  std::lock_guard lk(mu_);
  std::vector<ProbeEvent> out;
  for (auto &[seq, ev] : log_)
    if (seq > mark) out.push_back(ev);
  return out;
}

void Filter2xRegistry::set_custom_desc(const std::string &name,
                                       std::vector<std::pair<std::string, std::string>> desc) {
  std::lock_guard lk(mu_);
  for (auto &d : desc_)
    if (d.first == name) {
      d.second = std::move(desc);
      return;
    }
  desc_.emplace_back(name, std::move(desc));
}

std::vector<std::pair<std::string, std::string>> Filter2xRegistry::custom_desc(
    const std::string &name) {
  std::lock_guard lk(mu_);
  for (auto &d : desc_)
    if (d.first == name) return d.second;
  return {};
}

}  // namespace nns::compat2x

// ---- C API (nnstreamer_plugin_api_filter.h) -------------------------------------------------

// The shared-model functions (filter2x_shared.cc) are called only by sub-plugins, never by the
// plugin itself: referencing them here makes the linker take that object out of the static
// core library into every library that registers 2.x filters, so they are exported.
__attribute__((used)) static const void *const kSharedModelApi[] = {
    reinterpret_cast<const void *>(&nnstreamer_filter_shared_model_get),
    reinterpret_cast<const void *>(&nnstreamer_filter_shared_model_insert_and_get),
    reinterpret_cast<const void *>(&nnstreamer_filter_shared_model_remove),
    reinterpret_cast<const void *>(&nnstreamer_filter_shared_model_replace),
};

extern "C" {

__attribute__((visibility("default"))) int nnstreamer_filter_probe(GstTensorFilterFramework *tfsp) {
  try {
    std::string why;
    if (nns::compat2x::Filter2xRegistry::get().probe(tfsp, &why)) return 1;
    std::fprintf(stderr, "nnstreamer_filter_probe: %s\n", why.c_str());
  } catch (...) {
  }
  return 0;
}

__attribute__((visibility("default"))) void nnstreamer_filter_exit(const char *name) {
  if (!name) return;
  try {
    nns::compat2x::Filter2xRegistry::get().exit(name);
  } catch (...) {
  }
}

__attribute__((visibility("default"))) const GstTensorFilterFramework *nnstreamer_filter_find(
    const char *name) {
  if (!name) return nullptr;
  try {
    auto conf = nns::current_filter_conf();
    const nns::compat2x::Filter2x *f = nns::FilterRegistry::get().find_2x(name, *conf);
    if (f) return f->fw;
    // One of our back ends (or an alias of one), seen as a version-1 table.
    nns::BackendRef ref;
    try {
      ref = nns::FilterRegistry::get().resolve(name, {}, *conf);
    } catch (...) {
      return nullptr;
    }
    if (!ref) return nullptr;
    if (const auto *bridged = nns::compat2x::Filter2xRegistry::get().of_bridge(ref.iface))
      return bridged->fw;
    return nns::compat2x::framework_of_backend(ref.iface, name);
  } catch (...) {
    return nullptr;
  }
}

__attribute__((visibility("default"))) void nnstreamer_filter_set_custom_property_desc(
    const char *name, const char *prop, ...) {
  if (!name) return;
  std::vector<std::pair<std::string, std::string>> desc;
  va_list ap;
  va_start(ap, prop);
  for (const char *p = prop; p; p = va_arg(ap, const char *)) {
    const char *d = va_arg(ap, const char *);
    if (!d) break;  // a key without description ends the list, as in NNStreamer
    desc.emplace_back(p, d);
  }
  va_end(ap);
  try {
    nns::compat2x::Filter2xRegistry::get().set_custom_desc(name, std::move(desc));
  } catch (...) {
  }
}

}  // extern "C"
