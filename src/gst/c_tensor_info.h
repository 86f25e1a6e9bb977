// SPDX-License-Identifier: LGPL-2.1-only
// Forwarding header: the C tensor description helpers live in core/c_tensor_info.h (namespace
// nns). Kept so code that still names nns::gst::CTensorsConfig / nns::gst::to_c builds; new code
// includes core/c_tensor_info.h.
#pragma once

#include "core/c_tensor_info.h"

namespace nns::gst {
using nns::CTensorsConfig;
using nns::from_c;
using nns::to_c;
}  // namespace nns::gst
