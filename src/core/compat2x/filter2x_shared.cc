// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer_filter_shared_model_*: NNStreamer 2.x sub-plugins that honour
// shared-tensor-filter-key keep one model representation ("interpreter") per key, with the list
// of filter instances using it. This is that table: key -> representation + users.
#include <algorithm>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "nnstreamer_plugin_api_filter.h"

namespace {

struct Shared {
  void *interpreter = nullptr;
  std::vector<void *> users;
};

std::mutex &table_mu() {
  static std::mutex *m = new std::mutex();
  return *m;
}
std::map<std::string, Shared> &table() {
  static auto *t = new std::map<std::string, Shared>();
  return *t;
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) void *nnstreamer_filter_shared_model_get(void *instance,
                                                                                const char *key) {
  if (!key) return nullptr;
  std::lock_guard lk(table_mu());
  auto it = table().find(key);
  if (it == table().end()) return nullptr;
  auto &u = it->second.users;
  if (std::find(u.begin(), u.end(), instance) == u.end()) u.push_back(instance);
  return it->second.interpreter;
}

__attribute__((visibility("default"))) void *nnstreamer_filter_shared_model_insert_and_get(
    void *instance, char *key, void *interpreter) {
  if (!instance || !key || !interpreter) return nullptr;
  std::lock_guard lk(table_mu());
  auto [it, inserted] = table().try_emplace(key);
  if (!inserted) return nullptr;
  it->second.interpreter = interpreter;
  it->second.users.push_back(instance);
  return interpreter;
}

__attribute__((visibility("default"))) int nnstreamer_filter_shared_model_remove(
    void *instance, const char *key, void (*free_callback)(void *)) {
  if (!key) return 0;
  void *dead = nullptr;
  {
    std::lock_guard lk(table_mu());
    auto it = table().find(key);
    if (it == table().end()) return 0;
    auto &u = it->second.users;
    u.erase(std::remove(u.begin(), u.end(), instance), u.end());
    if (!u.empty()) return 1;
    dead = it->second.interpreter;
    table().erase(it);
  }
  if (free_callback && dead) free_callback(dead);
  return 1;
}

__attribute__((visibility("default"))) void nnstreamer_filter_shared_model_replace(
    void *instance, const char *key, void *new_interpreter,
    void (*replace_callback)(void *, void *), void (*free_callback)(void *)) {
  (void)instance;
  if (!key) return;
  std::lock_guard lk(table_mu());
  auto it = table().find(key);
  if (it == table().end()) return;
  if (replace_callback)
    for (void *u : it->second.users) replace_callback(u, new_interpreter);
  if (free_callback && it->second.interpreter != new_interpreter)
    free_callback(it->second.interpreter);
  it->second.interpreter = new_interpreter;
}

}  // extern "C"
