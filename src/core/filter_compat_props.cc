// SPDX-License-Identifier: LGPL-2.1-only
#include "core/filter_compat_props.h"

#include <cstring>

#include "core/c_tensor_info.h"
#include "core/filter_desc.h"

namespace nns {
namespace {

void fill_ranks(const GstTensorsInfo &info, unsigned int *ranks) {
  for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i) ranks[i] = 0;
  for (unsigned i = 0; i < info.num_tensors && i < NNS_TENSOR_SIZE_LIMIT; ++i) {
    const GstTensorInfo *t = gst_info_at(&info, i);
    unsigned r = 0;
    while (t && r < NNS_TENSOR_RANK_LIMIT && t->dimension[r] != 0) ++r;
    ranks[i] = r;
  }
}

void copy_gst_info(const GstTensorsInfo &src, GstTensorsInfo *dst) {
  auto d = new_desc();
  desc_from_gst_info(&src, *d);
  gst_info_clear(dst);
  gst_info_from_desc(*d, dst);
}

}  // namespace

CompatProps::CompatProps(const nns_filter_props &p) {
  std::memset(&prop_, 0, sizeof prop_);
  gst_info_init(&prop_.input_meta);
  gst_info_init(&prop_.output_meta);
  fwname_ = p.framework ? p.framework : "";
  custom_ = p.custom ? p.custom : "";
  accl_ = p.accelerator ? p.accelerator : "";
  for (uint32_t i = 0; i < p.num_models && p.model_files && p.model_files[i]; ++i)
    models_.emplace_back(p.model_files[i]);
  for (auto &m : models_) model_ptrs_.push_back(m.c_str());
  model_ptrs_.push_back(nullptr);

  prop_.fwname = fwname_.c_str();
  prop_.fw_opened = 1;
  prop_.model_files = model_ptrs_.data();
  prop_.num_models = static_cast<int>(models_.size());
  prop_.custom_properties = p.custom ? custom_.c_str() : nullptr;
  prop_.accl_str = p.accelerator ? accl_.c_str() : nullptr;
  prop_.invoke_dynamic = p.invoke_dynamic;
  if (p.invoke_async) {
    prop_.invoke_async = 1;
    prop_.async_callback = reinterpret_cast<void *>(&nnstreamer_filter_dispatch_output_async);
    prop_.async_user_data = &async_;
  }
  for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i) {
    prop_.input_layout[i] = p.input_layout ? p.input_layout[i] : _NNS_LAYOUT_ANY;
    prop_.output_layout[i] = p.output_layout ? p.output_layout[i] : _NNS_LAYOUT_ANY;
  }
  prop_.latency = -1;
  prop_.throughput = -1;
  if (p.input && p.input->num_tensors > 0) set_input(*p.input);
  if (p.output && p.output->num_tensors > 0) set_output(*p.output);
}

CompatProps::~CompatProps() {
  gst_info_clear(&prop_.input_meta);
  gst_info_clear(&prop_.output_meta);
}

void CompatProps::set_input(const nns_tensors_desc &d) {
  gst_info_clear(&prop_.input_meta);
  gst_info_from_desc(d, &prop_.input_meta);
  prop_.input_configured = 1;
  fill_ranks(prop_.input_meta, prop_.input_ranks);
}

void CompatProps::set_output(const nns_tensors_desc &d) {
  gst_info_clear(&prop_.output_meta);
  gst_info_from_desc(d, &prop_.output_meta);
  prop_.output_configured = 1;
  fill_ranks(prop_.output_meta, prop_.output_ranks);
}

void CompatProps::set_input(const GstTensorsInfo &i) {
  copy_gst_info(i, &prop_.input_meta);
  prop_.input_configured = 1;
  fill_ranks(prop_.input_meta, prop_.input_ranks);
}

void CompatProps::set_output(const GstTensorsInfo &i) {
  copy_gst_info(i, &prop_.output_meta);
  prop_.output_configured = 1;
  fill_ranks(prop_.output_meta, prop_.output_ranks);
}

int CompatProps::query_model_info(nns_tensors_desc *in, nns_tensors_desc *out,
                                  const InfoCall &query) {
  GstTensorsInfo gi, go;
  gst_info_init(&gi);
  gst_info_init(&go);
  int rc = query(&gi, &go);
  if (rc == 0) {
    desc_from_gst_info(&gi, *in);
    desc_from_gst_info(&go, *out);
    set_input(*in);
    set_output(*out);
  }
  gst_info_clear(&gi);
  gst_info_clear(&go);
  return rc;
}

int CompatProps::negotiate_input(const nns_tensors_desc &in, nns_tensors_desc *out,
                                 const InfoCall &set) {
  GstTensorsInfo gi, go;
  gst_info_from_desc(in, &gi);
  gst_info_init(&go);
  int rc = set(&gi, &go);
  if (rc == 0) {
    desc_from_gst_info(&go, *out);
    set_input(in);
    set_output(*out);
  }
  gst_info_clear(&gi);
  gst_info_clear(&go);
  return rc;
}

}  // namespace nns
