// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer's accelerator names and its reading of the accelerator= string
// ("true:npu,gpu,!cpu"), as nnstreamer_plugin_api_filter.h's get_accl_hw_type(),
// get_accl_hw_str() and parse_accl_hw() give them to sub-plugins (exported in src/compat), and
// as tensor_filter hands them to NNStreamer 2.x version-1 sub-plugins (src/core/compat2x).
//
// The facts, from NNStreamer 2.x:
// - names are matched exactly (case-sensitive): none, default, auto, cpu, cpu.simd, gpu, npu,
//   npu.movidius, npu.edgetpu, npu.vivante, npu.srcn, npu.slsi, npu.sr; cpu.neon only on Arm
//   (elsewhere it is no accelerator). ACCL_CPU_NEON and ACCL_CPU_SIMD share a value: its name
//   is cpu.neon on Arm, cpu.simd elsewhere. An unknown name is ACCL_NONE, an unknown value
//   "none".
// - accelerator= is in use when it starts with "true" (any case); then every supported name
//   found in the string, scanning from the left (the first one of the supported list that
//   matches at a position, case-insensitively, not right after a '!'), is taken in order, and
//   kept when its exact spelling is a known name. Nothing kept: auto. Not starting with "true":
//   none. Unset: default.
#pragma once

#include <string>
#include <vector>

#include "nnstreamer_plugin_api_filter.h"

namespace nns::accl {

// get_accl_hw_type(): ACCL_NONE for an unknown or null name.
accl_hw type_of(const char *name);
// get_accl_hw_str(): "none" for an unknown value.
const char *name_of(accl_hw hw);

// Every accelerator `accelerators` asks for among `supported` (names), in the order given:
// {ACCL_DEFAULT} when null, {ACCL_NONE} when it does not start with "true", {ACCL_AUTO} when it
// does but names none of them. ACCL_AUTO / ACCL_DEFAULT also appear when "auto" / "default" are
// in `supported` and named.
std::vector<accl_hw> match_all(const char *accelerators, const std::vector<std::string> &supported);

// parse_accl_hw(): the first accelerator `accelerators` asks for among the null-terminated
// `supported` list (plus auto and default), auto resolved to `auto_accl` and default to
// `default_accl` (each the first supported one when null or not usable on this machine).
// ACCL_NONE when `supported` is null or empty.
accl_hw parse(const char *accelerators, const char *const *supported, const char *auto_accl,
              const char *default_accl);

// Whether this CPU can run `name` (false only for cpu.neon on an Arm CPU without NEON/ASIMD).
bool usable_here(const char *name);

}  // namespace nns::accl
