// SPDX-License-Identifier: LGPL-2.1-only
// Process-wide registry behind nnstreamer_if_custom_register() (include/nnstreamer/tensor_if.h).
#pragma once

#include <optional>
#include <string>

#include "tensor_if.h"

namespace nns::gst {

struct IfCustom {
  tensor_if_custom func = nullptr;
  void *data = nullptr;
};

std::optional<IfCustom> find_if_custom(const std::string &name);

}  // namespace nns::gst
