// SPDX-License-Identifier: LGPL-2.1-only
// Test back end loaded from libnnstreamer_filter_testecho.so: output = input (set_input_info
// echoes the shapes). Reads no model content but needs the model file to exist.
#include <cstring>

#include "nns_filter_backend.hh"

namespace {

class Echo : public nns::FilterBackend {
 public:
  explicit Echo(const nns_filter_props &p) {
    if (p.custom && std::strcmp(p.custom, "fail_open:1") == 0)
      throw nns::FilterError("testecho refuses to open (custom=fail_open:1)");
  }
  bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) override {
    std::memcpy(&out, &in, sizeof in);
    return true;
  }
  void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
              uint32_t num_out) override {
    for (uint32_t i = 0; i < num_in && i < num_out; ++i)
      std::memcpy(out[i].data, in[i].data, in[i].size < out[i].size ? in[i].size : out[i].size);
  }
};

const char *const kExt[] = {".echo", nullptr};

}  // namespace

NNS_FILTER_BACKEND_EXPORT(Echo, "testecho", 0, kExt)
