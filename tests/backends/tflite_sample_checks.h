// SPDX-License-Identifier: LGPL-2.1-only
// Checks of upstream's small .tflite samples (../shared/models/models) that hold for every back
// end that runs them (tensorflow2-lite, armnn): one definition of what each sample computes.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "backends/backend_loader.h"

namespace nns::test {

// add.tflite: one float32 input "X_input" of dims 1, output "ADD_TOP" = input + 2.
inline void expect_add_sample(Instance &inst) {
  nns_tensors_desc in, out;
  ASSERT_EQ(inst.model_info(in, out), 0) << inst.error();
  ASSERT_EQ(in.num_tensors, 1u);
  ASSERT_EQ(out.num_tensors, 1u);
  EXPECT_EQ(in.tensors[0].type, static_cast<uint32_t>(_NNS_FLOAT32));
  EXPECT_EQ(in.tensors[0].dims[0], 1u);
  EXPECT_EQ(in.tensors[0].dims[1], 0u);
  EXPECT_STREQ(in.tensors[0].name, "X_input");
  EXPECT_STREQ(out.tensors[0].name, "ADD_TOP");
  for (float x : {0.f, 1.5f, -3.f, 1000.f}) {
    float o = -1;
    std::vector<GstTensorMemory> ins{{&x, 4}};
    std::vector<GstTensorMemory> outs{{&o, 4}};
    ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
    EXPECT_FLOAT_EQ(o, x + 2.f);  // the graph adds the constant 2
  }
}

// simple_32_in_32_out.tflite: 32 inputs and 32 outputs, in the model's (shuffled) order: output
// "PartitionedCall:j" is input "serving_default_input_<111+j>:0" plus one.
inline void expect_thirty_two_sample(Instance &inst) {
  nns_tensors_desc in, out;
  ASSERT_EQ(inst.model_info(in, out), 0) << inst.error();
  ASSERT_EQ(in.num_tensors, 32u);
  ASSERT_EQ(out.num_tensors, 32u);
  std::vector<float> x(32), o(32, -1.f);
  std::vector<GstTensorMemory> ins, outs;
  for (int k = 0; k < 32; ++k) {
    x[k] = 10.f * k;
    ins.push_back({&x[k], 4});
    outs.push_back({&o[k], 4});
  }
  ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
  for (uint32_t j = 0; j < 32; ++j) {
    std::string oname = out.tensors[j].name;
    ASSERT_EQ(oname.rfind("PartitionedCall:", 0), 0u) << oname;
    int idx = std::stoi(oname.substr(16));
    std::string want_in = "serving_default_input_" + std::to_string(111 + idx) + ":0";
    int src = -1;
    for (uint32_t k = 0; k < 32; ++k)
      if (want_in == in.tensors[k].name) src = static_cast<int>(k);
    ASSERT_GE(src, 0) << want_in;
    EXPECT_FLOAT_EQ(o[j], x[src] + 1.f) << oname;
  }
}

}  // namespace nns::test
