// SPDX-License-Identifier: LGPL-2.1-only
// The JSON meta file of an NNStreamer data repository (datareposink writes it beside the sample
// file, datareposrc reads it): the samples' caps, their count, and either one fixed sample size
// or, for flexible/sparse tensors, where each sample starts and the byte size of each of its
// tensors. Same keys and meaning as NNStreamer's, so either side can be NNStreamer's:
//   { "gst_caps": "...", "total_samples": N, "sample_size": S }
//   { "gst_caps": "...", "total_samples": N, "sample_offset": [...], "tensor_size": [...],
//     "tensor_count": [...] }       (tensor_count[i]: index of sample i's first tensor)
// GStreamer-free; everything read is checked before it is trusted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nns::datarepo {

struct Meta {
  std::string caps;
  uint64_t total_samples = 0;
  uint64_t sample_size = 0;  // fixed-size samples; 0 when the arrays below are used
  std::vector<uint64_t> sample_offset;
  std::vector<uint64_t> tensor_size;
  std::vector<uint64_t> tensor_count;

  bool per_sample() const { return !sample_offset.empty(); }
  // Tensors of sample i in the per-sample layout: [first, first + count).
  std::size_t first_tensor(std::size_t i) const { return tensor_count[i]; }
  std::size_t tensor_count_of(std::size_t i) const;
  uint64_t sample_bytes(std::size_t i) const;  // per-sample layout: sum of its tensor sizes
};

// Parses the JSON text; `path` names the file in errors. Throws nns::Error(kSettings) naming
// the missing or malformed member. Does not need the sample file.
Meta parse_meta(const std::string &json_text, const std::string &path);
// Pretty-printed JSON with NNStreamer's member names.
std::string write_meta(const Meta &m);

// Checks the meta against the sample file's size: every sample of [0, total_samples) lies inside
// the file, arrays agree in length and order. Throws nns::Error(kStream) naming the sample
// index and byte offset of the first problem (e.g. a truncated sample file).
void check_against_file(const Meta &m, uint64_t file_size, const std::string &data_path,
                        const std::string &json_path);

}  // namespace nns::datarepo
