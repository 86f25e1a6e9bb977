// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer 2.x filter sub-plugins written in C++ with nnstreamer::tensor_filter_subplugin
// (nnstreamer_cppplugin_api_filter.hh), as NNStreamer's and vendors' C++ sub-plugins are. One
// source, four files (CPPX_KIND selects the class registered):
//   1 cppx_pass   pass-through of whatever it is given (SET_INPUT_INFO: out = in)
//   2 cppx_multi  a model with two inputs and three outputs (GET_IN_OUT_INFO):
//                 in0 float32 4, in1 uint8 2 -> out0 float32 4 = in0 * 2 + 1,
//                 out1 uint8 2 = in1 reversed, out2 int32 1 = sum(in1)
//   3 cppx_dyn    invoke-dynamic: in uint8 N -> out0 float32 N = in / 2, out1 int32 1 = N,
//                 allocated in invoke and released through DESTROY_NOTIFY
//   4 cppx_fail   configure_instance throws std::invalid_argument
// Every file exports cppx_counters(int c[4]): objects made / deleted (the representative
// excluded), blocks allocated in invoke / released.
#include <errno.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "nnstreamer_cppplugin_api_filter.hh"
#include "nnstreamer_plugin_api_util.h"

namespace {

std::atomic<int> g_made{0}, g_deleted{0}, g_alloc{0}, g_freed{0};
const accl_hw kHw[] = {ACCL_CPU};

void set_tensor(GstTensorsInfo &info, unsigned i, tensor_type t, uint32_t d0) {
  GstTensorInfo *ti = gst_tensors_info_get_nth_info(&info, i);
  ti->type = t;
  ti->dimension[0] = d0;
  ti->dimension[1] = 1;
}

class cppx_base : public nnstreamer::tensor_filter_subplugin {
 public:
  explicit cppx_base(bool counted) : counted_(counted) {
    gst_tensors_info_init(&in_);
    gst_tensors_info_init(&out_);
    if (counted_) ++g_made;
  }
  ~cppx_base() override {
    gst_tensors_info_free(&in_);
    gst_tensors_info_free(&out_);
    if (counted_) ++g_deleted;
  }
  void configure_instance(const GstTensorFilterProperties *prop) override {
    if (!prop) throw std::invalid_argument("no properties");
  }
  void getFrameworkInfo(GstTensorFilterFrameworkInfo &info) override {
    info.name = name();
    info.allow_in_place = 0;
    info.allocate_in_invoke = 0;
    info.run_without_model = 1;
    info.verify_model_path = 0;
    info.hw_list = kHw;
    info.num_hw = 1;
    info.accl_auto = ACCL_CPU;
    info.accl_default = ACCL_CPU;
    info.statistics = nullptr;
  }
  virtual const char *name() const = 0;

 protected:
  bool counted_;
  GstTensorsInfo in_, out_;
};

class cppx_pass : public cppx_base {
 public:
  explicit cppx_pass(bool counted = false) : cppx_base(counted) {}
  tensor_filter_subplugin &getEmptyInstance() override { return *new cppx_pass(true); }
  const char *name() const override { return "cppx_pass"; }
  int getModelInfo(model_info_ops ops, GstTensorsInfo &in, GstTensorsInfo &out) override {
    if (ops != SET_INPUT_INFO) return -ENOENT;
    gst_tensors_info_copy(&in_, &in);
    gst_tensors_info_copy(&out_, &in);
    gst_tensors_info_copy(&out, &in);
    return 0;
  }
  void invoke(const GstTensorMemory *input, GstTensorMemory *output) override {
    for (unsigned i = 0; i < in_.num_tensors; ++i) {
      if (output[i].size != input[i].size) throw std::invalid_argument("size mismatch");
      std::memcpy(output[i].data, input[i].data, input[i].size);
    }
  }
};

class cppx_multi : public cppx_base {
 public:
  explicit cppx_multi(bool counted = false) : cppx_base(counted) {}
  tensor_filter_subplugin &getEmptyInstance() override { return *new cppx_multi(true); }
  const char *name() const override { return "cppx_multi"; }
  int getModelInfo(model_info_ops ops, GstTensorsInfo &in, GstTensorsInfo &out) override {
    if (ops != GET_IN_OUT_INFO) return -ENOENT;
    gst_tensors_info_init(&in);
    gst_tensors_info_init(&out);
    in.num_tensors = 2;
    set_tensor(in, 0, _NNS_FLOAT32, 4);
    set_tensor(in, 1, _NNS_UINT8, 2);
    out.num_tensors = 3;
    set_tensor(out, 0, _NNS_FLOAT32, 4);
    set_tensor(out, 1, _NNS_UINT8, 2);
    set_tensor(out, 2, _NNS_INT32, 1);
    return 0;
  }
  void invoke(const GstTensorMemory *input, GstTensorMemory *output) override {
    const float *a = static_cast<const float *>(input[0].data);
    const uint8_t *b = static_cast<const uint8_t *>(input[1].data);
    float *o0 = static_cast<float *>(output[0].data);
    for (int i = 0; i < 4; ++i) o0[i] = a[i] * 2.f + 1.f;
    uint8_t *o1 = static_cast<uint8_t *>(output[1].data);
    o1[0] = b[1];
    o1[1] = b[0];
    int32_t sum = b[0] + b[1];
    std::memcpy(output[2].data, &sum, sizeof sum);
  }
};

class cppx_dyn : public cppx_base {
 public:
  explicit cppx_dyn(bool counted = false) : cppx_base(counted) {}
  tensor_filter_subplugin &getEmptyInstance() override { return *new cppx_dyn(true); }
  const char *name() const override { return "cppx_dyn"; }
  int getModelInfo(model_info_ops ops, GstTensorsInfo &in, GstTensorsInfo &out) override {
    if (ops != SET_INPUT_INFO) return -ENOENT;
    gst_tensors_info_copy(&in_, &in);
    gst_tensors_info_init(&out);
    out.num_tensors = 2;
    set_tensor(out, 0, _NNS_FLOAT32, gst_tensor_info_get_size(&in.info[0]));
    set_tensor(out, 1, _NNS_INT32, 1);
    return 0;
  }
  void invoke(const GstTensorMemory *, GstTensorMemory *) override {
    throw std::invalid_argument("cppx_dyn runs with invoke-dynamic=true only");
  }
  void invoke_dynamic(GstTensorFilterProperties *prop, const GstTensorMemory *input,
                      GstTensorMemory *output) override {
    const uint32_t n = static_cast<uint32_t>(input[0].size);
    float *o0 = static_cast<float *>(std::malloc(n * sizeof(float)));
    int32_t *o1 = static_cast<int32_t *>(std::malloc(sizeof(int32_t)));
    for (uint32_t i = 0; i < n; ++i) o0[i] = static_cast<const uint8_t *>(input[0].data)[i] / 2.f;
    *o1 = static_cast<int32_t>(n);
    g_alloc += 2;
    output[0].data = o0;
    output[0].size = n * sizeof(float);
    output[1].data = o1;
    output[1].size = sizeof(int32_t);
    gst_tensors_info_init(&prop->output_meta);
    prop->output_meta.num_tensors = 2;
    set_tensor(prop->output_meta, 0, _NNS_FLOAT32, n);
    set_tensor(prop->output_meta, 1, _NNS_INT32, 1);
  }
  int eventHandler(event_ops ops, GstTensorFilterFrameworkEventData &data) override {
    if (ops != DESTROY_NOTIFY) return -ENOENT;
    std::free(data.data);
    ++g_freed;
    return 0;
  }
};

class cppx_fail : public cppx_base {
 public:
  explicit cppx_fail(bool counted = false) : cppx_base(counted) {}
  tensor_filter_subplugin &getEmptyInstance() override { return *new cppx_fail(true); }
  const char *name() const override { return "cppx_fail"; }
  void configure_instance(const GstTensorFilterProperties *prop) override {
    throw std::invalid_argument(std::string("cppx_fail refuses model '") +
                                (prop->num_models > 0 ? prop->model_files[0] : "") + "'");
  }
  int getModelInfo(model_info_ops, GstTensorsInfo &, GstTensorsInfo &) override { return -ENOENT; }
  void invoke(const GstTensorMemory *, GstTensorMemory *) override {}
};

#if CPPX_KIND == 1
using Registered = cppx_pass;
#elif CPPX_KIND == 2
using Registered = cppx_multi;
#elif CPPX_KIND == 3
using Registered = cppx_dyn;
#else
using Registered = cppx_fail;
#endif

// register_subplugin<>() is protected, as in NNStreamer: sub-plugins call it from a static
// member of their class.
class registrar : public Registered {
 public:
  static Registered *add() { return register_subplugin<Registered>(); }
  static void remove(Registered *r) { unregister_subplugin(r); }
};

Registered *g_registered = nullptr;

__attribute__((constructor)) void cppx_init() {
  g_registered = registrar::add();
}
__attribute__((destructor)) void cppx_fini() {
  registrar::remove(g_registered);
}

}  // namespace

extern "C" __attribute__((visibility("default"))) void cppx_counters(int *c) {
  c[0] = g_made;
  c[1] = g_deleted;
  c[2] = g_alloc;
  c[3] = g_freed;
}
