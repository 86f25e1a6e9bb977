// SPDX-License-Identifier: LGPL-2.1-only
#include "core/iio/iio_channel.h"

#include <algorithm>
#include <charconv>

#include "core/error.h"

namespace nns::iio {

namespace {

[[noreturn]] void bad_type(std::string_view text, const std::string &file, const char *why) {
  fail(ErrorKind::kSettings, "IIO channel type '" + std::string(text) + "' in " + file +
                                 " does not parse (" + why +
                                 "; expected [be|le]:[s|u]<bits>/<storagebits>>><shift>, "
                                 "e.g. le:s12/16>>4)");
}

// Reads an unsigned decimal at text[pos...], advancing pos.
unsigned read_uint(std::string_view text, std::size_t &pos, const std::string &file,
                   const char *what) {
  unsigned v = 0;
  auto [end, ec] = std::from_chars(text.data() + pos, text.data() + text.size(), v);
  if (ec != std::errc() || end == text.data() + pos) bad_type(text, file, what);
  pos = static_cast<std::size_t>(end - text.data());
  return v;
}

uint64_t mask_bits(unsigned bits) {
  return bits >= 64 ? ~uint64_t{0} : ((uint64_t{1} << bits) - 1);
}

}  // namespace

ChannelType parse_channel_type(std::string_view raw, const std::string &file) {
  std::string_view text = raw;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ' || text.back() == '\r'))
    text.remove_suffix(1);
  ChannelType t;
  if (text.size() < 4 || text[2] != ':') bad_type(text, file, "no endianness prefix");
  if (text.substr(0, 2) == "be")
    t.big_endian = true;
  else if (text.substr(0, 2) == "le")
    t.big_endian = false;
  else
    bad_type(text, file, "endianness is not 'be' or 'le'");
  if (text[3] == 's')
    t.is_signed = true;
  else if (text[3] == 'u')
    t.is_signed = false;
  else
    bad_type(text, file, "sign is not 's' or 'u'");
  std::size_t pos = 4;
  t.used_bits = read_uint(text, pos, file, "no bit count");
  if (pos >= text.size() || text[pos] != '/') bad_type(text, file, "no '/' after the bit count");
  ++pos;
  t.storage_bits = read_uint(text, pos, file, "no storage bit count");
  if (pos < text.size() && text[pos] == 'X')
    bad_type(text, file, "repeated samples (X<n>) are not supported");
  if (pos + 1 >= text.size() || text[pos] != '>' || text[pos + 1] != '>')
    bad_type(text, file, "no '>>' shift");
  pos += 2;
  t.shift = read_uint(text, pos, file, "no shift count");
  if (pos != text.size()) bad_type(text, file, "trailing characters");
  if (t.used_bits == 0 || t.used_bits > 64) bad_type(text, file, "bit count must be 1..64");
  if (t.storage_bits < t.used_bits || t.storage_bits > 64)
    bad_type(text, file, "storage bits must be between the bit count and 64");
  if (t.shift >= t.storage_bits) bad_type(text, file, "shift must be below the storage bits");
  if (t.used_bits + t.shift > t.storage_bits)
    bad_type(text, file, "bit count plus shift exceed the storage bits");
  return t;
}

float decode_sample(const Channel &ch, const uint8_t *scan) {
  const ChannelType &t = ch.type;
  const unsigned nbytes = t.storage_bytes();
  const uint8_t *p = scan + ch.location;
  // Assemble the stored word. Big-endian (and single-byte) samples keep their stored bits at the
  // top of the word, as NNStreamer reads them; little-endian ones are masked to the storage bits.
  uint64_t v = 0;
  if (t.big_endian || nbytes == 1) {
    for (unsigned i = 0; i < nbytes; ++i) v = (v << 8) | p[i];
    v >>= (nbytes * 8 - t.storage_bits);
  } else {
    for (unsigned i = nbytes; i-- > 0;) v = (v << 8) | p[i];
    v &= mask_bits(t.storage_bits);
  }
  v >>= t.shift;
  v &= mask_bits(t.used_bits);
  // The width NNStreamer sign-extends in: the C type of the storage size (1, 2, 4 or 8 bytes).
  const unsigned width = nbytes == 1 ? 8 : nbytes == 2 ? 16 : nbytes <= 4 ? 32 : 64;
  if (t.is_signed) {
    const unsigned up = width - t.used_bits;
    switch (width) {
      case 8:
        return (static_cast<float>(static_cast<int8_t>(static_cast<uint8_t>(v << up)) >> up) +
                ch.offset) *
               ch.scale;
      case 16:
        return (static_cast<float>(static_cast<int16_t>(static_cast<uint16_t>(v << up)) >> up) +
                ch.offset) *
               ch.scale;
      case 32:
        return (static_cast<float>(static_cast<int32_t>(static_cast<uint32_t>(v << up)) >> up) +
                ch.offset) *
               ch.scale;
      default:
        return (static_cast<float>(static_cast<int64_t>(v << up) >> up) + ch.offset) * ch.scale;
    }
  }
  return (static_cast<float>(v) + ch.offset) * ch.scale;
}

std::size_t layout_scan(std::vector<Channel> &channels) {
  std::stable_sort(channels.begin(), channels.end(),
                   [](const Channel &a, const Channel &b) { return a.index < b.index; });
  std::size_t size = 0, largest = 1;
  for (auto &ch : channels) {
    if (!ch.enabled) continue;
    const std::size_t n = ch.type.storage_bytes();
    if (n == 0) continue;
    ch.location = (size + n - 1) / n * n;
    size = ch.location + n;
    largest = std::max(largest, n);
  }
  return size == 0 ? 0 : (size + largest - 1) / largest * largest;
}

}  // namespace nns::iio
