// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/edge_glue.h"

#include <cstring>
#include <map>

#include "core/error.h"
#include "gst/gst_ptr.h"
#include "gst/query_batch.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

GType gst_meta_query_api_get_type(void) {
  static GType type = 0;
  static const gchar *tags[] = {nullptr};  // no tags: the meta survives every transform
  if (g_once_init_enter(&type)) {
    GType t = gst_meta_api_type_register("GstMetaQueryAPI", tags);
    g_once_init_leave(&type, t);
  }
  return type;
}

static gboolean meta_query_init(GstMeta *meta, gpointer, GstBuffer *) {
  reinterpret_cast<GstMetaQuery *>(meta)->client_id = 0;
  return TRUE;
}

static gboolean meta_query_transform(GstBuffer *dest, GstMeta *meta, GstBuffer *, GQuark,
                                     gpointer) {
  auto *src = reinterpret_cast<GstMetaQuery *>(meta);
  nns::gst::buffer_add_meta_query(dest, src->client_id);
  return TRUE;
}

const GstMetaInfo *gst_meta_query_get_info(void) {
  static const GstMetaInfo *info = nullptr;
  if (g_once_init_enter(&info)) {
    const GstMetaInfo *i =
        gst_meta_register(gst_meta_query_api_get_type(), "GstMetaQuery", sizeof(GstMetaQuery),
                          meta_query_init, nullptr, meta_query_transform);
    g_once_init_leave(&info, i);
  }
  return info;
}

namespace nns::gst {

GstMetaQuery *buffer_add_meta_query(GstBuffer *buf, int64_t client_id) {
  auto *m = reinterpret_cast<GstMetaQuery *>(
      gst_buffer_add_meta(buf, gst_meta_query_get_info(), nullptr));
  if (m) m->client_id = client_id;
  return m;
}

GstMetaQuery *buffer_get_meta_query(GstBuffer *buf) {
  return reinterpret_cast<GstMetaQuery *>(gst_buffer_get_meta(buf, gst_meta_query_api_get_type()));
}

GType query_connect_type_get_type() {
  static GType type = 0;
  if (g_once_init_enter(&type)) {
    static const GEnumValue values[] = {
        {0, "TCP", "Directly sending stream frames via TCP connections."},
        {2, "HYBRID",
         "Connect with MQTT brokers and directly sending stream frames via TCP connections."},
        {0, nullptr, nullptr}};
    g_once_init_leave(&type, g_enum_register_static("tensor_query_protocol", values));
  }
  return type;
}

GType edge_connect_type_get_type() {
  static GType type = 0;
  if (g_once_init_enter(&type)) {
    static const GEnumValue values[] = {
        {0, "TCP", "Directly sending stream frames via TCP connections."},
        {2, "HYBRID",
         "Connect with MQTT brokers and directly sending stream frames via TCP connections."},
        {1, "MQTT", "Sending stream frames via MQTT connections."},
        {3, "CUSTOM", "Sending stream frames via CUSTOM connections."},
        {0, nullptr, nullptr}};
    g_once_init_leave(&type, g_enum_register_static("edge_protocol", values));
  }
  return type;
}

void require_tcp(int connect_type) {
  if (connect_type == 0 || connect_type == 2) return;  // TCP, HYBRID
  fail(ErrorKind::kSettings,
       std::string("connect-type ") +
           edge::connect_type_name(static_cast<edge::ConnectType>(connect_type)) +
           " is not supported yet (TCP and HYBRID are implemented in this build)");
}

FrameView::FrameView(GstBuffer *buf, bool tensor_caps) {
  const std::size_t n = tensor_caps ? buffer_tensor_count(buf) : gst_buffer_n_memory(buf);
  mems_.reserve(n);
  maps_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    GstMemory *m = tensor_caps ? buffer_get_tensor(buf, i) : gst_buffer_get_memory(buf, i);
    if (!m) fail(ErrorKind::kStream, "buffer has no memory " + std::to_string(i));
    if (!gst_memory_map(m, &maps_[i], GST_MAP_READ)) {
      gst_memory_unref(m);
      fail(ErrorKind::kStream, "cannot map memory " + std::to_string(i) + " for reading");
    }
    mems_.push_back(m);
    frame_.mems.push_back({maps_[i].data, maps_[i].size});
  }
}

FrameView::~FrameView() {
  for (std::size_t i = 0; i < mems_.size(); ++i) {
    gst_memory_unmap(mems_[i], &maps_[i]);
    gst_memory_unref(mems_[i]);
  }
}

namespace {

class GstPayload final : public edge::Payload {
 public:
  explicit GstPayload(std::size_t n) : mem_(gst_allocator_alloc(nullptr, n, nullptr)) {
    if (mem_ && gst_memory_map(mem_, &map_, GST_MAP_WRITE)) mapped_ = true;
  }
  ~GstPayload() override {
    if (mapped_) gst_memory_unmap(mem_, &map_);
    if (mem_) gst_memory_unref(mem_);
  }
  bool ok() const { return mapped_; }
  uint8_t *data() override { return map_.data; }
  std::size_t size() const override { return mapped_ ? map_.size : 0; }
  GstMemory *release() {
    if (mapped_) gst_memory_unmap(mem_, &map_);
    mapped_ = false;
    GstMemory *m = mem_;
    mem_ = nullptr;
    return m;
  }

 private:
  GstMemory *mem_;
  GstMapInfo map_{};
  bool mapped_ = false;
};

GstMemory *take_memory(edge::Payload &p) {
  if (auto *g = dynamic_cast<GstPayload *>(&p)) return g->release();
  GstMemory *m = gst_allocator_alloc(nullptr, p.size(), nullptr);
  MemoryMap map(m, GST_MAP_WRITE);
  if (p.size()) std::memcpy(map.data(), p.data(), p.size());
  return m;
}

}  // namespace

edge::Allocator gst_memory_allocator() {
  return [](std::size_t n) -> edge::PayloadPtr {
    auto p = std::make_unique<GstPayload>(n);
    if (!p->ok()) return nullptr;
    return p;
  };
}

GstBuffer *buffer_from_message_for_pad(edge::Message &&m, GstPad *src_pad) {
  // The tensor config only matters for packing more than 16 memories (not per frame else).
  if (m.mems.size() <= gst_buffer_get_max_memory())
    return buffer_from_message(std::move(m), nullptr);
  CapsPtr caps(gst_pad_get_current_caps(src_pad));
  if (!caps || !is_tensor_caps(caps.get())) return buffer_from_message(std::move(m), nullptr);
  const TensorsConfig cfg = config_from_caps(caps.get());
  return buffer_from_message(std::move(m), &cfg);
}

GstBuffer *buffer_from_message(edge::Message &&m, const TensorsConfig *config) {
  BufferPtr buf(gst_buffer_new());
  const std::size_t n = m.mems.size();
  const bool pack = config && config->info.size() == n && n > gst_buffer_get_max_memory();
  if (n > gst_buffer_get_max_memory() && !pack)
    fail(ErrorKind::kStream, "the frame has " + std::to_string(n) + " memories; a buffer holds " +
                                 std::to_string(gst_buffer_get_max_memory()) +
                                 " unless the caps are tensors with that many tensors");
  for (std::size_t i = 0; i < n; ++i) {
    GstMemory *mem = take_memory(*m.mems[i]);
    if (pack)
      buffer_append_tensor(buf.get(), mem, config->info[i]);
    else
      gst_buffer_append_memory(buf.get(), mem);
  }
  return buf.release();
}

std::string QueryServerShared::capability() {
  guint batch;
  {
    std::lock_guard<std::mutex> l(lock);
    batch = max_batch;
  }
  auto peer_caps = [batch](GstPad *pad) -> std::string {
    if (!pad) return "ANY";
    CapsPtr c(gst_pad_peer_query_caps(pad, nullptr));
    if (!c) return "ANY";
    if (batch > 1) {  // batches of `batch` downstream: the clients send and get one slot
      CapsPtr one(unbatch_caps(c.get(), batch));
      if (!gst_caps_is_empty(one.get())) c = std::move(one);
    }
    GCharPtr s(gst_caps_to_string(c.get()));
    return s.get();
  };
  GstPad *src = nullptr, *sink = nullptr;
  {
    std::lock_guard<std::mutex> l(lock);
    if (src_pad) src = GST_PAD(gst_object_ref(src_pad));
    if (sink_pad) sink = GST_PAD(gst_object_ref(sink_pad));
  }
  std::string s =
      "@query_server_src_caps@" + peer_caps(src) + "@query_server_sink_caps@" + peer_caps(sink);
  if (src) gst_object_unref(src);
  if (sink) gst_object_unref(sink);
  return s;
}

GType query_load_balance_get_type() {
  static GType type = 0;
  static const GEnumValue values[] = {
      {static_cast<gint>(edge::Balance::kNone), "one server at a time, the others for fail-over",
       "none"},
      {static_cast<gint>(edge::Balance::kRoundRobin), "each request to the next server",
       "round-robin"},
      {static_cast<gint>(edge::Balance::kLeastOutstanding),
       "each request to the server with the fewest requests in flight", "least-outstanding"},
      {0, nullptr, nullptr}};
  if (g_once_init_enter(&type))
    g_once_init_leave(&type, g_enum_register_static("GstTensorQueryLoadBalance", values));
  return type;
}

void add_server_stats(GstStructure *st, const std::vector<edge::ServerStats> &servers) {
  GValue arr = G_VALUE_INIT;
  gst_value_array_init(&arr, static_cast<guint>(servers.size()));
  for (const auto &sv : servers) {
    GValue one = G_VALUE_INIT;
    g_value_init(&one, GST_TYPE_STRUCTURE);
    g_value_take_boxed(
        &one, gst_structure_new("server", "name", G_TYPE_STRING, sv.name.c_str(), "live",
                                G_TYPE_BOOLEAN, sv.live, "sent", G_TYPE_UINT64, sv.sent, "received",
                                G_TYPE_UINT64, sv.received, "lost", G_TYPE_UINT64, sv.lost,
                                "resent", G_TYPE_UINT64, sv.resent, "in-flight", G_TYPE_UINT64,
                                sv.in_flight, "latency-mean-us", G_TYPE_DOUBLE, sv.latency_mean_us,
                                "latency-max-us", G_TYPE_DOUBLE, sv.latency_max_us, nullptr));
    gst_value_array_append_and_take_value(&arr, &one);
  }
  gst_structure_take_value(st, "servers", &arr);
}

std::shared_ptr<QueryServerShared> query_server_get(guint id) {
  static std::mutex m;
  static auto *table = new std::map<guint, std::shared_ptr<QueryServerShared>>();
  std::lock_guard<std::mutex> l(m);
  auto &slot = (*table)[id];
  if (!slot) slot = std::make_shared<QueryServerShared>();
  return slot;
}

}  // namespace nns::gst
