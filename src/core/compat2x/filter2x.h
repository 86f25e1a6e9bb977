// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer 2.x filter sub-plugins (GstTensorFilterFramework, versions 0 and 1) beside our
// back ends. GStreamer-free.
//
// A 2.x sub-plugin registers itself with nnstreamer_filter_probe(), usually from the
// constructor of libnnstreamer_filter_<name>.so when FilterRegistry dlopen()s that file. Each
// accepted table gets a bridge: an nns_filter_backend_i whose functions call the 2.x table,
// so tensor_filter and the single-shot API use it like any of our back ends. Entries are never
// freed (their bridge tables may be in use); nnstreamer_filter_exit() only hides the name.
//
// Probe outcomes (accepted names, rejection reasons) are logged in order so that the loader
// can tell, after dlopen(), what the file's constructor did (see Filter2xRegistry::mark()).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "nns_filter_backend.h"
#include "nnstreamer_plugin_api_filter.h"

namespace nns::compat2x {

struct Filter2x {
  const GstTensorFilterFramework *fw = nullptr;
  std::string name;
  int version = 0;                    // table layout: 0 or 1
  GstTensorFilterFrameworkInfo info;  // version 1: getFrameworkInfo(NULL); version 0: from v0
  std::vector<accl_hw> hw;            // info.hw_list copied
  std::string origin;                 // the .so path, or "registered in-process"
  nns_filter_backend_i iface{};       // the bridge
  int slot = -1;
  bool registered = false;
};

class Filter2xRegistry {
 public:
  static Filter2xRegistry &get();

  // nnstreamer_filter_probe(): true when registered; otherwise *why says why.
  bool probe(const GstTensorFilterFramework *fw, std::string *why);
  void exit(const std::string &name);
  // The registered entry `name`, or nullptr.
  const Filter2x *find(const std::string &name);
  std::vector<std::string> names();
  // The entry whose bridge table is `iface`, or nullptr (iface is one of our back ends).
  const Filter2x *of_bridge(const nns_filter_backend_i *iface);
  // Records where `name` came from (the file whose constructor registered it).
  void set_origin(const std::string &name, const std::string &origin);

  // Probe log: mark() before dlopen(), since(mark) after it.
  struct ProbeEvent {
    bool accepted;
    std::string text;  // the name, or the rejection reason
  };
  uint64_t mark();
  std::vector<ProbeEvent> since(uint64_t mark);

  // nnstreamer_filter_set_custom_property_desc()
  void set_custom_desc(const std::string &name,
                       std::vector<std::pair<std::string, std::string>> desc);
  std::vector<std::pair<std::string, std::string>> custom_desc(const std::string &name);

 private:
  Filter2xRegistry() = default;
  std::string check(const GstTensorFilterFramework *fw, GstTensorFilterFrameworkInfo &info) const;
  void log(bool accepted, std::string text);

  std::mutex mu_;
  std::vector<std::unique_ptr<Filter2x>> entries_;  // never shrinks
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>> desc_;
  std::vector<std::pair<uint64_t, ProbeEvent>> log_;
  uint64_t seq_ = 0;
};

// Fills entry.iface (the bridge table) and binds it to a free slot; false when every slot is
// taken (filter2x_bridge.cc).
bool bind_bridge(Filter2x &entry);
// Our back end `b` as a version-1 NNStreamer 2.x table (backend_as_2x.cc): made on first use,
// valid for the life of the process. `asked` (the name or alias looked up) is remembered so
// that open(prop) with prop->fwname == asked finds the table.
const GstTensorFilterFramework *framework_of_backend(const nns_filter_backend_i *b,
                                                     const std::string &asked);
// Number of bridge slots (distinct 2.x tables registered over the life of the process).
constexpr int kBridgeSlots = 64;

}  // namespace nns::compat2x
