// SPDX-License-Identifier: LGPL-2.1-only
#include "core/custom_options.h"

#include <cctype>
#include <charconv>

#include "core/error.h"
#include "core/tensor_info.h"

namespace nns {

bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(a[i])) !=
        std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  return true;
}

namespace {

std::string join(std::initializer_list<std::string_view> v) {
  std::string s;
  for (auto x : v) {
    if (!s.empty()) s += ", ";
    s += x;
  }
  return s;
}

}  // namespace

CustomOptions::CustomOptions(const char *text, std::string_view owner,
                             std::initializer_list<std::string_view> accepted)
    : owner_(owner) {
  if (!text) return;
  for (const std::string &item : split(text, ",")) {
    if (item.empty()) continue;
    auto colon = item.find(':');
    if (colon == std::string::npos)
      fail(ErrorKind::kSettings,
           owner_ + ": custom option '" + item +
               "' is not of the form Key:Value (accepted keys: " + join(accepted) + ")");
    std::string key = trim(std::string_view(item).substr(0, colon));
    std::string value = trim(std::string_view(item).substr(colon + 1));
    const std::string_view *canon = nullptr;
    for (const auto &a : accepted)
      if (iequals(a, key)) canon = &a;
    if (!canon)
      fail(ErrorKind::kSettings, owner_ + ": unknown custom option key '" + key +
                                     "' (accepted keys: " + join(accepted) + ")");
    for (const auto &e : entries_)
      if (e.first == *canon)
        fail(ErrorKind::kSettings, owner_ + ": custom option '" + e.first + "' is given twice");
    entries_.emplace_back(std::string(*canon), value);
  }
}

std::optional<std::string> CustomOptions::get(std::string_view key) const {
  for (const auto &e : entries_)
    if (iequals(e.first, key)) return e.second;
  return std::nullopt;
}

void CustomOptions::bad_value(std::string_view key, const std::string &value,
                              const std::string &expected) const {
  fail(ErrorKind::kSettings, owner_ + ": custom option " + std::string(key) + ":" + value +
                                 " is invalid; expected " + expected);
}

std::optional<int64_t> CustomOptions::get_int(std::string_view key, int64_t min,
                                              int64_t max) const {
  auto v = get(key);
  if (!v) return std::nullopt;
  int64_t n = 0;
  auto [p, ec] = std::from_chars(v->data(), v->data() + v->size(), n);
  const std::string range =
      "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  if (ec != std::errc() || p != v->data() + v->size() || v->empty() || n < min || n > max)
    bad_value(key, *v, range);
  return n;
}

std::optional<bool> CustomOptions::get_bool(std::string_view key) const {
  auto v = get(key);
  if (!v) return std::nullopt;
  for (auto t : {"1", "true", "yes", "on"})
    if (iequals(*v, t)) return true;
  for (auto f : {"0", "false", "no", "off"})
    if (iequals(*v, f)) return false;
  bad_value(key, *v, "true or false (1/0, yes/no, on/off)");
}

std::optional<std::size_t> CustomOptions::get_choice(
    std::string_view key, std::initializer_list<std::string_view> choices) const {
  auto v = get(key);
  if (!v) return std::nullopt;
  std::size_t i = 0;
  for (auto c : choices) {
    if (iequals(*v, c)) return i;
    ++i;
  }
  bad_value(key, *v, "one of " + join(choices));
}

}  // namespace nns
