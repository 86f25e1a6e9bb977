// SPDX-License-Identifier: LGPL-2.1-only
// Throughput of the among-device elements on loopback (docs/BENCHMARKS.md):
//   mqtt: 150 KB frames, fakesrc ! mqttsink -> mosquitto (started here, 127.0.0.1, free port)
//         -> mqttsrc ! fakesink, QoS 1, frames/s and MB/s from the first to the last frame
//         received;
//   grpc: 150 528-byte uint8 tensors (3:224:224:1), tensor_sink_grpc (client) ->
//         tensor_src_grpc (server), idl=protobuf and idl=flatbuf.
// usage: among_device_bench [mqtt|grpc] [frames]
#include <gst/gst.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>

#include "../tests/mqtt/mosquitto_broker.h"
#include "gst/extra_plugins.h"
#include "gst/plugin_init.h"

namespace {

struct Counter {
  std::atomic<int> n{0};
  std::chrono::steady_clock::time_point first, last;
};

GstPadProbeReturn count(GstPad *, GstPadProbeInfo *, gpointer data) {
  auto *c = static_cast<Counter *>(data);
  const auto now = std::chrono::steady_clock::now();
  if (c->n++ == 0) c->first = now;
  c->last = now;
  return GST_PAD_PROBE_OK;
}

GstElement *launch(const std::string &d) {
  GError *e = nullptr;
  GstElement *p = gst_parse_launch(d.c_str(), &e);
  if (e) {
    std::fprintf(stderr, "%s: %s\n", d.c_str(), e->message);
    std::exit(1);
  }
  return p;
}

// Runs rx (which ends after `frames`) and tx; returns when rx ends or 120 s passed.
void run(const char *what, const std::string &rx_desc, const std::string &tx_desc, int frames,
         std::size_t frame_bytes, bool wait_rx_playing) {
  GstElement *rx = launch(rx_desc);
  Counter c;
  GstElement *sink = gst_bin_get_by_name(GST_BIN(rx), "out");
  GstPad *pad = gst_element_get_static_pad(sink, "sink");
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, count, &c, nullptr);
  gst_object_unref(pad);
  gst_element_set_state(rx, GST_STATE_PLAYING);
  GstElement *src = gst_bin_get_by_name(GST_BIN(rx), "src");
  gst_element_get_state(src, nullptr, nullptr, wait_rx_playing ? 5 * GST_SECOND : 0);
  g_usleep(200000);
  GstElement *tx = launch(tx_desc);
  gst_element_set_state(tx, GST_STATE_PLAYING);
  GstBus *bus = gst_element_get_bus(rx);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 120 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  if (m && GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    GError *e = nullptr;
    gst_message_parse_error(m, &e, nullptr);
    std::fprintf(stderr, "%s: %s\n", what, e->message);
    g_error_free(e);
  }
  if (m) gst_message_unref(m);
  const int n = c.n;
  const double s = std::chrono::duration<double>(c.last - c.first).count();
  if (n > 1 && s > 0)
    std::printf("%s: %d of %d frames of %zu bytes, %.1f frames/s, %.1f MB/s\n", what, n, frames,
                frame_bytes, (n - 1) / s, (n - 1) * static_cast<double>(frame_bytes) / s / 1e6);
  else
    std::printf("%s: %d of %d frames received\n", what, n, frames);
  gst_object_unref(bus);
  gst_element_set_state(tx, GST_STATE_NULL);
  gst_element_set_state(rx, GST_STATE_NULL);
  gst_object_unref(src);
  gst_object_unref(sink);
  gst_object_unref(tx);
  gst_object_unref(rx);
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  nns_register_static();
  nns_mqtt_register_static();  // mqttsink/mqttsrc: the "mqtt" plugin
  nns_grpc_register_static();  // tensor_*_grpc: the "nnstreamer_grpc" plugin
  const std::string which = argc > 1 ? argv[1] : "all";
  const int frames = argc > 2 ? std::atoi(argv[2]) : 500;
  if (which == "all" || which == "mqtt") {
    mqtt_test::Broker b;
    if (!b.start()) {
      std::printf("mqtt: mosquitto did not start\n");
    } else {
      const std::size_t bytes = 150 * 1024;
      const std::string topic = "bench/mqtt";
      run("mqtt qos1",
          "mqttsrc name=src is-live=false mqtt-qos=1 port=" + b.port_str() + " sub-topic=" + topic +
              " num-buffers=" + std::to_string(frames) +
              " ! fakesink name=out sync=false async=false",
          "fakesrc num-buffers=" + std::to_string(frames) +
              " sizetype=fixed filltype=zero sizemax=" + std::to_string(bytes) +
              " datarate=" + std::to_string(2000000000) +  // frames ~77 us apart: not the limit
              " ! application/octet-stream ! mqttsink mqtt-qos=1 port=" + b.port_str() +
              " pub-topic=" + topic,
          frames, bytes, true);
    }
  }
  for (const char *idl : {"protobuf", "flatbuf"}) {
    if (which != "all" && which != "grpc") break;
    const uint16_t port = mqtt_test::free_port();
    const std::size_t bytes = 3 * 224 * 224;
    run((std::string("grpc ") + idl).c_str(),
        "tensor_src_grpc name=src host=127.0.0.1 idl=" + std::string(idl) +
            " port=" + std::to_string(port) + " num-buffers=" + std::to_string(frames) +
            " ! fakesink name=out sync=false",
        "fakesrc num-buffers=" + std::to_string(frames) +
            " sizetype=fixed filltype=zero sizemax=" + std::to_string(bytes) +
            " ! other/tensors,format=static,num_tensors=1,dimensions=3:224:224:1,types=uint8,"
            "framerate=30/1 ! tensor_sink_grpc host=127.0.0.1 idl=" +
            idl + " port=" + std::to_string(port),
        frames, bytes, false);
  }
  return 0;
}
