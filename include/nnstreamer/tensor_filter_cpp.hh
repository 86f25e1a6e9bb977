// SPDX-License-Identifier: LGPL-2.1-only
// framework=cpp: attach a C++ object as a filter. Same class and registration calls as
// NNStreamer's tensor_filter_cpp.hh (source compatible):
//
//   class myfilter : public tensor_filter_cpp {
//    public:
//     myfilter() : tensor_filter_cpp("myfilter01") {}
//     int getInputDim(GstTensorsInfo *info) override;   // or return -EINVAL and use setInputDim
//     int getOutputDim(GstTensorsInfo *info) override;
//     int setInputDim(const GstTensorsInfo *in, GstTensorsInfo *out) override;
//     int invoke(const GstTensorMemory *in, GstTensorMemory *out) override;
//     bool isAllocatedBeforeInvoke() override { return true; }
//   };
//   myfilter fx;  fx._register();
//   ... ! tensor_filter framework=cpp model=myfilter01 ! ...
//
// `model=myfilter01,/path/libabc.so` loads libabc.so first when myfilter01 is not yet
// registered (its static constructor is expected to register it). One registered object
// serves every filter that names it; calls into it are serialized. `prop` points at the
// properties of the filter currently calling in.
//
// getInputDim/getOutputDim return 0 when they know the shapes; a non-zero value means
// "ask setInputDim". invoke returns 0, a negative value on error, a positive value to drop
// the frame. When isAllocatedBeforeInvoke() is false, invoke sets out[i].data to memory
// from malloc(), which the element frees.
#ifndef NNSTREAMER_CPP_TENSOR_FILTER_CPP_HH_
#define NNSTREAMER_CPP_TENSOR_FILTER_CPP_HH_

#ifdef __cplusplus

#include <stdint.h>

#include <atomic>

#include "nnstreamer_plugin_api_filter.h"

struct nns_cpp_filter_access;

class tensor_filter_cpp {
 private:
  const uint32_t validity;
  const char *name;
  std::atomic_uint ref_count;
  friend struct nns_cpp_filter_access;

 protected:
  const GstTensorFilterProperties *prop;

 public:
  explicit tensor_filter_cpp(const char *modelName);
  virtual ~tensor_filter_cpp();

  virtual int getInputDim(GstTensorsInfo *info) = 0;
  virtual int getOutputDim(GstTensorsInfo *info) = 0;
  virtual int setInputDim(const GstTensorsInfo *in, GstTensorsInfo *out) = 0;
  virtual int invoke(const GstTensorMemory *in, GstTensorMemory *out) = 0;
  virtual bool isAllocatedBeforeInvoke() = 0;

  // Registers `filter` under its model name: 0, -EINVAL (invalid object or no name) or
  // -EEXIST (name taken). The object must outlive its registration.
  static int __register(tensor_filter_cpp *filter, unsigned int ref_count = 0);
  int _register(unsigned int ref_count = 0) { return __register(this, ref_count); }
  // 0, -EINVAL (unknown name) or -EBUSY (still used by a filter).
  static int __unregister(const char *name);
  int _unregister() { return __unregister(this->name); }

  bool isValid();
};

#endif /* __cplusplus */

#endif /* NNSTREAMER_CPP_TENSOR_FILTER_CPP_HH_ */
