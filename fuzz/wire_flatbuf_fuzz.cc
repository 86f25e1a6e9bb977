// SPDX-License-Identifier: LGPL-2.1-only
// libFuzzer target: nns::wire::decode(flatbuf) on arbitrary bytes (what tensor_converter's
// flatbuf sub-plugin runs on every incoming buffer). See wire_fuzz_check.h for the properties.
#include "wire_fuzz_check.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  nns::fuzz::check_wire(nns::wire::Format::kFlatbuf, data, size);
  return 0;
}
