// SPDX-License-Identifier: LGPL-2.1-only
// libFuzzer target: an IIO channel type string as read from sysfs (nns::iio::parse_channel_type)
// and the decoding of one stored sample with it (nns::iio::decode_sample), as tensor_src_iio runs
// them. Input: the type text up to the first '\n', then the sample bytes.
// Properties: parse returns or throws nns::Error; an accepted type has 1 <= bits <= storage <= 64
// and shift + bits <= storage; the decoded value (scale 1, offset 0) is finite and within the
// range of `bits` bits.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/error.h"
#include "core/iio/iio_channel.h"

namespace {

[[noreturn]] void broken(const char *what) {
  std::fprintf(stderr, "fuzz property broken: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const void *nl = std::memchr(data, '\n', size);
  const size_t text_len = nl ? static_cast<const uint8_t *>(nl) - data : size;
  std::string text(reinterpret_cast<const char *>(data), text_len);
  nns::iio::Channel ch;
  try {
    ch.type = nns::iio::parse_channel_type(text, "fuzz");
  } catch (const nns::Error &) {
    return 0;
  }
  const auto &t = ch.type;
  if (t.used_bits < 1 || t.used_bits > t.storage_bits || t.storage_bits > 64 ||
      t.shift + t.used_bits > t.storage_bits)
    broken("accepted an impossible type");
  const size_t rest = nl ? size - text_len - 1 : 0;
  if (rest < t.storage_bytes()) return 0;
  const float v = nns::iio::decode_sample(ch, data + text_len + 1);
  if (!std::isfinite(v)) broken("decoded a non-finite value");
  const double limit = std::ldexp(1.0, static_cast<int>(t.used_bits));
  if (std::fabs(static_cast<double>(v)) > limit) broken("decoded value out of the bits' range");
  return 0;
}
