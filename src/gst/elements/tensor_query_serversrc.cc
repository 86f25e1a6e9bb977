// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_query_serversrc
 *
 * The receiving half of a query server: listens on host:port with nnstreamer-edge's TCP
 * protocol (docs/wire-edge-tcp.md), accepts any number of tensor_query_client peers and
 * pushes each request as a buffer carrying a GstMetaQuery with the client id, so that
 * tensor_query_serversink (same `id`) sends the answer back to the client that asked.
 * A live source by default (is-live=TRUE), so server pipelines never wait for preroll.
 *
 *   gst-launch-1.0 tensor_query_serversrc port=3000 ! \
 *     other/tensors,format=static,num_tensors=1,dimensions=3:224:224:1,types=uint8,\
 *     framerate=0/1 ! tensor_filter framework=onnxruntime model=m.onnx ! \
 *     tensor_query_serversink
 *
 * Only connect-type=TCP is implemented; HYBRID is accepted as a value and refused at start
 * with an error saying so.
 */
#include <gst/base/gstpushsrc.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <vector>
#include <mutex>

#include "gst/edge_glue.h"
#include "gst/edge_props.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/memory_recycler.h"
#include "gst/query_batch.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(query_serversrc_debug);
#define GST_CAT_DEFAULT query_serversrc_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_QUERY_SERVERSRC (gst_tensor_query_serversrc_get_type())
G_DECLARE_FINAL_TYPE(GstTensorQueryServerSrc, gst_tensor_query_serversrc, GST,
                     TENSOR_QUERY_SERVERSRC, GstPushSrc)
G_END_DECLS

namespace {

struct Settings {
  nns::gst::ConnSettings conn;
  guint id = 0;
  guint max_batch = 1;
  guint64 batch_timeout_us = 0;
};

using Clock = std::chrono::steady_clock;

struct ServerSrcPriv {
  std::mutex lock;  // settings
  Settings s;
  std::shared_ptr<nns::gst::QueryServerShared> shared;
  std::atomic<guint64> received{0};
  // Batching (streaming thread): per-slot byte sizes of each tensor, from the caps.
  std::vector<std::size_t> slot;
  std::atomic<guint64> batches{0}, batched{0}, refused{0};
  nns::gst::MemoryRecycler stack_mem{16};  // the batches' memories, reused (no fresh pages)
};

enum {
  PROP_0,
  PROP_ID,
  PROP_IS_LIVE,
  PROP_MAX_BATCH,
  PROP_BATCH_TIMEOUT,
  PROP_STATS,
  PROP_CONN_FIRST
};

const nns::gst::ConnPropTable &conn_props() {
  using nns::gst::ConnProp;
  static const nns::gst::ConnPropTable t(
      PROP_CONN_FIRST,
      {{ConnProp::kHost, "Host", "The hostname to listen as", "localhost"},
       {ConnProp::kPort, "Port", "The port to listen to (0=random available port)", nullptr, 3000},
       {ConnProp::kDestHost, "Destination Host", "The destination hostname to connect",
        "127.0.0.1"},
       {ConnProp::kDestPort, "Destination Port",
        "The destination port to connect to (0=random available port)", nullptr, 1883},
       {ConnProp::kConnectType, "Connect Type", "The connection type.", nullptr, 0, 0, false, false,
        nns::gst::query_connect_type_get_type},
       {ConnProp::kTimeout, "Timeout", "The timeout as seconds to maintain connection", nullptr, 10,
        3600},
       {ConnProp::kTopic, "Topic",
        "The main topic of the host and option if necessary. "
        "(topic)/(optional topic for main topic).",
        nullptr, 0, 0, true}});
  return t;
}

}  // namespace

struct _GstTensorQueryServerSrc {
  GstPushSrc parent;
  ServerSrcPriv *priv;
};

G_DEFINE_TYPE(GstTensorQueryServerSrc, gst_tensor_query_serversrc, GST_TYPE_PUSH_SRC)
GST_ELEMENT_REGISTER_DEFINE(tensor_query_serversrc, "tensor_query_serversrc", GST_RANK_NONE,
                            GST_TYPE_TENSOR_QUERY_SERVERSRC)

static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

static void serversrc_set_property(GObject *object, guint id, const GValue *value,
                                   GParamSpec *pspec) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().set(id, value, &p->s.conn)) return;
  switch (id) {
    case PROP_ID:
      p->s.id = g_value_get_uint(value);
      break;
    case PROP_IS_LIVE:
      gst_base_src_set_live(GST_BASE_SRC(object), g_value_get_boolean(value));
      break;
    case PROP_MAX_BATCH:
      p->s.max_batch = g_value_get_uint(value);
      break;
    case PROP_BATCH_TIMEOUT:
      p->s.batch_timeout_us = g_value_get_uint64(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void serversrc_get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(object)->priv;
  if (id == PROP_STATS) {
    g_value_take_boxed(
        value, gst_structure_new("application/x-query-serversrc-stats", "received", G_TYPE_UINT64,
                                 p->received.load(), "batches", G_TYPE_UINT64, p->batches.load(),
                                 "batched", G_TYPE_UINT64, p->batched.load(), "refused",
                                 G_TYPE_UINT64, p->refused.load(), nullptr));
    return;
  }
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().get(id, value, p->s.conn)) return;
  switch (id) {
    case PROP_ID:
      g_value_set_uint(value, p->s.id);
      break;
    case PROP_IS_LIVE:
      g_value_set_boolean(value, gst_base_src_is_live(GST_BASE_SRC(object)));
      break;
    case PROP_MAX_BATCH:
      g_value_set_uint(value, p->s.max_batch);
      break;
    case PROP_BATCH_TIMEOUT:
      g_value_set_uint64(value, p->s.batch_timeout_us);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static gboolean serversrc_start(GstBaseSrc *bsrc) {
  return nns::gst::guard(bsrc, FALSE, [&]() -> gboolean {
    auto *self = GST_TENSOR_QUERY_SERVERSRC(bsrc);
    auto *p = self->priv;
    Settings s;
    {
      std::lock_guard<std::mutex> l(p->lock);
      s = p->s;
    }
    nns::gst::require_tcp(s.conn.connect_type);
    auto shared = nns::gst::query_server_get(s.id);
    {
      std::lock_guard<std::mutex> l(shared->lock);
      if (shared->node)
        nns::fail(nns::ErrorKind::kSettings,
                  "another tensor_query_serversrc already serves id " + std::to_string(s.id));
      shared->requests.clear();
      shared->arrived.clear();
      shared->flushing = false;
      shared->max_batch = std::max(1u, s.max_batch);
      gst_object_replace(reinterpret_cast<GstObject **>(&shared->src_pad),
                         GST_OBJECT(GST_BASE_SRC_PAD(bsrc)));
    }
    nns::edge::NodeOptions o = s.conn.node_options(nns::edge::Role::kQueryServer);
    o.connect_timeout_ms = s.conn.timeout ? static_cast<int>(s.conn.timeout) * 1000 : -1;
    nns::edge::NodeCallbacks cb;
    std::weak_ptr<nns::gst::QueryServerShared> weak = shared;
    cb.on_data = [weak](nns::edge::Message &&m) {
      if (auto sh = weak.lock()) {
        std::lock_guard<std::mutex> l(sh->lock);
        sh->requests.push_back(std::move(m));
        sh->arrived.push_back(Clock::now());
        sh->cv.notify_all();
      }
    };
    cb.on_warning = [self](const std::string &w) { NNS_POST_WARNING(self, w); };
    cb.on_connected = [self](int64_t id, const std::string &peer) {
      GST_INFO_OBJECT(self, "client %s connected, id %" G_GINT64_FORMAT, peer.c_str(), id);
    };
    cb.caps = [weak]() -> std::string {
      auto sh = weak.lock();
      return sh ? sh->capability() : std::string();
    };
    cb.alloc = nns::gst::gst_memory_allocator();
    std::shared_ptr<nns::edge::ServerNode> node =
        nns::edge::make_server(s.conn.type(), o, std::move(cb));
    node->start();
    GST_INFO_OBJECT(self, "query server %u listening on %s:%u", s.id, s.conn.host.c_str(),
                    node->port());
    {
      std::lock_guard<std::mutex> l(shared->lock);
      shared->node = node;
    }
    p->shared = shared;
    p->received = 0;
    p->batches = p->batched = p->refused = 0;
    return TRUE;
  });
}

static gboolean serversrc_stop(GstBaseSrc *bsrc) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(bsrc)->priv;
  if (!p->shared) return TRUE;
  std::shared_ptr<nns::edge::ServerNode> node;
  {
    std::lock_guard<std::mutex> l(p->shared->lock);
    node.swap(p->shared->node);
    p->shared->flushing = true;
    p->shared->cv.notify_all();
  }
  if (node) node->stop();
  {
    std::lock_guard<std::mutex> l(p->shared->lock);
    p->shared->requests.clear();
    p->shared->arrived.clear();
    p->shared->max_batch = 1;
    gst_object_replace(reinterpret_cast<GstObject **>(&p->shared->src_pad), nullptr);
  }
  p->shared.reset();
  p->stack_mem.clear();
  return TRUE;
}

static gboolean serversrc_unlock(GstBaseSrc *bsrc) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(bsrc)->priv;
  if (p->shared) {
    std::lock_guard<std::mutex> l(p->shared->lock);
    p->shared->flushing = true;
    p->shared->cv.notify_all();
  }
  return TRUE;
}

static gboolean serversrc_unlock_stop(GstBaseSrc *bsrc) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(bsrc)->priv;
  if (p->shared) {
    std::lock_guard<std::mutex> l(p->shared->lock);
    p->shared->flushing = false;
  }
  return TRUE;
}

namespace {

int64_t client_of(const nns::edge::Message &m) {
  const auto id_str = m.meta.get("client_id");
  return id_str ? g_ascii_strtoll(id_str->c_str(), nullptr, 10) : 0;
}

// max-batch > 1: the caps downstream must hold batches of max-batch (outermost dimension);
// a model with a fixed batch of 1 cannot, and is named.
// The element that takes the batches, for messages: the first one downstream with a `model`
// property (past capsfilters and queues), with its model file and input tensors.
std::string downstream_model(GstBaseSrc *bsrc) {
  std::string first;
  GstElement *e = nns::gst::find_along(GST_BASE_SRC_PAD(bsrc), "model", &first);
  if (!e) return first.empty() ? std::string("the element after it") : first;
  gchar *model = nullptr, *names = nullptr, *dims = nullptr;
  g_object_get(e, "model", &model, nullptr);
  if (g_object_class_find_property(G_OBJECT_GET_CLASS(e), "inputname"))
    g_object_get(e, "inputname", &names, "input", &dims, nullptr);
  std::string out = std::string(GST_ELEMENT_NAME(e)) + " (model '" + (model ? model : "") + "'" +
                    (names && *names ? std::string(", input '") + names + "'" : "") +
                    (dims && *dims ? std::string(" ") + dims : "") + ")";
  g_free(model);
  g_free(names);
  g_free(dims);
  gst_object_unref(e);
  return out;
}

gboolean serversrc_set_caps(GstBaseSrc *bsrc, GstCaps *caps) {
  return nns::gst::guard(bsrc, FALSE, [&]() -> gboolean {
    auto *p = GST_TENSOR_QUERY_SERVERSRC(bsrc)->priv;
    guint n;
    {
      std::lock_guard<std::mutex> l(p->lock);
      n = p->s.max_batch;
    }
    p->slot.clear();
    if (n <= 1) return TRUE;
    if (auto why = nns::gst::batch_caps_problem(caps, n)) {
      const std::string who = downstream_model(bsrc);
      nns::fail(nns::ErrorKind::kNegotiation,
                "max-batch=" + std::to_string(n) + ": the input of " + who +
                    " cannot take a batch: " + *why +
                    "; use max-batch=1, or a model whose batch dimension is " + std::to_string(n) +
                    " or free (then give it with the caps or input=)");
    }
    p->slot = nns::gst::slot_sizes(nns::gst::config_from_caps(caps).info, n);
    return TRUE;
  });
}

// The source's template is ANY, so GstBaseSrc does not negotiate by itself (the capsfilter
// after it gives the caps to the stream). With max-batch > 1 the caps must be known here:
// take downstream's, fixated; set_caps checks them.
gboolean serversrc_negotiate(GstBaseSrc *bsrc) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(bsrc)->priv;
  guint n;
  {
    std::lock_guard<std::mutex> l(p->lock);
    n = p->s.max_batch;
  }
  if (n <= 1) return GST_BASE_SRC_CLASS(gst_tensor_query_serversrc_parent_class)->negotiate(bsrc);
  return nns::gst::guard(bsrc, FALSE, [&]() -> gboolean {
    nns::gst::CapsPtr caps(gst_pad_peer_query_caps(GST_BASE_SRC_PAD(bsrc), nullptr));
    if (!caps || gst_caps_is_empty(caps.get()) || gst_caps_is_any(caps.get()))
      nns::fail(nns::ErrorKind::kNegotiation,
                "max-batch=" + std::to_string(n) + ": the input of " + downstream_model(bsrc) +
                    " cannot take a batch: the caps after tensor_query_serversrc must give it "
                    "(static tensors whose outermost dimension is " +
                    std::to_string(n) + "), got '" +
                    (caps ? nns::gst::caps_to_string(caps.get()) : std::string("none")) +
                    "'; use max-batch=1, or a model whose batch dimension is " + std::to_string(n) +
                    " or free (then give it with the caps or input=)");
    caps.reset(gst_caps_fixate(caps.release()));
    return gst_base_src_set_caps(bsrc, caps.get());
  });
}

// True when the request's memories fit the batch slots.
bool fits(const std::vector<std::size_t> &slot, const nns::edge::Message &m) {
  if (m.mems.size() != slot.size()) return false;
  for (std::size_t i = 0; i < slot.size(); ++i)
    if (m.mems[i]->size() != slot[i]) return false;
  return true;
}

// Up to max-batch requests: the first waiting one, then those that arrive until
// batch-timeout after it arrived or, when it was already waiting (it came while the previous
// batch was being computed), after the server became free (now), or until the batch is full.
// Counting from the arrival alone lets 8 lockstep clients split into two groups of 4 for
// good: each group's requests arrive while the other's batch runs, their timeout expires
// there, and every batch leaves half empty (its padding computed all the same: twice the CPU
// per frame, measured). Requests that do not fit the slots are dropped with a warning (they
// would not fit the caps either).
GstFlowReturn take_batch(GstTensorQueryServerSrc *self, std::vector<nns::edge::Message> *batch) {
  auto *p = self->priv;
  auto sh = p->shared;
  guint n;
  guint64 timeout_us;
  {
    std::lock_guard<std::mutex> l(p->lock);
    n = p->s.max_batch;
    timeout_us = p->s.batch_timeout_us;
  }
  std::vector<std::string> refused;
  std::unique_lock<std::mutex> l(sh->lock);
  const Clock::time_point free_at = Clock::now();
  Clock::time_point deadline{};
  while (batch->size() < n) {
    if (batch->empty())
      sh->cv.wait(l, [&] { return sh->flushing || !sh->requests.empty(); });
    else
      sh->cv.wait_until(l, deadline, [&] { return sh->flushing || !sh->requests.empty(); });
    if (sh->flushing) return GST_FLOW_FLUSHING;
    while (!sh->requests.empty() && batch->size() < n) {
      nns::edge::Message m = std::move(sh->requests.front());
      const auto at = sh->arrived.front();
      sh->requests.pop_front();
      sh->arrived.pop_front();
      if (!fits(p->slot, m)) {
        ++p->refused;
        refused.push_back("client id " + std::to_string(client_of(m)));
        continue;
      }
      if (batch->empty()) deadline = std::max(at, free_at) + std::chrono::microseconds(timeout_us);
      batch->push_back(std::move(m));
    }
    if (!batch->empty() && Clock::now() >= deadline) break;
  }
  l.unlock();
  for (const auto &who : refused)
    NNS_POST_WARNING(self, "max-batch: the request of " + who +
                               " does not match the caps of one batch slot; dropped");
  return GST_FLOW_OK;
}

// Stacks the requests along the outermost dimension into one buffer of max-batch slots.
GstBuffer *stack(GstTensorQueryServerSrc *self, std::vector<nns::edge::Message> &&batch) {
  auto *p = self->priv;
  guint n;
  {
    std::lock_guard<std::mutex> l(p->lock);
    n = p->s.max_batch;
  }
  GstBuffer *buf = gst_buffer_new();
  std::vector<int64_t> clients;
  for (const auto &m : batch) clients.push_back(client_of(m));
  for (std::size_t t = 0; t < p->slot.size(); ++t) {
    const std::size_t sz = p->slot[t];
    GstMemory *mem = p->stack_mem.alloc(sz * n);
    GstMapInfo mi;
    if (!mem || !gst_memory_map(mem, &mi, GST_MAP_WRITE)) {
      if (mem) gst_memory_unref(mem);
      gst_buffer_unref(buf);
      nns::fail(nns::ErrorKind::kStream,
                "cannot allocate a batch of " + std::to_string(sz * n) + " bytes");
    }
    for (std::size_t i = 0; i < batch.size(); ++i)
      memcpy(mi.data + i * sz, batch[i].mems[t]->data(), sz);
    memset(mi.data + batch.size() * sz, 0, (n - batch.size()) * sz);  // unused slots
    gst_memory_unmap(mem, &mi);
    gst_buffer_append_memory(buf, mem);
  }
  nns::gst::buffer_add_meta_query(buf, clients.front());
  nns::gst::buffer_add_batch_meta(buf, n, clients);
  ++p->batches;
  p->batched += batch.size();
  return buf;
}

}  // namespace

static GstFlowReturn serversrc_create(GstPushSrc *psrc, GstBuffer **out) {
  return nns::gst::guard(psrc, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *self = GST_TENSOR_QUERY_SERVERSRC(psrc);
    auto *p = self->priv;
    auto sh = p->shared;
    if (!sh) return GST_FLOW_FLUSHING;
    if (!p->slot.empty()) {  // batching (set_caps accepted max-batch > 1)
      std::vector<nns::edge::Message> batch;
      const GstFlowReturn r = take_batch(self, &batch);
      if (r != GST_FLOW_OK) return r;
      p->received += batch.size();
      *out = stack(self, std::move(batch));
      return GST_FLOW_OK;
    }
    nns::edge::Message m;
    {
      std::unique_lock<std::mutex> l(sh->lock);
      sh->cv.wait(l, [&] { return sh->flushing || !sh->requests.empty(); });
      if (sh->flushing) return GST_FLOW_FLUSHING;
      m = std::move(sh->requests.front());
      sh->requests.pop_front();
      sh->arrived.pop_front();
    }
    const int64_t client_id = client_of(m);
    GstBuffer *buf = nns::gst::buffer_from_message_for_pad(std::move(m), GST_BASE_SRC_PAD(psrc));
    nns::gst::buffer_add_meta_query(buf, client_id);
    ++p->received;
    *out = buf;
    return GST_FLOW_OK;
  });
}

static void serversrc_finalize(GObject *object) {
  auto *self = GST_TENSOR_QUERY_SERVERSRC(object);
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_query_serversrc_parent_class)->finalize(object);
}

static void gst_tensor_query_serversrc_class_init(GstTensorQueryServerSrcClass *klass) {
  auto *gobject = G_OBJECT_CLASS(klass);
  auto *element = GST_ELEMENT_CLASS(klass);
  auto *basesrc = GST_BASE_SRC_CLASS(klass);
  auto *pushsrc = GST_PUSH_SRC_CLASS(klass);
  gobject->set_property = serversrc_set_property;
  gobject->get_property = serversrc_get_property;
  gobject->finalize = serversrc_finalize;
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  conn_props().install(gobject);
  g_object_class_install_property(
      gobject, PROP_ID,
      g_param_spec_uint("id", "ID", "ID for distinguishing query servers.", 0, G_MAXUINT, 0, rw));
  g_object_class_install_property(
      gobject, PROP_IS_LIVE,
      g_param_spec_boolean("is-live", "Is Live",
                           "Synchronize the incoming buffers' timestamp with the current "
                           "running time",
                           TRUE, rw));
  g_object_class_install_property(
      gobject, PROP_MAX_BATCH,
      g_param_spec_uint("max-batch", "Maximum batch",
                        "Requests of several clients stacked along the outermost dimension into "
                        "one buffer of this many slots (the caps downstream have it as outermost "
                        "dimension); 1: one request per buffer",
                        1, 1024, 1, rw));
  g_object_class_install_property(
      gobject, PROP_BATCH_TIMEOUT,
      g_param_spec_uint64("batch-timeout", "Batch timeout",
                          "Microseconds the first request of a batch waits for others, from its "
                          "arrival or from when the server is free if it was already waiting "
                          "(0: only those already waiting join it)",
                          0, G_MAXUINT64, 0, rw));
  g_object_class_install_property(
      gobject, PROP_STATS,
      g_param_spec_boxed("stats", "Statistics",
                         "Requests received; with max-batch > 1: buffers made (batches), requests "
                         "in them (batched), requests that did not fit a slot (refused)",
                         GST_TYPE_STRUCTURE,
                         static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  gst_element_class_add_static_pad_template(element, &src_template);
  gst_element_class_set_static_metadata(element, "TensorQueryServerSrc", "Source/Tensor/Query",
                                        "Receive tensor data as a server over the network",
                                        "nnstreamer-cpp");
  basesrc->start = serversrc_start;
  basesrc->stop = serversrc_stop;
  basesrc->unlock = serversrc_unlock;
  basesrc->set_caps = serversrc_set_caps;
  basesrc->negotiate = serversrc_negotiate;
  basesrc->unlock_stop = serversrc_unlock_stop;
  pushsrc->create = serversrc_create;
  GST_DEBUG_CATEGORY_INIT(query_serversrc_debug, "tensor_query_serversrc", 0,
                          "Tensor Query Server Source");
}

static void gst_tensor_query_serversrc_init(GstTensorQueryServerSrc *self) {
  self->priv = new ServerSrcPriv();
  self->priv->s.conn = conn_props().defaults();
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
  gst_base_src_set_do_timestamp(GST_BASE_SRC(self), TRUE);
  gst_base_src_set_live(GST_BASE_SRC(self), TRUE);
}
