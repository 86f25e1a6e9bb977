// SPDX-License-Identifier: LGPL-2.1-only
#include "core/datarepo/datarepo_meta.h"

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace nns::datarepo {

namespace {

using json = nlohmann::json;

[[noreturn]] void bad(const std::string &path, const std::string &what) {
  fail(ErrorKind::kSettings, "data repository meta file " + path + ": " + what);
}

uint64_t get_count(const json &o, const char *key, const std::string &path) {
  auto it = o.find(key);
  if (it == o.end()) bad(path, std::string("no \"") + key + "\" member");
  if (!it->is_number_integer() || it->get<int64_t>() < 0)
    bad(path, std::string("\"") + key + "\" must be a non-negative integer, got " + it->dump());
  return it->get<uint64_t>();
}

std::vector<uint64_t> get_array(const json &o, const char *key, const std::string &path) {
  auto it = o.find(key);
  if (it == o.end()) bad(path, std::string("no \"") + key + "\" member");
  if (!it->is_array()) bad(path, std::string("\"") + key + "\" must be an array");
  std::vector<uint64_t> v;
  v.reserve(it->size());
  for (std::size_t i = 0; i < it->size(); ++i) {
    const json &e = (*it)[i];
    if (!e.is_number_integer() || e.get<int64_t>() < 0)
      bad(path, std::string("\"") + key + "\"[" + std::to_string(i) +
                    "] must be a non-negative integer, got " + e.dump());
    v.push_back(e.get<uint64_t>());
  }
  return v;
}

}  // namespace

std::size_t Meta::tensor_count_of(std::size_t i) const {
  const std::size_t end = i + 1 < tensor_count.size() ? tensor_count[i + 1] : tensor_size.size();
  return end - tensor_count[i];
}

uint64_t Meta::sample_bytes(std::size_t i) const {
  uint64_t n = 0;
  for (std::size_t k = 0; k < tensor_count_of(i); ++k) n += tensor_size[first_tensor(i) + k];
  return n;
}

Meta parse_meta(const std::string &text, const std::string &path) {
  json o;
  try {
    o = json::parse(text);
  } catch (const json::parse_error &e) {
    bad(path, std::string("not valid JSON (") + e.what() + ")");
  }
  if (!o.is_object()) bad(path, "the top level is not a JSON object");
  Meta m;
  auto caps = o.find("gst_caps");
  if (caps == o.end() || !caps->is_string()) bad(path, "no \"gst_caps\" string member");
  m.caps = caps->get<std::string>();
  m.total_samples = get_count(o, "total_samples", path);
  if (m.total_samples == 0) bad(path, "\"total_samples\" is 0");
  if (o.contains("sample_offset")) {
    m.sample_offset = get_array(o, "sample_offset", path);
    m.tensor_size = get_array(o, "tensor_size", path);
    m.tensor_count = get_array(o, "tensor_count", path);
    if (m.sample_offset.size() != m.total_samples || m.tensor_count.size() != m.total_samples)
      bad(path, "\"sample_offset\" has " + std::to_string(m.sample_offset.size()) +
                    " and \"tensor_count\" " + std::to_string(m.tensor_count.size()) +
                    " entries for " + std::to_string(m.total_samples) + " samples");
    for (std::size_t i = 0; i < m.tensor_count.size(); ++i) {
      if (m.tensor_count[i] > m.tensor_size.size() ||
          (i > 0 && m.tensor_count[i] < m.tensor_count[i - 1]))
        bad(path, "\"tensor_count\"[" + std::to_string(i) +
                      "] = " + std::to_string(m.tensor_count[i]) + " is out of order or past the " +
                      std::to_string(m.tensor_size.size()) + " entries of \"tensor_size\"");
    }
  } else {
    m.sample_size = get_count(o, "sample_size", path);
  }
  return m;
}

std::string write_meta(const Meta &m) {
  nlohmann::ordered_json o;  // NNStreamer's member order
  o["gst_caps"] = m.caps;
  o["total_samples"] = m.total_samples;
  if (m.per_sample()) {
    o["sample_offset"] = m.sample_offset;
    o["tensor_size"] = m.tensor_size;
    o["tensor_count"] = m.tensor_count;
  } else {
    o["sample_size"] = m.sample_size;
  }
  return o.dump(2) + "\n";
}

void check_against_file(const Meta &m, uint64_t file_size, const std::string &data_path,
                        const std::string &json_path) {
  auto cut = [&](uint64_t i, uint64_t off, uint64_t need) {
    fail(ErrorKind::kStream,
         "sample " + std::to_string(i) + " of " + data_path + " at byte offset " +
             std::to_string(off) + " needs " + std::to_string(need) + " bytes, but the file has " +
             std::to_string(off < file_size ? file_size - off : 0) + " from there (" +
             std::to_string(file_size) + " bytes in all; truncated file, or " + json_path +
             " does not describe it)");
  };
  if (!m.per_sample()) {
    if (m.sample_size == 0) return;  // images: one file per sample
    if (m.total_samples > file_size / m.sample_size) {
      const uint64_t i = file_size / m.sample_size;
      cut(i, i * m.sample_size, m.sample_size);
    }
    return;
  }
  for (std::size_t i = 0; i < m.total_samples; ++i) {
    const uint64_t off = m.sample_offset[i], n = m.sample_bytes(i);
    if (off > file_size || n > file_size - off) cut(i, off, n);
  }
}

}  // namespace nns::datarepo
