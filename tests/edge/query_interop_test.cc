// SPDX-License-Identifier: LGPL-2.1-only
// The capability a batching tensor_query_serversrc (max-batch > 1) sends to each new client,
// against the bytes NNStreamer 2.7.0's own server sends for the same pipeline at batch 1
// (captured in the run of docs/interop.md, "Query load balancing and batching"). NNStreamer's
// tensor_query_client sets its src caps from query_server_sink_caps only when they are fixed
// ("out-caps from tensor_query_serversink is not fixed" otherwise, then no answers): a batching
// server used to announce its per-request caps as lists of dimension spellings plus an
// other/tensor twin, which an upstream client refused. No upstream code at test time.
#include <atomic>
#include <cstring>

#include "edge/edge_io.h"
#include "edge_test_util.h"
#include "gst/gst_ptr.h"
#include "support/harness.h"

using namespace edge_test;

namespace {

// What NNStreamer 2.7.0's server sent (upstream appends the src caps a second time; the client
// reads the first field of each name) for
//   tensor_query_serversrc ! other/tensors,format=static,num_tensors=1,
//     dimensions=(string)3:8:6:1,types=uint8,framerate=0/1 ! tensor_transform mode=arithmetic
//     option=add:1 ! (the same caps) ! tensor_query_serversink
const char *kUpstreamAdd =
    "@query_server_src_caps@other/tensors, format=(string)static, num_tensors=(int)1, "
    "dimensions=(string)3:8:6:1, types=(string)uint8, framerate=(fraction)0/1"
    "@query_server_sink_caps@other/tensors, format=(string)static, num_tensors=(int)1, "
    "dimensions=(string)3:8:6:1, types=(string)uint8, framerate=(fraction)0/1"
    "@query_server_src_caps@other/tensors, format=(string)static, num_tensors=(int)1, "
    "dimensions=(string)3:8:6:1, types=(string)uint8, framerate=(fraction)0/1";
// The same with tensor_transform mode=typecast option=float32 and float32 caps before the sink
// (upstream's sink caps come from an intersection: another field order).
const char *kUpstreamTypecastSink =
    "other/tensors, format=(string)static, num_tensors=(int)1, framerate=(fraction)0/1, "
    "dimensions=(string)3:8:6:1, types=(string)float32";

std::string caps(int n, const char *type) {
  return "other/tensors,format=static,num_tensors=1,dimensions=(string)3:8:6:" + std::to_string(n) +
         ",types=" + type + ",framerate=0/1";
}

// Starts `desc` (a server on `port`) in this process and returns the capability string it sends
// first to a raw TCP client.
std::string capability_of(const std::string &desc, uint16_t port) {
  GError *err = nullptr;
  GstElement *pipe = gst_parse_launch(desc.c_str(), &err);
  if (err) {
    ADD_FAILURE() << err->message;
    g_error_free(err);
    return "";
  }
  gst_element_set_state(pipe, GST_STATE_PLAYING);  // listens from READY->PAUSED on
  std::string why, out;
  namespace e = nns::edge;
  e::Fd fd = e::tcp_connect("127.0.0.1", port, 2000, &why);
  if (!fd.valid()) {
    ADD_FAILURE() << why;
  } else {
    std::atomic<bool> stop{false};
    e::Message m;
    if (e::read_frame(fd.get(), e::Limits{}, e::heap_payload, stop, 5000, &m, &why) !=
        e::IoStatus::kOk)
      ADD_FAILURE() << why;
    else if (m.header.cmd != e::Cmd::kCapability || m.mems.size() != 1)
      ADD_FAILURE() << "the first frame is not a capability";
    else
      out.assign(reinterpret_cast<const char *>(m.mems[0]->data()),
                 strnlen(reinterpret_cast<const char *>(m.mems[0]->data()), m.mems[0]->size()));
  }
  fd.reset();
  gst_element_set_state(pipe, GST_STATE_NULL);
  gst_object_unref(pipe);
  return out;
}

// The part after "@name@" up to the next '@' (the first occurrence, as both clients read it).
std::string field(const std::string &cap, const std::string &name) {
  const std::string key = "@" + name + "@";
  const auto at = cap.find(key);
  if (at == std::string::npos) return "";
  const auto from = at + key.size();
  return cap.substr(from, cap.find('@', from) - from);
}

std::string server(uint16_t port, int max_batch, const std::string &middle, const char *out_type) {
  return "tensor_query_serversrc host=127.0.0.1 port=" + std::to_string(port) +
         " max-batch=" + std::to_string(max_batch) + " ! " + caps(max_batch, "uint8") + " ! " +
         middle + " ! " + caps(max_batch, out_type) + " ! tensor_query_serversink";
}

}  // namespace

TEST(QueryInterop, BatchingServerAnnouncesNNStreamersFixedCaps) {
  for (int n : {1, 4}) {
    const uint16_t port = free_port();
    const std::string cap = capability_of(
        server(port, n, "tensor_transform mode=arithmetic option=add:1", "uint8"), port);
    // Byte for byte upstream's, up to its repeated src field.
    EXPECT_EQ(cap, std::string(kUpstreamAdd).substr(0, cap.size())) << "max-batch=" << n;
    EXPECT_FALSE(cap.empty());
    nns::gst::CapsPtr sink(gst_caps_from_string(field(cap, "query_server_sink_caps").c_str()));
    ASSERT_TRUE(sink) << cap;
    EXPECT_TRUE(gst_caps_is_fixed(sink.get())) << "max-batch=" << n << ": " << cap;
  }
}

TEST(QueryInterop, BatchingServerAnswerCapsFixedAndEqualUpstreams) {
  const uint16_t port = free_port();
  const std::string cap = capability_of(
      server(port, 4, "tensor_transform mode=typecast option=float32", "float32"), port);
  EXPECT_EQ(field(cap, "query_server_src_caps"), field(kUpstreamAdd, "query_server_src_caps"))
      << cap;
  nns::gst::CapsPtr sink(gst_caps_from_string(field(cap, "query_server_sink_caps").c_str()));
  nns::gst::CapsPtr want(gst_caps_from_string(kUpstreamTypecastSink));
  ASSERT_TRUE(sink && want) << cap;
  EXPECT_TRUE(gst_caps_is_fixed(sink.get())) << cap;
  EXPECT_TRUE(gst_caps_is_equal(sink.get(), want.get())) << cap;
}
