/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * NNStreamer 2.x's base class for filter sub-plugins written in C++.
 *
 * A sub-plugin derives from nnstreamer::tensor_filter_subplugin, implements the pure virtual
 * functions and calls register_subplugin<Derived>() from its .so's constructor (and
 * unregister_subplugin() from its destructor). The base class turns every object into a
 * version-1 GstTensorFilterFramework: the object registered is the "empty" representative
 * whose getEmptyInstance() makes one object per opened model.
 *
 * The declaration (members, their order, the virtual functions and their order, the static
 * members) is NNStreamer 2.x's, so the mangled names, the vtable and the object layout are the
 * same and a sub-plugin compiled against NNStreamer's header loads into nnstreamer-cpp
 * unchanged (docs/compat-nnstreamer-2x.md, "C++ sub-plugins"). The definitions are in
 * libnnstreamer.so and libnnstreamer-single.so.
 */
#ifndef NNSTREAMER_CPPPLUGIN_API_FILTER_HH_
#define NNSTREAMER_CPPPLUGIN_API_FILTER_HH_
#ifdef __cplusplus

#include <assert.h>
#include <stdint.h>
#include <string.h>

#include <stdexcept>
#include <type_traits>

#include "nnstreamer_plugin_api_filter.h"

namespace nnstreamer {

class tensor_filter_subplugin {
 private:
  /* Object layout (keep): vtable pointer, sanity, fwdesc. */
  const uint64_t sanity; /* a fixed value marking a live object of this class */

  /* The callbacks every object's fwdesc starts from (copied by the constructor). */
  static const GstTensorFilterFramework fwdesc_template;

  static inline tensor_filter_subplugin *get_tfsp_with_checks(void *ptr);
  static int cpp_open(const GstTensorFilterProperties *prop, void **private_data);
  static void cpp_close(const GstTensorFilterProperties *prop, void **private_data);
  static int cpp_invoke(const GstTensorFilterFramework *tf, GstTensorFilterProperties *prop,
                        void *private_data, const GstTensorMemory *input, GstTensorMemory *output);
  static int cpp_getFrameworkInfo(const GstTensorFilterFramework *tf,
                                  const GstTensorFilterProperties *prop, void *private_data,
                                  GstTensorFilterFrameworkInfo *fw_info);
  static int cpp_getModelInfo(const GstTensorFilterFramework *tf,
                              const GstTensorFilterProperties *prop, void *private_data,
                              model_info_ops ops, GstTensorsInfo *in_info,
                              GstTensorsInfo *out_info);
  static int cpp_eventHandler(const GstTensorFilterFramework *tf,
                              const GstTensorFilterProperties *prop, void *private_data,
                              event_ops ops, GstTensorFilterFrameworkEventData *data);

  /* This object's version-1 table; subplugin_data points back at the registered object. */
  GstTensorFilterFramework fwdesc;

 protected:
  /* Creates the representative object of T, registers it (nnstreamer_filter_probe) and returns
   * it; keep it for unregister_subplugin(). */
  template <typename T>
  static T *register_subplugin() {
    static_assert(std::is_base_of<tensor_filter_subplugin, T>::value,
                  "T must derive from nnstreamer::tensor_filter_subplugin");
    T *representative = new T();
    assert(representative);
    memcpy(&representative->fwdesc, &fwdesc_template, sizeof(fwdesc_template));
    representative->fwdesc.subplugin_data = representative;
    nnstreamer_filter_probe(&representative->fwdesc);
    return representative;
  }

  /* Unregisters the name T's getFrameworkInfo() gives and deletes the representative. */
  template <typename T>
  static void unregister_subplugin(T *representative) {
    static_assert(std::is_base_of<tensor_filter_subplugin, T>::value,
                  "T must derive from nnstreamer::tensor_filter_subplugin");
    GstTensorFilterFrameworkInfo info;
    assert(representative);
    memset(&info, 0, sizeof(info));
    representative->getFrameworkInfo(info);
    nnstreamer_filter_exit(info.name);
    delete representative;
  }

 public:
  /* An "empty" object: not bound to a model. Derived classes keep such a constructor. */
  tensor_filter_subplugin();

  /* Virtual functions, in vtable order (keep). */

  /* A new empty object of the derived class (allocated with new; deleted at close). */
  virtual tensor_filter_subplugin &getEmptyInstance() = 0;
  /* Makes an empty object usable for prop's model; throws on failure (std::invalid_argument:
   * -EINVAL, std::system_error: -code, anything else: -1 from open). */
  virtual void configure_instance(const GstTensorFilterProperties *prop) = 0;
  virtual ~tensor_filter_subplugin();
  /* Runs the model; an exception makes invoke return -EINVAL (std::system_error: -code). */
  virtual void invoke(const GstTensorMemory *input, GstTensorMemory *output) = 0;
  /* invoke-dynamic=true: the sub-plugin allocates every output (released through
   * eventHandler(DESTROY_NOTIFY), else free()) and describes them in prop->output_meta.
   * (In the vtable since NNStreamer 2.4.x/2.6; sub-plugins built against older headers lack
   * this slot.) Not supported unless overridden. */
  virtual void invoke_dynamic(GstTensorFilterProperties *prop, const GstTensorMemory *input,
                              GstTensorMemory *output) {
    (void)prop;
    (void)input;
    (void)output;
    throw std::invalid_argument("this C++ filter sub-plugin does not support invoke-dynamic");
  }
  /* The framework's information; info.name never changes. Also asked of empty objects. */
  virtual void getFrameworkInfo(GstTensorFilterFrameworkInfo &info) = 0;
  /* The model's tensors: GET_IN_OUT_INFO or SET_INPUT_INFO; -ENOENT when not supported,
   * -EINVAL for an invalid request. */
  virtual int getModelInfo(model_info_ops ops, GstTensorsInfo &in_info,
                           GstTensorsInfo &out_info) = 0;
  /* Events (DESTROY_NOTIFY, SUSPEND, ...). The base class handles none: -ENOENT. */
  virtual int eventHandler(event_ops ops, GstTensorFilterFrameworkEventData &data);
};

} /* namespace nnstreamer */

#endif /* __cplusplus */
#endif /* NNSTREAMER_CPPPLUGIN_API_FILTER_HH_ */
