// SPDX-License-Identifier: LGPL-2.1-only
#include "grpc/tensor_link.h"

#include <gtest/gtest.h>

#include "nnstreamer.grpc.fb.h"
#include "nnstreamer.grpc.pb.h"

using namespace nns::grpclink;

TEST(GrpcTensorLink, ServiceNamesAreNNStreamers) {
  // The method paths NNStreamer's tensor_src_grpc / tensor_sink_grpc call.
  EXPECT_STREQ(nnstreamer::protobuf::TensorService::service_full_name(),
               "nnstreamer.protobuf.TensorService");
  const auto *d =
      nnstreamer::protobuf::Tensors::descriptor()->file()->FindServiceByName("TensorService");
  ASSERT_NE(d, nullptr);
  ASSERT_EQ(d->method_count(), 2);
  EXPECT_EQ(d->method(0)->name(), "SendTensors");
  EXPECT_TRUE(d->method(0)->client_streaming());
  EXPECT_FALSE(d->method(0)->server_streaming());
  EXPECT_EQ(d->method(1)->name(), "RecvTensors");
  EXPECT_TRUE(d->method(1)->server_streaming());
  EXPECT_EQ(d->method(0)->output_type()->full_name(), "google.protobuf.Empty");
}

TEST(GrpcTensorLink, MessageBytesMatchTheConverterSchema) {
  // Tensors{num_tensor=1, fr{30,1}, tensor{name "Anonymous", type uint8(5), dims 2, data "ab"}}
  nnstreamer::protobuf::Tensors m;
  m.set_num_tensor(1);
  m.mutable_fr()->set_rate_n(30);
  m.mutable_fr()->set_rate_d(1);
  auto *t = m.add_tensor();
  t->set_name("Anonymous");
  t->set_type(nnstreamer::protobuf::Tensor::NNS_UINT8);
  t->add_dimension(2);
  t->set_data("ab");
  const std::string b = m.SerializeAsString();
  const std::string want(
      "\x08\x01\x12\x04\x08\x1e\x10\x01\x1a\x14\x0a\x09"
      "Anonymous\x10\x05\x1a\x01\x02\x22\x02"
      "ab",
      30);
  EXPECT_EQ(b, want);
}

TEST(GrpcTensorLink, CheckFrame) {
  Frame f;
  EXPECT_NE(check_frame(f, 0).find("0 tensors"), std::string::npos);
  f.tensors.push_back({7, {2, 3, 0, 0}, std::string(24, 'x')});
  EXPECT_EQ(check_frame(f, 1), "");
  EXPECT_NE(check_frame(f, 2).find("num_tensor is 2 but the message holds 1"), std::string::npos);
  f.tensors[0].data.resize(23);
  EXPECT_EQ(check_frame(f, 1), "tensor 0: 23 bytes of data but its type and dimensions need 24");
  f.tensors[0].type = 11;
  EXPECT_NE(check_frame(f, 1).find("unknown type 11"), std::string::npos);
  f.tensors[0] = {5, std::vector<uint32_t>(17, 1), "x"};
  EXPECT_NE(check_frame(f, 1).find("17 dimensions"), std::string::npos);
  f.tensors[0] = {5, {0}, ""};
  EXPECT_NE(check_frame(f, 1).find("no dimensions"), std::string::npos);
  f.tensors[0] = {6, {0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu}, ""};
  EXPECT_NE(check_frame(f, 1).find("overflow"), std::string::npos);
}

TEST(GrpcTensorLink, FlatbufServiceNameIsNNStreamers) {
  EXPECT_STREQ(nnstreamer::flatbuf::TensorService::service_full_name(),
               "nnstreamer.flatbuf.TensorService");
}
