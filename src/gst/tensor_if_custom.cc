// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/tensor_if_custom.h"

#include <cerrno>
#include <map>
#include <mutex>

namespace nns::gst {
namespace {

std::mutex &lock() {
  static std::mutex m;
  return m;
}
std::map<std::string, IfCustom> &table() {
  static auto *t = new std::map<std::string, IfCustom>();  // never destroyed: safe at exit
  return *t;
}

}  // namespace

std::optional<IfCustom> find_if_custom(const std::string &name) {
  std::lock_guard<std::mutex> l(lock());
  auto it = table().find(name);
  if (it == table().end()) return std::nullopt;
  return it->second;
}

}  // namespace nns::gst

extern "C" int nnstreamer_if_custom_register(const gchar *name, tensor_if_custom func, void *data) {
  if (!name || !*name || !func) return -EINVAL;
  std::lock_guard<std::mutex> l(nns::gst::lock());
  auto [it, inserted] = nns::gst::table().emplace(name, nns::gst::IfCustom{func, data});
  (void)it;
  return inserted ? 0 : -EINVAL;
}

extern "C" int nnstreamer_if_custom_unregister(const gchar *name) {
  if (!name) return -EINVAL;
  std::lock_guard<std::mutex> l(nns::gst::lock());
  return nns::gst::table().erase(name) ? 0 : -EINVAL;
}
