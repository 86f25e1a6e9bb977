// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer_plugin_api_filter.h's accelerator helpers over nns::accl (src/core/filter_accl.h).
#include "compat/compat_export.h"
#include "core/filter_accl.h"
#include "nnstreamer_plugin_api_filter.h"

NNS_COMPAT_API accl_hw get_accl_hw_type(const char *str) {
  return nns::accl::type_of(str);
}

NNS_COMPAT_API const char *get_accl_hw_str(const accl_hw key) {
  return nns::accl::name_of(key);
}

NNS_COMPAT_API accl_hw parse_accl_hw_fill(parse_accl_args accl_args) {
  try {
    return nns::accl::parse(accl_args.in_accl, accl_args.sup_accl, accl_args.auto_accl,
                            accl_args.def_accl);
  } catch (...) {  // allocation failure: nothing may cross into C
    return ACCL_NONE;
  }
}
