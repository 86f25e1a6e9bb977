// SPDX-License-Identifier: LGPL-2.1-only
// Shared GStreamer glue of the among-device elements (tensor_query_*, edgesrc, edgesink):
// the connect-type enums, NNStreamer's GstMetaQuery (the client id a query server carries
// with each buffer from tensor_query_serversrc to tensor_query_serversink), buffer <-> frame
// conversion without copies, and the per-id table that pairs a server's src and sink.
#pragma once

#include <gst/gst.h>

#include <chrono>

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/tensor_info.h"
#include "edge/edge_pool.h"
#include "edge/edge_node.h"

G_BEGIN_DECLS
// NNStreamer's GstMetaQuery (gst/nnstreamer/tensor_meta.h): same name, API and field.
typedef struct {
  GstMeta meta;
  int64_t client_id;
} GstMetaQuery;
GType gst_meta_query_api_get_type(void);
const GstMetaInfo *gst_meta_query_get_info(void);
G_END_DECLS

namespace nns::gst {

GstMetaQuery *buffer_add_meta_query(GstBuffer *buf, int64_t client_id);
GstMetaQuery *buffer_get_meta_query(GstBuffer *buf);

// GEnum "tensor_query_protocol" (TCP=0, HYBRID=2) and "edge_protocol" (TCP=0, MQTT=1,
// HYBRID=2, CUSTOM=3), nnstreamer-edge's nns_edge_connect_type_e values.
GType query_connect_type_get_type();
// tensor_query_client load-balance (values of nns::edge::Balance).
GType query_load_balance_get_type();
// Adds "servers", an array of one structure per server of a load-balancing client.
void add_server_stats(GstStructure *st, const std::vector<edge::ServerStats> &servers);
GType edge_connect_type_get_type();
// Throws nns::Error(kSettings) "connect-type X is not supported yet ..." unless TCP or HYBRID.
void require_tcp(int connect_type);

// The memories of a buffer, mapped for reading, as an OutFrame (no copy). Tensor caps send
// one memory per tensor (unpacking >16 tensors), other caps one per GstMemory.
class FrameView {
 public:
  FrameView(GstBuffer *buf, bool tensor_caps);
  ~FrameView();
  FrameView(const FrameView &) = delete;
  FrameView &operator=(const FrameView &) = delete;
  edge::OutFrame &frame() { return frame_; }

 private:
  std::vector<GstMemory *> mems_;
  std::vector<GstMapInfo> maps_;
  edge::OutFrame frame_;
};

// Receives frame memories straight into GstMemory.
edge::Allocator gst_memory_allocator();
// Moves the received memories into a new buffer (tensor caps with > 16 tensors are packed
// as NNStreamer does, using `config`). Throws nns::Error(kStream) when that is impossible.
GstBuffer *buffer_from_message(edge::Message &&m, const TensorsConfig *config);
// Same, taking the tensor config from `src_pad`'s current caps when packing needs it.
GstBuffer *buffer_from_message_for_pad(edge::Message &&m, GstPad *src_pad);

// The server side shared by tensor_query_serversrc and tensor_query_serversink with the
// same `id` (NNStreamer pairs them the same way).
struct QueryServerShared {
  std::mutex lock;
  std::condition_variable cv;
  std::shared_ptr<edge::ServerNode> node;  // started and stopped by serversrc
  std::deque<edge::Message> requests;      // arrived, not yet pushed by serversrc
  std::deque<std::chrono::steady_clock::time_point> arrived;  // of each request (batching)
  bool flushing = false;
  guint max_batch = 1;         // serversrc max-batch: the capability shows one request's caps
  GstPad *src_pad = nullptr;   // serversrc's src pad (its peer gives the accepted caps)
  GstPad *sink_pad = nullptr;  // serversink's sink pad (its peer gives the answer caps)
  std::string capability();    // "@query_server_src_caps@...@query_server_sink_caps@..."
};
std::shared_ptr<QueryServerShared> query_server_get(guint id);  // created on first use, kept

}  // namespace nns::gst
