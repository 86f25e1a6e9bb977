// SPDX-License-Identifier: LGPL-2.1-only
// Entry points of NNStreamer's C ABI defined in src/compat/. The compat objects are built with
// -fvisibility=hidden, so only what is marked here is exported; the libraries holding them are
// linked with -Bsymbolic-functions, so their own calls never go to a same-named function of
// another library loaded earlier (docs/compat-nnstreamer-2x.md, "Symbol binding").
#pragma once

#define NNS_COMPAT_API extern "C" __attribute__((visibility("default")))
