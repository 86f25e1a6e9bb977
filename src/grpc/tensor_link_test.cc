// SPDX-License-Identifier: LGPL-2.1-only
#include "grpc/tensor_link.h"

#include <gtest/gtest.h>

#include "nnstreamer.grpc.fb.h"
#include "nnstreamer.grpc.pb.h"
#include "nnstreamer_generated.h"

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

namespace {

std::string unhex(const std::string &h) {
  std::string b;
  for (std::size_t i = 0; i + 1 < h.size(); i += 2)
    b.push_back(static_cast<char>(std::stoi(h.substr(i, 2), nullptr, 16)));
  return b;
}

// videotestsrc pattern=ball ! video/x-raw,format=RGB,width=4,height=2,framerate=10/1 !
// tensor_converter: one uint8 3:4:2:1 tensor of 24 x 0xff, 10/1.
Frame ball_frame() {
  Frame f;
  f.rate_n = 10;
  f.rate_d = 1;
  std::vector<uint32_t> dims(16, 0);
  dims[0] = 3;
  dims[1] = 4;
  dims[2] = 2;
  dims[3] = 1;
  f.tensors.push_back({5, dims, std::string(24, '\xff')});
  return f;
}

}  // namespace

// The messages NNStreamer 2.7.0's tensor_sink_grpc (nnstreamer 5b13ea6) sent for ball_frame(),
// captured on the wire (gRPC length prefix removed; docs/interop.md). Ours sends the same bytes,
// and reads them back to the same frame.
TEST(GrpcTensorLink, ProtobufBytesCapturedFromNNStreamer270) {
  const std::string up = unhex(
      "08011204080a10011a390a09416e6f6e796d6f757310051a1003040201000000"
      "0000000000000000002218ffffffffffffffffffffffffffffffffffffffffff"
      "ffffff");
  EXPECT_EQ(protobuf_wire_bytes(ball_frame()), up);
  nnstreamer::protobuf::Tensors m;
  ASSERT_TRUE(m.ParseFromString(up));
  EXPECT_EQ(m.num_tensor(), 1u);
  EXPECT_EQ(m.tensor(0).dimension_size(), 16);
}

TEST(GrpcTensorLink, FlatbufBytesCapturedFromNNStreamer270) {
  // Upstream builds each Tensor's dimension vector before its name; a different builder order
  // gives a different (equally valid) buffer, so this pins the order too.
  const std::string up = unhex(
      "1000000000000a0014000400080010000a000000010000000a00000001000000"
      "0400000001000000100000000c001400040008000c0010000c0000002c000000"
      "05000000340000000400000018000000ffffffffffffffffffffffffffffffff"
      "ffffffffffffffff09000000416e6f6e796d6f75730000001000000003000000"
      "0400000002000000010000000000000000000000000000000000000000000000"
      "00000000000000000000000000000000000000000000000000000000");
  ASSERT_EQ(up.size(), 188u);
  EXPECT_EQ(flatbuf_wire_bytes(ball_frame()), up);
  flatbuffers::Verifier v(reinterpret_cast<const uint8_t *>(up.data()), up.size());
  ASSERT_TRUE(nnstreamer::flatbuf::VerifyTensorsBuffer(v));
  const auto *t = nnstreamer::flatbuf::GetTensors(up.data());
  EXPECT_EQ(t->num_tensor(), 1);
  EXPECT_EQ(t->fr()->rate_n(), 10);
  EXPECT_EQ(t->tensor()->Get(0)->dimension()->size(), 16u);
  EXPECT_EQ(t->tensor()->Get(0)->data()->size(), 24u);
}
