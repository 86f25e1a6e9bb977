// SPDX-License-Identifier: LGPL-2.1-only
// tensor_src_grpc / tensor_sink_grpc on 127.0.0.1 free ports: src server <- sink client and
// sink server -> src client with exact bytes for several types and shapes; a raw gRPC peer
// (the generated stub of NNStreamer's service) sending a bad message; peers gone; settings.
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "../mqtt/mosquitto_broker.h"
#include "gst/extra_plugins.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"
#include "nnstreamer.grpc.fb.h"
#include "nnstreamer_generated.h"
#include "nnstreamer.grpc.pb.h"
#include "support/deadline.h"
#include "support/harness.h"

using namespace std::chrono_literals;

namespace {

// tensor_src_grpc/tensor_sink_grpc are the "nnstreamer_grpc" plugin (libnnstreamer-grpc.so):
// registered in this process too, after test_main's gst_init().
class GrpcPlugin : public ::testing::Environment {
  void SetUp() override { ASSERT_TRUE(nns_grpc_register_static()); }
};
[[maybe_unused]] ::testing::Environment *const g_grpc_plugin =
    ::testing::AddGlobalTestEnvironment(new GrpcPlugin);

class Pipe {
 public:
  explicit Pipe(const std::string &desc) {
    GError *err = nullptr;
    pipe_ = gst_parse_launch(desc.c_str(), &err);
    if (err) {
      ADD_FAILURE() << err->message;
      g_error_free(err);
    }
    bus_ = gst_element_get_bus(pipe_);
  }
  ~Pipe() {
    nns::test::finish_within(15, "pipeline to NULL",
                             [&] { gst_element_set_state(pipe_, GST_STATE_NULL); });
    gst_object_unref(bus_);
    gst_object_unref(pipe_);
  }
  GstElement *get(const char *name) {
    GstElement *e = gst_bin_get_by_name(GST_BIN(pipe_), name);
    gst_object_unref(e);
    return e;
  }
  void play() { gst_element_set_state(pipe_, GST_STATE_PLAYING); }
  bool wait_state(const char *name, GstState want) {
    GstState s = GST_STATE_NULL;
    const auto end = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < end) {
      gst_element_get_state(get(name), &s, nullptr, 0);
      if (s >= want) return true;
      std::this_thread::sleep_for(10ms);
    }
    return false;
  }
  // Waits for ERROR or EOS; returns the error text ("" on EOS or timeout).
  std::string wait_end(bool *eos = nullptr, std::chrono::seconds t = 15s) {
    GstMessage *m = gst_bus_timed_pop_filtered(
        bus_, static_cast<GstClockTime>(t.count()) * GST_SECOND,
        static_cast<GstMessageType>(GST_MESSAGE_ERROR | GST_MESSAGE_EOS));
    if (!m) return "";
    std::string text;
    if (GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
      GError *e = nullptr;
      gst_message_parse_error(m, &e, nullptr);
      text = e->message;
      g_error_free(e);
    } else if (eos) {
      *eos = true;
    }
    gst_message_unref(m);
    return text;
  }
  GstElement *pipe_ = nullptr;

 private:
  GstBus *bus_ = nullptr;
};

struct Shape {
  std::string caps;
  std::vector<gsize> sizes;
};

const Shape kShapes[] = {
    {"other/tensors,format=static,num_tensors=2,dimensions=(string)\"3:4:2,5\","
     "types=(string)\"uint8,float32\",framerate=(fraction)30/1",
     {24, 20}},
    {"other/tensor,dimension=(string)7:1:1:1,type=(string)int16,framerate=(fraction)10/1", {14}},
    {"other/tensors,format=static,num_tensors=3,dimensions=(string)\"2,1:1:1:1:1:1:1:2,4:4\","
     "types=(string)\"float64,int64,uint32\",framerate=(fraction)5/2",
     {16, 16, 64}},
};

GstBuffer *make_buffer(const std::vector<gsize> &sizes, int seed) {
  GstBuffer *b = gst_buffer_new();
  for (gsize s : sizes) {
    GstMemory *m = gst_allocator_alloc(nullptr, s, nullptr);
    GstMapInfo map;
    gst_memory_map(m, &map, GST_MAP_WRITE);
    for (gsize i = 0; i < s; ++i) map.data[i] = static_cast<guint8>(seed * 13 + i * 3 + s);
    gst_memory_unmap(m, &map);
    gst_buffer_append_memory(b, m);
  }
  return b;
}

std::vector<uint8_t> bytes_of(GstBuffer *b) {
  std::vector<uint8_t> v(gst_buffer_get_size(b));
  gst_buffer_extract(b, 0, v.data(), v.size());
  return v;
}

std::string tx_desc(const std::string &extra) {
  return "appsrc name=in format=time ! tensor_sink_grpc name=sink host=127.0.0.1 " + extra;
}
std::string rx_desc(const std::string &extra) {
  return "tensor_src_grpc name=src host=127.0.0.1 " + extra +
         " ! appsink name=out sync=false max-buffers=100";
}

void set_caps(Pipe &p, const std::string &caps) {
  GstCaps *c = gst_caps_from_string(caps.c_str());
  ASSERT_NE(c, nullptr) << caps;
  g_object_set(p.get("in"), "caps", c, nullptr);
  gst_caps_unref(c);
}

// N frames through, checked exactly: bytes, memories, caps, count x framerate timestamps.
void expect_frames(Pipe &rx, const Shape &s, int n) {
  GstCaps *want = gst_caps_from_string(s.caps.c_str());
  for (int i = 0; i < n; ++i) {
    GstSample *smp = gst_app_sink_try_pull_sample(GST_APP_SINK(rx.get("out")), 10 * GST_SECOND);
    ASSERT_NE(smp, nullptr) << "frame " << i;
    GstBuffer *got = gst_sample_get_buffer(smp);
    nns::gst::BufferPtr exp(make_buffer(s.sizes, i));
    EXPECT_EQ(bytes_of(got), bytes_of(exp.get()));
    ASSERT_EQ(gst_buffer_n_memory(got), s.sizes.size());
    GstCaps *caps = gst_sample_get_caps(smp);
    EXPECT_TRUE(nns::gst::config_from_caps(caps).same_as(nns::gst::config_from_caps(want)))
        << nns::gst::caps_to_string(caps) << " vs " << s.caps;
    GstStructure *st = gst_caps_get_structure(caps, 0);
    gint rn = 0, rd = 1;
    gst_structure_get_fraction(st, "framerate", &rn, &rd);
    EXPECT_EQ(GST_BUFFER_PTS(got), gst_util_uint64_scale(i, rd * GST_SECOND, rn));
    gst_sample_unref(smp);
  }
  gst_caps_unref(want);
}

}  // namespace

class TensorGrpcIdl : public ::testing::TestWithParam<const char *> {};
INSTANTIATE_TEST_SUITE_P(Idl, TensorGrpcIdl, ::testing::Values("protobuf", "flatbuf"));

TEST_P(TensorGrpcIdl, SrcServerFromSinkClient) {
  const std::string idl = std::string(" idl=") + GetParam();
  for (const auto &s : kShapes) {
    SCOPED_TRACE(s.caps);
    const uint16_t port = mqtt_test::free_port();
    Pipe rx(rx_desc("port=" + std::to_string(port) + idl));
    rx.play();
    ASSERT_TRUE(rx.wait_state("src", GST_STATE_PAUSED));
    Pipe tx(tx_desc("port=" + std::to_string(port) + idl));
    set_caps(tx, s.caps);
    tx.play();
    for (int i = 0; i < 4; ++i)
      ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(tx.get("in")), make_buffer(s.sizes, i)),
                GST_FLOW_OK);
    expect_frames(rx, s, 4);
    guint out = 0;
    g_object_get(tx.get("sink"), "out", &out, nullptr);
    EXPECT_EQ(out, 4u);
    g_object_get(rx.get("src"), "out", &out, nullptr);
    EXPECT_EQ(out, 4u);
  }
}

TEST_P(TensorGrpcIdl, SinkServerToSrcClient) {
  const std::string idl = std::string(" idl=") + GetParam();
  for (const auto &s : kShapes) {
    SCOPED_TRACE(s.caps);
    const uint16_t port = mqtt_test::free_port();
    Pipe tx(tx_desc("server=true port=" + std::to_string(port) + idl));
    set_caps(tx, s.caps);
    tx.play();
    ASSERT_TRUE(tx.wait_state("sink", GST_STATE_READY));
    for (int i = 0; i < 4; ++i)
      ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(tx.get("in")), make_buffer(s.sizes, i)),
                GST_FLOW_OK);
    Pipe rx(rx_desc("server=false port=" + std::to_string(port) + idl));
    rx.play();
    expect_frames(rx, s, 4);
    // The server ends: the client sees the stream finish and ends with EOS.
    gst_app_src_end_of_stream(GST_APP_SRC(tx.get("in")));
    bool tx_eos = false;
    EXPECT_EQ(tx.wait_end(&tx_eos), "");
    EXPECT_TRUE(tx_eos);
    nns::test::finish_within(10, "server to NULL",
                             [&] { gst_element_set_state(tx.pipe_, GST_STATE_NULL); });
    bool rx_eos = false;
    EXPECT_EQ(rx.wait_end(&rx_eos), "");
    EXPECT_TRUE(rx_eos);
  }
}

// A downstream capsfilter written as upstream's tests write several tensors ('.' between them,
// no quotes) negotiates with the frames' caps: same config, the filter's spelling downstream.
TEST(TensorGrpc, DotSpelledCapsfilterAfterSrc) {
  const Shape &s = kShapes[0];  // 3:4:2,5 uint8,float32 at 30/1
  const char *dot =
      "other/tensors,format=static,num_tensors=2,types=uint8.float32,dimensions=3:4:2.5,"
      "framerate=30/1";
  const uint16_t port = mqtt_test::free_port();
  Pipe rx(rx_desc("port=" + std::to_string(port) + " ! " + dot));
  rx.play();
  ASSERT_TRUE(rx.wait_state("src", GST_STATE_PAUSED));
  Pipe tx(tx_desc("port=" + std::to_string(port)));
  set_caps(tx, s.caps);
  tx.play();
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(tx.get("in")), make_buffer(s.sizes, i)),
              GST_FLOW_OK);
  expect_frames(rx, s, 2);
  GstPad *pad = gst_element_get_static_pad(rx.get("src"), "src");
  nns::gst::CapsPtr cur(gst_pad_get_current_caps(pad));
  gst_object_unref(pad);
  ASSERT_TRUE(cur);
  const GstStructure *st = gst_caps_get_structure(cur.get(), 0);
  EXPECT_STREQ(gst_structure_get_string(st, "types"), "uint8.float32");
  EXPECT_STREQ(gst_structure_get_string(st, "dimensions"), "3:4:2.5");
}

// The same filter with another dimension still fails, naming the frames' caps and the filter's.
TEST(TensorGrpc, DotSpelledCapsfilterWithOtherDimensionsFails) {
  const Shape &s = kShapes[0];
  const uint16_t port = mqtt_test::free_port();
  Pipe rx(rx_desc("port=" + std::to_string(port) +
                  " ! other/tensors,format=static,num_tensors=2,types=uint8.float32,"
                  "dimensions=3:4:2.6,framerate=30/1"));
  rx.play();
  ASSERT_TRUE(rx.wait_state("src", GST_STATE_PAUSED));
  Pipe tx(tx_desc("port=" + std::to_string(port)));
  set_caps(tx, s.caps);
  tx.play();
  ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(tx.get("in")), make_buffer(s.sizes, 0)),
            GST_FLOW_OK);
  const std::string err = rx.wait_end();
  EXPECT_NE(err.find("dimensions=(string)\"3:4:2\\,5\""), std::string::npos) << err;
  EXPECT_NE(err.find("3:4:2.6"), std::string::npos) << err;
}

// A peer speaking NNStreamer's service directly (the generated stub) with a frame whose data
// does not match its dimensions: the server errors naming the client and the problem.
TEST(TensorGrpc, BadMessageFromAPeer) {
  const uint16_t port = mqtt_test::free_port();
  Pipe rx(rx_desc("port=" + std::to_string(port)));
  rx.play();
  ASSERT_TRUE(rx.wait_state("src", GST_STATE_PAUSED));
  auto ch =
      grpc::CreateChannel("127.0.0.1:" + std::to_string(port), grpc::InsecureChannelCredentials());
  auto stub = nnstreamer::protobuf::TensorService::NewStub(ch);
  grpc::ClientContext ctx;
  google::protobuf::Empty reply;
  auto w = stub->SendTensors(&ctx, &reply);
  nnstreamer::protobuf::Tensors m;
  m.set_num_tensor(1);
  m.mutable_fr()->set_rate_n(1);
  m.mutable_fr()->set_rate_d(1);
  auto *t = m.add_tensor();
  t->set_type(nnstreamer::protobuf::Tensor::NNS_FLOAT32);
  t->add_dimension(4);
  t->set_data(std::string(15, 'x'));
  w->Write(m);
  w->WritesDone();
  const grpc::Status st = w->Finish();
  EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  const std::string err = rx.wait_end();
  EXPECT_NE(err.find("src: client ipv4:127.0.0.1:"), std::string::npos) << err;
  EXPECT_NE(err.find("sent a bad message: tensor 0: 15 bytes of data but its type and "
                     "dimensions need 16"),
            std::string::npos)
      << err;
}

TEST(TensorGrpc, PeerMissingOrGone) {
  const uint16_t port = mqtt_test::free_port();
  {
    Pipe rx(rx_desc("server=false port=" + std::to_string(port)));
    rx.play();
    const std::string err = rx.wait_end();
    EXPECT_NE(err.find("src: server 127.0.0.1:" + std::to_string(port)), std::string::npos) << err;
    EXPECT_NE(err.find("gRPC status 14"), std::string::npos) << err;  // UNAVAILABLE
  }
  // The receiving server goes away mid-stream: the sending client errors, no hang.
  auto rx = std::make_unique<Pipe>(rx_desc("port=" + std::to_string(port)));
  rx->play();
  ASSERT_TRUE(rx->wait_state("src", GST_STATE_PAUSED));
  Pipe tx(tx_desc("port=" + std::to_string(port)));
  set_caps(tx, kShapes[1].caps);
  tx.play();
  gst_app_src_push_buffer(GST_APP_SRC(tx.get("in")), make_buffer(kShapes[1].sizes, 0));
  GstSample *smp = gst_app_sink_try_pull_sample(GST_APP_SINK(rx->get("out")), 10 * GST_SECOND);
  ASSERT_NE(smp, nullptr);
  gst_sample_unref(smp);
  rx.reset();
  std::string err;
  for (int i = 1; i < 200 && err.empty(); ++i) {
    gst_app_src_push_buffer(GST_APP_SRC(tx.get("in")), make_buffer(kShapes[1].sizes, i));
    err = tx.wait_end(nullptr, 0s);
    std::this_thread::sleep_for(10ms);
  }
  if (err.empty()) err = tx.wait_end(nullptr, 5s);
  EXPECT_NE(err.find("sink: server 127.0.0.1:" + std::to_string(port)), std::string::npos) << err;
}

TEST(TensorGrpc, SettingsAndDefaults) {
  GstElement *src = gst_element_factory_make("tensor_src_grpc", nullptr);
  GstElement *sink = gst_element_factory_make("tensor_sink_grpc", nullptr);
  ASSERT_TRUE(src && sink);
  gboolean server_src = FALSE, server_sink = TRUE, blocking = FALSE, silent = FALSE;
  gint port = 0;
  gchar *idl = nullptr, *host = nullptr;
  g_object_get(src, "server", &server_src, "port", &port, "idl", &idl, "host", &host, "blocking",
               &blocking, "silent", &silent, nullptr);
  g_object_get(sink, "server", &server_sink, nullptr);
  EXPECT_TRUE(server_src);
  EXPECT_FALSE(server_sink);
  EXPECT_EQ(port, 55115);
  EXPECT_STREQ(idl, "protobuf");
  EXPECT_STREQ(host, "localhost");
  EXPECT_TRUE(blocking);
  EXPECT_TRUE(silent);
  g_free(idl);
  g_free(host);
  gst_object_unref(src);
  gst_object_unref(sink);
  {
    Pipe rx(rx_desc("idl=json port=0"));
    rx.play();
    EXPECT_NE(rx.wait_end().find("src: idl 'json' is not one of protobuf, flatbuf"),
              std::string::npos);
  }
  {
    // port=0 picks a free port and reports it.
    Pipe rx(rx_desc("port=0"));
    rx.play();
    ASSERT_TRUE(rx.wait_state("src", GST_STATE_PAUSED));
    gint p = 0;
    g_object_get(rx.get("src"), "port", &p, nullptr);
    EXPECT_GT(p, 0);
  }
}

// NNStreamer's srcInvalidHost_n / sinkInvalidHost_n: a host that is neither localhost nor an IP
// address is refused when set (the previous host reads back); starting then fails naming it.
TEST(TensorGrpc, InvalidHostIsRefused) {
  for (const char *factory : {"tensor_src_grpc", "tensor_sink_grpc"}) {
    SCOPED_TRACE(factory);
    GstElement *e = gst_element_factory_make(factory, nullptr);
    ASSERT_TRUE(e);
    auto host = [&] {
      gchar *h = nullptr;
      g_object_get(e, "host", &h, nullptr);
      std::string out = h ? h : "<NULL>";
      g_free(h);
      return out;
    };
    g_object_set(e, "host", "invalid host", nullptr);
    EXPECT_EQ(host(), "localhost");
    g_object_set(e, "host", "1.1.1.1", nullptr);
    EXPECT_EQ(host(), "1.1.1.1");
    g_object_set(e, "host", "::1", nullptr);
    EXPECT_EQ(host(), "::1");
    g_object_set(e, "host", "no.such.name", nullptr);
    EXPECT_EQ(host(), "::1");
    gst_object_unref(e);
  }
  {
    Pipe rx(rx_desc("port=0 host=\"invalid host\""));
    rx.play();
    const std::string err = rx.wait_end();
    EXPECT_NE(err.find("src: host 'invalid host' was refused"), std::string::npos) << err;
    EXPECT_NE(err.find("kept '127.0.0.1'"), std::string::npos) << err;
  }
  {
    Pipe tx(tx_desc("port=1 host=bad_host"));
    set_caps(tx,
             "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=4,"
             "framerate=10/1");
    tx.play();
    const std::string err = tx.wait_end();
    EXPECT_NE(err.find("sink: host 'bad_host' was refused"), std::string::npos) << err;
  }
}

// idl=flatbuf: a peer whose message does not pass the flatbuffers verifier, and one whose tensor
// data is short.
TEST(TensorGrpc, BadFlatbufMessageFromAPeer) {
  namespace fb = nnstreamer::flatbuf;
  for (int bad_kind = 0; bad_kind < 2; ++bad_kind) {
    const uint16_t port = mqtt_test::free_port();
    Pipe rx(rx_desc("idl=flatbuf port=" + std::to_string(port)));
    rx.play();
    ASSERT_TRUE(rx.wait_state("src", GST_STATE_PAUSED));
    auto ch = grpc::CreateChannel("127.0.0.1:" + std::to_string(port),
                                  grpc::InsecureChannelCredentials());
    auto stub = fb::TensorService::NewStub(ch);
    grpc::ClientContext ctx;
    flatbuffers::grpc::Message<fb::Empty> reply;
    auto w = stub->SendTensors(&ctx, &reply);
    flatbuffers::grpc::MessageBuilder b;
    if (bad_kind == 0) {
      // A root table whose vtable offset points far outside the buffer.
      const uint8_t junk[] = {4, 0, 0, 0, 0xff, 0xff, 0xff, 0x7f};
      w->Write(flatbuffers::grpc::Message<fb::Tensors>(::grpc::Slice(junk, sizeof junk)));
    } else {
      const uint32_t dims[] = {4};
      const uint8_t data[15] = {};
      auto t = fb::CreateTensor(b, b.CreateString("x"), fb::Tensor_type_NNS_FLOAT32,
                                b.CreateVector(dims, 1), b.CreateVector(data, 15));
      const fb::frame_rate fr(1, 1);
      b.Finish(fb::CreateTensors(b, 1, &fr, b.CreateVector(&t, 1)));
      w->Write(b.ReleaseMessage<fb::Tensors>());
    }
    w->WritesDone();
    const grpc::Status st = w->Finish();
    EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
    const std::string err = rx.wait_end();
    EXPECT_NE(err.find("src: client ipv4:127.0.0.1:"), std::string::npos) << err;
    EXPECT_NE(err.find(bad_kind == 0 ? "not a valid flatbuffers Tensors table"
                                     : "tensor 0: 15 bytes of data but its type and dimensions "
                                       "need 16"),
              std::string::npos)
        << err;
  }
}

// The elements are their own plugin so that other pipelines never load gRPC: the nnstreamer
// plugin module links neither gRPC nor protobuf, the nnstreamer_grpc module does (ELF NEEDED).
TEST(TensorGrpc, OnlyTheGrpcPluginLinksGrpc) {
  auto needed = [](const std::string &so) {
    std::string out;
    if (FILE *f = popen(("readelf -d '" + so + "' 2>&1").c_str(), "r")) {
      char buf[512];
      while (fgets(buf, sizeof buf, f))
        if (std::strstr(buf, "(NEEDED)")) out += buf;
      pclose(f);
    }
    return out;
  };
  const std::string dir = std::string(NNS_BUILD_DIR) + "/plugin/";
  const std::string core = needed(dir + "libnnstreamer.so");
  const std::string grpc = needed(dir + "libnnstreamer-grpc.so");
  ASSERT_NE(core.find("libgst"), std::string::npos) << "readelf -d libnnstreamer.so: " << core;
  EXPECT_EQ(core.find("grpc"), std::string::npos) << core;
  EXPECT_EQ(core.find("protobuf"), std::string::npos) << core;
  EXPECT_NE(grpc.find("libgrpc++"), std::string::npos) << grpc;
  EXPECT_NE(grpc.find("libnnstreamer_wire.so"), std::string::npos) << grpc;
}
