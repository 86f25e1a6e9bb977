// SPDX-License-Identifier: LGPL-2.1-only
// A C++ filter in its own library (framework=cpp model=tf_cpp_lib,<this .so>): registers
// itself when loaded. Output = input + 3.
#include <cerrno>

#include "tensor_filter_cpp.hh"

namespace {

class LibFilter : public tensor_filter_cpp {
 public:
  LibFilter() : tensor_filter_cpp("tf_cpp_lib") {}
  int getInputDim(GstTensorsInfo *) override { return -EINVAL; }
  int getOutputDim(GstTensorsInfo *) override { return -EINVAL; }
  int setInputDim(const GstTensorsInfo *in, GstTensorsInfo *out) override {
    *out = *in;
    out->info[0].name = nullptr;
    return 0;
  }
  int invoke(const GstTensorMemory *in, GstTensorMemory *out) override {
    for (size_t k = 0; k < in[0].size; ++k)
      static_cast<unsigned char *>(out[0].data)[k] =
          static_cast<unsigned char>(static_cast<const unsigned char *>(in[0].data)[k] + 3);
    return 0;
  }
  bool isAllocatedBeforeInvoke() override { return true; }
};

LibFilter g_filter;
const int g_registered = g_filter._register();

}  // namespace
