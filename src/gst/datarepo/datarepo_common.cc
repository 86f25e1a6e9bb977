// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/datarepo/datarepo_common.h"

#include <cstring>

#include "core/error.h"
#include "gst/tensor_caps.h"

namespace nns::gst::datarepo {

Kind kind_of(const GstCaps *caps) {
  if (!caps || gst_caps_is_empty(caps) || gst_caps_is_any(caps)) return Kind::kUnknown;
  const GstStructure *s = gst_caps_get_structure(caps, 0);
  const char *name = gst_structure_get_name(s);
  if (g_str_equal(name, "other/tensors") || g_str_equal(name, "other/tensor")) {
    const char *fmt = gst_structure_get_string(s, "format");
    return fmt && !g_str_equal(fmt, "static") ? Kind::kTensorFlexible : Kind::kTensorStatic;
  }
  if (g_str_equal(name, "video/x-raw")) return Kind::kVideo;
  if (g_str_equal(name, "audio/x-raw")) return Kind::kAudio;
  if (g_str_equal(name, "text/x-raw")) return Kind::kText;
  if (g_str_equal(name, "application/octet-stream")) return Kind::kOctet;
  if (g_str_has_prefix(name, "image/")) return Kind::kImage;
  return Kind::kUnknown;
}

const char *kind_name(Kind k) {
  switch (k) {
    case Kind::kTensorStatic:
      return "static tensors";
    case Kind::kTensorFlexible:
      return "flexible/sparse tensors";
    case Kind::kVideo:
      return "video";
    case Kind::kAudio:
      return "audio";
    case Kind::kText:
      return "text";
    case Kind::kOctet:
      return "octet stream";
    case Kind::kImage:
      return "images";
    default:
      return "unknown";
  }
}

namespace {

// Finds the one integer conversion: [start, end) of "%...d" in `p`; throws otherwise.
void find_conversion(const std::string &p, const char *prop, std::size_t *start, std::size_t *end) {
  std::size_t found = std::string::npos, found_end = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i] != '%') continue;
    if (i + 1 < p.size() && p[i + 1] == '%') {
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    while (j < p.size() && (p[j] == '0' || (p[j] >= '1' && p[j] <= '9'))) ++j;
    std::size_t len_mod = 0;
    while (j + len_mod < p.size() && p[j + len_mod] == 'l' && len_mod < 2) ++len_mod;
    j += len_mod;
    if (j >= p.size() || std::strchr("diu", p[j]) == nullptr || j - i > 12)
      fail(ErrorKind::kSettings, std::string(prop) + " '" + p + "': only one integer conversion " +
                                     "such as %d, %04d or %04ld may appear (found '" +
                                     p.substr(i, std::min<std::size_t>(j - i + 1, 8)) + "')");
    if (found != std::string::npos)
      fail(ErrorKind::kSettings,
           std::string(prop) + " '" + p + "' has more than one integer conversion");
    found = i;
    found_end = j + 1;
    i = j;
  }
  if (found == std::string::npos)
    fail(ErrorKind::kSettings, std::string(prop) + " '" + p +
                                   "' needs an integer conversion for the sample index, e.g. "
                                   "image_%04d.png");
  *start = found;
  *end = found_end;
}

std::string unescape(const std::string &s) {
  std::string out;
  for (std::size_t i = 0; i < s.size(); ++i) {
    out.push_back(s[i]);
    if (s[i] == '%' && i + 1 < s.size() && s[i + 1] == '%') ++i;
  }
  return out;
}

}  // namespace

void check_index_pattern(const std::string &pattern, const char *prop) {
  std::size_t a, b;
  find_conversion(pattern, prop, &a, &b);
}

std::string format_index(const std::string &p, uint64_t index, const char *prop) {
  std::size_t a, b;
  find_conversion(p, prop, &a, &b);
  // Width and zero padding from the conversion; the length modifier does not matter here.
  std::size_t i = a + 1;
  bool zero = i < b && p[i] == '0';
  unsigned width = 0;
  while (i < b && p[i] >= '0' && p[i] <= '9')
    width = width * 10 + static_cast<unsigned>(p[i++] - '0');
  std::string digits = std::to_string(index);
  if (digits.size() < width) digits.insert(0, width - digits.size(), zero ? '0' : ' ');
  return unescape(p.substr(0, a)) + digits + unescape(p.substr(b));
}

}  // namespace nns::gst::datarepo
