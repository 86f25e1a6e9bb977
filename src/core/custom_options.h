// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter custom= parsing shared by back ends: "Key:Value,Key:Value". Keys are matched
// case-insensitively against the back end's accepted list; an unknown key is an error naming
// it and every accepted key. Values keep their case.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nns {

class CustomOptions {
 public:
  // Parses `text` (NULL/empty: no options). `owner` names the back end in messages
  // ("onnxruntime"). Throws nns::Error(kSettings) on an unknown key, a missing ':' or a key
  // given twice.
  CustomOptions(const char *text, std::string_view owner,
                std::initializer_list<std::string_view> accepted);

  // Value of `key` (one of the accepted spellings) if given.
  std::optional<std::string> get(std::string_view key) const;
  // Integer value in [min, max]; throws naming the key, the value and the range.
  std::optional<int64_t> get_int(std::string_view key, int64_t min, int64_t max) const;
  // Boolean: 1/0, true/false, yes/no, on/off (any case).
  std::optional<bool> get_bool(std::string_view key) const;
  // One of `choices` (case-insensitive); returns its index. Throws listing the choices.
  std::optional<std::size_t> get_choice(std::string_view key,
                                        std::initializer_list<std::string_view> choices) const;

  const std::vector<std::pair<std::string, std::string>> &entries() const { return entries_; }

 private:
  [[noreturn]] void bad_value(std::string_view key, const std::string &value,
                              const std::string &expected) const;

  std::string owner_;
  std::vector<std::pair<std::string, std::string>> entries_;  // canonical key, value
};

bool iequals(std::string_view a, std::string_view b);

}  // namespace nns
