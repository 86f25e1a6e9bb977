// SPDX-License-Identifier: LGPL-2.1-only
// Helpers of the tensor_decoder sub-plugin tests (image_segment, pose_estimation): an all-zero
// tensor source and the check of a decoder's bus error.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <fstream>
#include <string>

#include "support/harness.h"

namespace nns::test::decoder {

// Pipeline head: one buffer of `bytes` zero bytes (a file in a fresh temp folder) through
// tensor_converter as a tensor of `dims` and `types`, ending in " ! ".
inline std::string tensor_file_src(const std::string &dims, std::size_t bytes,
                                   const std::string &types = "float32") {
  std::string path = nns::test::make_temp_dir() + "/in.bin";
  std::ofstream(path) << std::string(bytes, '\0');
  return "filesrc location=" + path +
         " blocksize=-1 num-buffers=1 ! application/octet-stream ! tensor_converter input-dim=" +
         dims + " input-type=" + types + " ! ";
}

// Runs `desc`: it must end in an error from the tensor_decoder whose text contains `want`.
inline void expect_error(const std::string &desc, const std::string &want) {
  auto r = nns::test::run_pipeline(desc);
  EXPECT_FALSE(r.eos);
  EXPECT_NE(r.error_text.find(want), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("tensordecoder"), std::string::npos) << r.error_text;
}

}  // namespace nns::test::decoder
