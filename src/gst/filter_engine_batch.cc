// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter behind a batching query server (tensor_query_serversrc max-batch > 1,
// docs/elements/tensor_query_serversrc.md): a model whose batch cannot grow to max-batch is
// refused with one message naming max-batch, the model and its inputs, whatever the back end
// (ONNX Runtime's fixed input, a .tflite graph whose RESHAPE bakes the batch in and fails to
// re-translate, a TorchScript module that fails its probe run), the engine's own message kept
// as the detail.
#include <memory>

#include "core/error.h"
#include "core/filter_registry.h"
#include "gst/filter_engine.h"
#include "gst/query_batch.h"

namespace nns::gst {

namespace {

// `want` and the model's `got` differ at most in the outermost dimension of each tensor (the
// batch): same count, types and inner dimensions.
bool same_but_batch(const TensorsInfo &want, const TensorsInfo &got) {
  if (want.size() != got.size()) return false;
  for (std::size_t i = 0; i < want.size(); ++i) {
    const std::size_t r = want[i].rank();
    if (r == 0 || want[i].type != got[i].type) return false;
    Dims a = want[i].dims, b = got[i].dims;
    a[r - 1] = 1;
    b[r - 1] = 1;
    if (!dims_equal(a, b)) return false;
  }
  return true;
}

std::string inputs_string(const TensorsInfo &in) {
  std::string s;
  for (std::size_t i = 0; i < in.size(); ++i)
    s += (i ? ", " : "") + std::string("input ") + std::to_string(i) +
         (in[i].name.empty() ? "" : " '" + in[i].name + "'") + " " +
         std::string(type_name(in[i].type)) + " " + dims_to_string(in[i].dims);
  return s;
}

}  // namespace

void FilterEngine::refuse_batch(const FilterSettings &s, const TensorsInfo &want,
                                const std::string &what, const std::string &cause) {
  const auto batch = upstream_batch(GST_ELEMENT_CAST(element_));
  if (!batch) return;
  const std::string n = std::to_string(batch->n);
  // The model at its own shapes: without input=/output= (which say the batch) nor sharing.
  FilterSettings own = s;
  own.input.clear();
  own.inputtype.clear();
  own.output.clear();
  own.outputtype.clear();
  own.shared_key.clear();
  TensorsInfo mi, mo;
  bool known = false;
  std::string model = s.model;
  try {
    const FilterOpenSpec spec = make_open_spec(own);
    auto conf = current_filter_conf();
    BackendRef be = FilterRegistry::get().resolve(spec.framework, spec.models, *conf);
    auto probe = FilterInstance::open(be, spec);
    model = probe->describe();
    known = probe->model_info(mi, mo) && mi.size() && mi.valid();
  } catch (const std::exception &) {
    return;  // the model does not open at its own shapes either: not the batch's fault
  }
  if (known && want.size() && !same_but_batch(want, mi))
    return;  // input= differs from the model beyond the batch: the cause says how
  std::string got;
  if (!known) {
    got = "a model that does not run at " + n + " (the back end declares no input shapes)";
  } else {
    std::string fixed;
    for (std::size_t i = 0; i < mi.size(); ++i) {
      const std::size_t r = mi[i].rank();
      fixed += (i ? "," : "") + (r ? std::to_string(mi[i].dims[r - 1]) : std::string("none"));
    }
    got = "a model that fixes it to " + fixed;
  }
  fail(ErrorKind::kNegotiation,
       "max-batch=" + n + " (" + batch->who + "): the input of " + GST_OBJECT_NAME(element_) +
           " (" + model + (known ? ", " + inputs_string(mi) : "") +
           ") cannot take a batch: expected a batch dimension (the outermost) that can grow to " +
           n + ", got " + got + (want.size() ? " (" + what + want.dims_string() + " fails)" : "") +
           "; use max-batch=1, or a model whose batch dimension is " + n +
           " or free. Detail: " + cause);
}

}  // namespace nns::gst
