// SPDX-License-Identifier: LGPL-2.1-only
// What the converter and decoder registries share: a name -> table list filled in-process
// (constructor registration) or by loading lib<prefix>_<name>.so on demand from the folders
// nns::Conf gives for a SubpluginKind (the object registers itself from a constructor, or
// exports an entry function returning its table), with the reason of every failed load kept
// for error messages. Loaded objects are never unloaded. Tables are handled as `const void *`;
// SubpluginTraits says how to read and check one kind of table.
#pragma once

#include <gst/gst.h>

#include <cerrno>
#include <cstdarg>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/nns_conf.h"

namespace nns::gst {

struct SubpluginTraits {
  SubpluginKind kind;
  const char *noun;          // "converter", "decoder": used in messages
  const char *entry_symbol;  // optional export returning the table
  const char *(*name_of)(const void *table);
  // Empty when the table is usable, else why not (logged as "<noun> sub-plugin ...").
  std::string (*check)(const void *table);
  void *anchor;                 // address of a function in this object (see promote_self_global)
  GstDebugCategory **category;  // where to log
};

class SubpluginRegistry {
 public:
  explicit SubpluginRegistry(const SubpluginTraits &t) : t_(t) {}

  std::recursive_mutex &mutex() { return mutex_; }  // a loaded constructor re-enters add()

  // add() returns false (and logs why) for an invalid table or a taken name.
  bool add(const void *table);
  bool remove(std::string_view name);
  // Registered table `name`; otherwise loads the file for `name`. Takes the lock.
  const void *find(std::string_view name);
  // Loads every file of the folders once per configuration. Caller holds mutex().
  void load_all_locked();
  // Registered and loadable names, sorted, without duplicates.
  std::vector<std::string> names();
  // Why the last load of `name` failed ("" if none).
  std::string load_error(std::string_view name);
  // `symbol` of the object `table` was loaded from (nullptr when not loaded from a file or
  // the object lacks it): optional extension exports.
  void *file_symbol(const void *table, const char *symbol);
  // Registered tables in registration order. Caller holds mutex().
  const std::vector<std::pair<std::string, const void *>> &tables_locked() const { return tables_; }
  unsigned generation() const { return generation_; }  // bumped on every add/remove

  // Custom-property descriptions (nnstreamer_{decoder,converter}_set_custom_property_desc).
  using PropertyDescs = std::vector<std::pair<std::string, std::string>>;
  // Replaces those of registered sub-plugin `name`; false (nothing kept) when it is not
  // registered. An empty list leaves it without descriptions.
  bool set_property_descs(std::string_view name, PropertyDescs descs);
  // The descriptions of `name`; nullopt when it has none.
  std::optional<PropertyDescs> property_descs(std::string_view name);
  // Collects `prop, desc, prop, desc, ..., NULL` as NNStreamer reads it: the list ends at a NULL
  // property or at a property without a description (which is dropped, with a warning).
  static PropertyDescs collect_descs(const char *owner, const char *prop, va_list ap);

 private:
  const void *lookup_locked(std::string_view name) const;
  void load_file(const std::string &name, const std::string &path);
  void fail_load(const std::string &name, std::string msg);

  SubpluginTraits t_;
  std::recursive_mutex mutex_;
  std::vector<std::pair<std::string, const void *>> tables_;
  std::vector<std::pair<const void *, void *>> handles_;  // table -> dlopen handle
  std::vector<std::string> tried_paths_;                  // files already dlopen'ed (or failed)
  std::vector<std::pair<std::string, std::string>> load_errors_;
  std::vector<std::string> rejections_;  // why add() refused tables, in order
  const void *scanned_conf_ = nullptr;   // configuration whose folders were last loaded
  unsigned generation_ = 0;
  std::vector<std::pair<std::string, PropertyDescs>> descs_;
};

// Application callbacks registered by name (custom-code modes): 0 or -EINVAL, as NNStreamer.
template <typename Callback>
class CustomCallbacks {
 public:
  int add(const char *name, Callback cb, bool valid) {
    if (!name || !*name || !valid) return -EINVAL;
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto &c : list_)
      if (c.first == name) return -EINVAL;
    list_.emplace_back(name, cb);
    return 0;
  }
  int remove(const char *name) {
    if (!name) return -EINVAL;
    std::lock_guard<std::mutex> lock(mutex_);
    for (auto it = list_.begin(); it != list_.end(); ++it) {
      if (it->first == name) {
        list_.erase(it);
        return 0;
      }
    }
    return -EINVAL;
  }
  std::optional<Callback> find(std::string_view name) {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto &c : list_)
      if (c.first == name) return c.second;
    return std::nullopt;
  }

 private:
  std::mutex mutex_;
  std::vector<std::pair<std::string, Callback>> list_;
};

}  // namespace nns::gst
