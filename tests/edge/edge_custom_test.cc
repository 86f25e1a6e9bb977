// SPDX-License-Identifier: LGPL-2.1-only
// edgesink / edgesrc with connect-type=CUSTOM: a C connection library (custom_conn_lib.c, UDP
// on loopback, serialized edge data) loaded with dlopen through nnstreamer-edge's custom ABI;
// publisher and subscriber in separate processes with exact payloads, the order of the calls
// into the library, and the errors naming the library and what is missing.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include "edge_test_util.h"
#include "support/harness.h"

using namespace edge_test;

namespace {

const std::string kLib = NNS_TEST_CUSTOM_LIB;
// The build tree's libnnstreamer-edge, whatever is installed (children inherit it).
const bool kCapiEnv = setenv("NNS_EDGE_CAPI_LIB", NNS_TEST_EDGE_CAPI, 1) == 0;

std::string custom(uint16_t port, const std::string &lib = kLib) {
  return "connect-type=CUSTOM custom-lib=" + lib +
         " dest-host=127.0.0.1 dest-port=" + std::to_string(port);
}

std::vector<std::string> lines(const std::string &s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

void send_udp(uint16_t port, const std::string &bytes) {
  int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(port);
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr *>(&a), sizeof a);
  close(fd);
}

}  // namespace

TEST(EdgeChild, Run) {
  edge_test::run_child();
}

TEST(EdgeCustom, PublisherInAnotherProcessExactBytesAndCaps) {
  const uint16_t port = free_port();
  SubPipeline sub(custom(port));
  ASSERT_TRUE(sub.play());
  TempFile in("edge_custom_in.bin");
  std::string want;
  for (int i = 0; i < 8 * 64; ++i) want.push_back(static_cast<char>(i * 5 + i / 64));
  std::ofstream(in.path, std::ios::binary) << want;
  Child pub("filesrc location=" + in.path +
                " blocksize=64 ! video/x-raw,format=GRAY8,width=8,height=8,framerate=0/1 ! "
                "edgesink sync=false " +
                custom(port),
            "custom_pub");
  std::string got, caps;
  for (int i = 0; i < 8; ++i) {
    std::string bytes;
    ASSERT_TRUE(sub.pull(&bytes, i == 0 ? &caps : nullptr)) << "buffer " << i << "\n" << pub.log();
    got += bytes;
  }
  EXPECT_EQ(got, want);
  EXPECT_EQ(caps,
            "video/x-raw, format=(string)GRAY8, width=(int)8, height=(int)8, "
            "framerate=(fraction)0/1");
  EXPECT_EQ(pub.wait_exit(), 0) << pub.log();
}

TEST(EdgeCustom, CallsTheLibraryInNnstreamerEdgesOrder) {
  TempFile trace("edge_custom_trace.txt");
  setenv("NNS_TEST_CUSTOM_TRACE", trace.path.c_str(), 1);
  const uint16_t port = free_port();
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=2 ! video/x-raw,format=GRAY8,width=4,height=4 ! edgesink "
      "sync=false host=127.0.0.1 topic=cam " +
          custom(port),
      10);
  ASSERT_TRUE(r.eos) << r.error_text;
  auto pub = lines(slurp(trace.path));
  ASSERT_GE(pub.size(), 9u);
  EXPECT_EQ(std::vector<std::string>(pub.begin(), pub.begin() + 8),
            (std::vector<std::string>{"create", "set_info HOST=127.0.0.1", "set_info PORT=3000",
                                      "set_info DEST_HOST=127.0.0.1",
                                      "set_info DEST_PORT=" + std::to_string(port),
                                      "set_info TOPIC=cam", "set_event_cb", "start"}));
  EXPECT_EQ(pub[8].rfind("set_info CAPS=@edge_sink_caps@video/x-raw, format=(string)GRAY8", 0), 0u)
      << pub[8];
  EXPECT_EQ(
      std::vector<std::string>(pub.begin() + 9, pub.end()),
      (std::vector<std::string>{"send_data 1 memories", "send_data 1 memories", "stop", "close"}));
  std::remove(trace.path.c_str());
  {
    SubPipeline sub(custom(port));
    ASSERT_TRUE(sub.play());
    // The library reports CONNECTION_CLOSED: the stream ends with an error naming it.
    send_udp(port, "bye");
    const std::string err = sub.error(5 * GST_SECOND);
    EXPECT_NE(err.find("subscription ended: the custom connection of " + kLib + " closed"),
              std::string::npos)
        << err;
  }
  unsetenv("NNS_TEST_CUSTOM_TRACE");
  EXPECT_EQ(lines(slurp(trace.path)),
            (std::vector<std::string>{"create", "set_info DEST_HOST=127.0.0.1",
                                      "set_info DEST_PORT=" + std::to_string(port), "set_event_cb",
                                      "start", "connect", "stop", "close"}));
}

TEST(EdgeCustom, LibraryErrorsNameTheLibrary) {
  const std::string base = "videotestsrc num-buffers=1 ! edgesink connect-type=CUSTOM";
  auto r = nns::test::run_pipeline(base, 5);
  EXPECT_NE(r.error_text.find("connect-type CUSTOM needs the custom-lib property"),
            std::string::npos)
      << r.error_text;
  r = nns::test::run_pipeline(base + " custom-lib=/nonexistent/libx.so", 5);
  EXPECT_NE(r.error_text.find("cannot load custom-lib '/nonexistent/libx.so': "
                              "/nonexistent/libx.so: cannot open shared object file"),
            std::string::npos)
      << r.error_text;
  const std::string capi = NNS_TEST_EDGE_CAPI;
  r = nns::test::run_pipeline("edgesrc connect-type=CUSTOM custom-lib=" + capi + " ! fakesink", 5);
  EXPECT_NE(
      r.error_text.find("custom-lib '" + capi + "' has no symbol nns_edge_custom_get_instance"),
      std::string::npos)
      << r.error_text;
  const std::string nostart = NNS_TEST_CUSTOM_LIB_NOSTART;
  r = nns::test::run_pipeline(base + " custom-lib=" + nostart, 5);
  EXPECT_NE(r.error_text.find("custom-lib '" + nostart + "': nns_edge_custom_start is NULL"),
            std::string::npos)
      << r.error_text;
}

TEST(EdgeCustom, PublisherCapsRefineAPartialCapsfilter) {
  const uint16_t port = free_port();
  SubPipeline sub(custom(port) + " ! video/x-raw,format=GRAY8");
  ASSERT_TRUE(sub.play());
  Child pub(
      "videotestsrc num-buffers=40 is-live=true ! "
      "video/x-raw,format=GRAY8,width=4,height=4,framerate=50/1 ! edgesink sync=false " +
          custom(port),
      "custom_caps");
  std::string bytes, caps;
  ASSERT_TRUE(sub.pull(&bytes, &caps)) << pub.log();
  EXPECT_EQ(caps,
            "video/x-raw, format=(string)GRAY8, width=(int)4, height=(int)4, "
            "framerate=(fraction)50/1, multiview-mode=(string)mono, "
            "pixel-aspect-ratio=(fraction)1/1, interlace-mode=(string)progressive");
  EXPECT_EQ(pub.wait_exit(), 0) << pub.log();
}

// NNStreamer's edgeCustom.sinkNormal / srcNormal: with only connect-type=CUSTOM and custom-lib
// (no destination), the pipelines reach PLAYING and run until stopped; without custom-lib or
// with a library that does not exist they fail to start (sinkInvalidProp*_n, srcInvalidProp*_n).
namespace {

// PLAYING reached (or, with `live`, still waiting for a first buffer: a live source without
// data), then ~0.5 s without an error on the bus.
std::string plays_without_error(const std::string &desc, bool live = false) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p) {
    std::string m = err ? err->message : "parse failed";
    if (err) g_error_free(err);
    return m;
  }
  std::string out;
  GstStateChangeReturn ret = gst_element_set_state(p, GST_STATE_PLAYING);
  if (ret != GST_STATE_CHANGE_FAILURE)
    ret = gst_element_get_state(p, nullptr, nullptr, (live ? 1 : 5) * GST_SECOND);
  if (ret == GST_STATE_CHANGE_FAILURE) out = "state change failed";
  if (ret == GST_STATE_CHANGE_ASYNC && !live) out = "PLAYING not reached within 5 s";
  GstBus *bus = gst_element_get_bus(p);
  if (GstMessage *m = gst_bus_timed_pop_filtered(bus, 500 * GST_MSECOND, GST_MESSAGE_ERROR)) {
    GError *e = nullptr;
    gst_message_parse_error(m, &e, nullptr);
    out = e ? e->message : "error";
    if (e) g_error_free(e);
    gst_message_unref(m);
  }
  gst_object_unref(bus);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(p);
  return out;
}

}  // namespace

TEST(EdgeCustomUpstream, SinkAndSrcWithOnlyTheLibraryPlay) {
  EXPECT_EQ(plays_without_error("videotestsrc ! video/x-raw,width=32,height=24,format=RGB,"
                                "framerate=10/1 ! tensor_converter ! edgesink connect-type=CUSTOM "
                                "custom-lib=" +
                                kLib + " name=sinkx port=0"),
            "");
  EXPECT_EQ(plays_without_error("edgesrc connect-type=CUSTOM custom-lib=" + kLib +
                                    " name=srcx ! other/tensors,num_tensors=1,dimensions=3:32:24:1,"
                                    "types=uint8,format=static,framerate=30/1 ! tensor_sink",
                                true),
            "");
}

TEST(EdgeCustomUpstream, MissingOrInvalidLibraryFailsToStart) {
  for (const std::string &lib : {std::string(""), std::string(" custom-lib=libINVALID.so")}) {
    SCOPED_TRACE(lib);
    EXPECT_NE(plays_without_error("videotestsrc ! video/x-raw,width=32,height=24,format=RGB,"
                                  "framerate=10/1 ! tensor_converter ! edgesink "
                                  "connect-type=CUSTOM name=sinkx port=0" +
                                  lib),
              "");
    EXPECT_NE(plays_without_error("edgesrc connect-type=CUSTOM name=srcx" + lib +
                                  " ! other/tensors,num_tensors=1,dimensions=3:32:24:1,"
                                  "types=uint8,format=static,framerate=30/1 ! tensor_sink"),
              "");
  }
}
