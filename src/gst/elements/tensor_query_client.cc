// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_query_client
 *
 * Sends each input buffer to a query server (tensor_query_serversrc ! ... !
 * tensor_query_serversink, possibly NNStreamer's on another device) over nnstreamer-edge's
 * TCP protocol and pushes the server's answers. The connection is made when the input caps
 * arrive; the server's capability is checked against them (an error names both caps).
 *
 *   gst-launch-1.0 videotestsrc ! video/x-raw,format=RGB,width=224,height=224 ! \
 *     tensor_converter ! tensor_query_client dest-host=127.0.0.1 dest-port=3000 ! tensor_sink
 *
 * `max-request` bounds the requests in flight (the newest input beyond it is dropped and
 * counted); `timeout` (ms) bounds how long each input waits for an answer. When the server
 * goes away the client posts a warning, drops (and counts) the inputs meanwhile, reconnects
 * and carries on; `stats` reports sent/received/dropped/lost/reconnects. At EOS the answers
 * still in flight are awaited (up to `timeout`, or 10 s when it is 0) before EOS goes on.
 */
#include <gst/gst.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <vector>

#include "edge/edge_pool.h"

#include "gst/edge_glue.h"
#include "gst/edge_props.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(query_client_debug);
#define GST_CAT_DEFAULT query_client_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_QUERY_CLIENT (gst_tensor_query_client_get_type())
G_DECLARE_FINAL_TYPE(GstTensorQueryClient, gst_tensor_query_client, GST, TENSOR_QUERY_CLIENT,
                     GstElement)
G_END_DECLS

namespace {

using Clock = std::chrono::steady_clock;
constexpr int kDrainDefaultMs = 10000;     // EOS wait when timeout=0 (QUERY_DEFAULT_TIMEOUT_SEC)
constexpr int kReconnectEveryMs = 200;     // at most one reconnect attempt per this interval
constexpr int kReconnectTimeoutMs = 1000;  // each attempt's connect/handshake bound

struct Settings {
  nns::gst::ConnSettings conn;  // timeout: ms to wait for an answer (0: no wait)
  guint max_request = 2;
  bool silent = true;
  gint balance = 0;  // nns::edge::Balance
  bool resend = true;
};

// Timestamps of a request, given to its answer (answers come back in request order).
struct Pending {
  GstClockTime pts, dts, duration;
  guint64 offset, offset_end;
  std::chrono::steady_clock::time_point sent;
  guint64 seq = 0;  // load-balance mode: the request's number
};

struct ClientPriv {
  std::mutex lock;  // settings
  Settings s;

  // Session (streaming thread, except where noted).
  std::unique_ptr<nns::edge::ClientNode> node;  // one server (load-balance=none)
  std::unique_ptr<nns::edge::ClientPool> pool;  // several servers (load balancing)
  bool answer_caps_set = false;                 // pool: the first server set the answer caps
  std::string in_caps;
  bool in_tensor = false;
  bool out_tensor = false;
  nns::TensorsConfig out_config;
  std::string out_candidates;    // the server's answer caps (or our input caps for ANY)
  bool out_pending = false;      // not fixed: chosen with the first answer
  std::vector<GstEvent *> held;  // sticky events that must follow those caps (segment, tags)
  bool lost = false;             // the server went away; reconnect on the next buffer
  Clock::time_point last_attempt{};

  // Answers (node threads push, streaming thread pops).
  std::mutex qlock;
  std::condition_variable qcv;
  std::deque<nns::edge::Message> answers;
  std::deque<Pending> pending;  // requests in flight, oldest first
  // Load-balance mode: requests not yet answered in input order (seqs contiguous), answers
  // and losses that arrived out of order. Resolved ones at the front move to answers/pending.
  nns::edge::InOrder<Pending> lb;
  guint64 next_seq = 0;
  bool flushing = false;
  std::string closed_why;  // set by the node thread when the session ends
  bool closed = false;
  bool protocol_error = false;  // the server sent an invalid frame

  // Statistics.
  guint64 sent = 0, received = 0, dropped = 0, lost_count = 0, reconnects = 0;
};

enum {
  PROP_0,
  PROP_SILENT,
  PROP_MAX_REQUEST,
  PROP_STATS,
  PROP_LOAD_BALANCE,
  PROP_RESEND,
  PROP_CONN_FIRST
};

const nns::gst::ConnPropTable &conn_props() {
  using nns::gst::ConnProp;
  static const nns::gst::ConnPropTable t(
      PROP_CONN_FIRST,
      {{ConnProp::kHost, "Host", "A host address to receive the packets from query server",
        "localhost"},
       {ConnProp::kPort, "Port", "A port number to receive the packets from query server", nullptr,
        3001},
       {ConnProp::kDestHost, "Destination Host", "A tenor query server host to send the packets",
        "localhost"},
       {ConnProp::kDestPort, "Destination Port",
        "The port of tensor query server to send the packets", nullptr, 3000},
       {ConnProp::kConnectType, "Connect Type", "The connections type between client and server.",
        nullptr, 0, 0, false, false, nns::gst::query_connect_type_get_type},
       {ConnProp::kTopic, "Topic", "The main topic of the host.", nullptr, 0, 0, true},
       {ConnProp::kTimeout, "timeout value",
        "A timeout value (in ms) to wait message from query server after sending buffer to "
        "server. 0 means no wait.",
        nullptr, 0, G_MAXUINT}});
  return t;
}

}  // namespace

struct _GstTensorQueryClient {
  GstElement parent;
  GstPad *sinkpad;
  GstPad *srcpad;
  ClientPriv *priv;
};

G_DEFINE_TYPE(GstTensorQueryClient, gst_tensor_query_client, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_query_client, "tensor_query_client", GST_RANK_NONE,
                            GST_TYPE_TENSOR_QUERY_CLIENT)

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

namespace {

std::string caps_str(const GstCaps *c) {
  return nns::gst::caps_to_string(c);
}

// Caps with framerate forced to 0/1 (the server's rate is not the client's concern).
nns::gst::CapsPtr without_rate(const std::string &s) {
  nns::gst::CapsPtr c(gst_caps_from_string(s.c_str()));
  if (!c) return c;
  c.reset(gst_caps_make_writable(c.release()));
  for (guint i = 0; i < gst_caps_get_size(c.get()); ++i) {
    GstStructure *st = gst_caps_get_structure(c.get(), i);
    if (gst_structure_has_field(st, "framerate"))
      gst_structure_set(st, "framerate", GST_TYPE_FRACTION, 0, 1, nullptr);
  }
  return c;
}

std::optional<std::string> push_out_caps(GstTensorQueryClient *self, GstCaps *out);

// Checks the server capability against our input caps; on success sets the output caps.
std::optional<std::string> check_server_caps(GstTensorQueryClient *self, const std::string &cap) {
  auto *p = self->priv;
  const auto src = nns::edge::caps_field(cap, "query_server_src_caps");
  const auto sink = nns::edge::caps_field(cap, "query_server_sink_caps");
  if (!src || !sink)
    return "the server's capability '" + cap +
           "' lacks query_server_src_caps/query_server_sink_caps";
  auto client = without_rate(p->in_caps);
  auto server = without_rate(*src);
  if (!client || !server)
    return "cannot parse the caps: client '" + p->in_caps + "', server '" + *src + "'";
  // Tensor streams compare as tensors (dims "64:1" equals "64:1:1:1"), as upstream does.
  bool same_tensors = false;
  if (nns::gst::is_tensor_caps(client.get()) && nns::gst::is_tensor_caps(server.get()) &&
      gst_caps_is_fixed(client.get()) && gst_caps_is_fixed(server.get())) {
    try {
      same_tensors = nns::gst::config_from_caps(client.get())
                         .info.same_as(nns::gst::config_from_caps(server.get()).info);
    } catch (const nns::Error &) {
      same_tensors = false;
    }
  }
  if (!same_tensors && !gst_caps_can_intersect(client.get(), server.get()))
    return "the server cannot take the client's caps: client sends '" + p->in_caps +
           "', server (tensor_query_serversrc) takes '" + *src + "'";
  // Output caps: the server sink's caps when fixed; ANY (a pass-through server) means our
  // input caps; otherwise the choice waits for the first answer (set_out_caps_for).
  nns::gst::CapsPtr out(gst_caps_from_string(sink->c_str()));
  if (!out || gst_caps_is_empty(out.get()))
    return "cannot parse the server's answer caps '" + *sink + "'";
  if (gst_caps_is_any(out.get())) out.reset(gst_caps_from_string(p->in_caps.c_str()));
  if (p->answer_caps_set) {  // another server of the pool: its answers must be the same
    nns::gst::CapsPtr have(gst_caps_from_string(p->out_candidates.c_str()));
    if (!have || !gst_caps_can_intersect(out.get(), have.get()))
      return "its answer caps '" + caps_str(out.get()) + "' differ from the other servers' '" +
             p->out_candidates + "'";
    return std::nullopt;
  }
  p->out_candidates = caps_str(out.get());
  if (!gst_caps_is_fixed(out.get())) {
    p->out_pending = true;
    p->answer_caps_set = p->pool != nullptr;
    return std::nullopt;
  }
  p->out_pending = false;
  auto err = push_out_caps(self, out.get());
  p->answer_caps_set = p->pool != nullptr && !err;
  return err;
}

// Unfixed answer caps (a server whose tensor_filter announces every shape it can produce):
// the first structure whose tensor sizes match the memories of the first answer, else the
// part shared with our input, else the first structure.
void set_out_caps_for(GstTensorQueryClient *self, const nns::edge::Message &m) {
  auto *p = self->priv;
  nns::gst::CapsPtr cands(gst_caps_from_string(p->out_candidates.c_str()));
  nns::gst::CapsPtr chosen;
  for (guint i = 0; cands && i < gst_caps_get_size(cands.get()) && !chosen; ++i) {
    nns::gst::CapsPtr one(gst_caps_fixate(gst_caps_copy_nth(cands.get(), i)));
    if (!nns::gst::is_tensor_caps(one.get())) continue;
    try {
      const auto cfg = nns::gst::config_from_caps(one.get());
      if (cfg.info.format != nns::TensorFormat::kStatic || cfg.info.size() != m.mems.size())
        continue;
      bool match = true;
      for (std::size_t k = 0; k < m.mems.size() && match; ++k)
        match = cfg.info[k].byte_size() == m.mems[k]->size();
      if (match) chosen = std::move(one);
    } catch (const nns::Error &) {
    }
  }
  if (!chosen && cands) {
    nns::gst::CapsPtr in(gst_caps_from_string(p->in_caps.c_str()));
    nns::gst::CapsPtr both(gst_caps_intersect(cands.get(), in.get()));
    chosen.reset(gst_caps_fixate(gst_caps_is_empty(both.get()) ? gst_caps_ref(cands.get())
                                                               : both.release()));
  }
  p->out_pending = false;
  if (!chosen) nns::fail(nns::ErrorKind::kNegotiation, "no caps for the server's answers");
  if (auto err = push_out_caps(self, chosen.get())) nns::fail(nns::ErrorKind::kNegotiation, *err);
}

std::optional<std::string> push_out_caps(GstTensorQueryClient *self, GstCaps *out) {
  auto *p = self->priv;
  if (!gst_pad_push_event(self->srcpad, gst_event_new_caps(out))) {
    // Downstream refused: say so with both caps.
    nns::gst::CapsPtr peer(gst_pad_peer_query_caps(self->srcpad, nullptr));
    return "downstream does not accept the server's answer caps '" + caps_str(out) +
           "' (it takes '" + (peer ? caps_str(peer.get()) : std::string("?")) + "')";
  }
  p->out_tensor = nns::gst::is_tensor_caps(out);
  p->out_config = p->out_tensor ? nns::gst::config_from_caps(out) : nns::TensorsConfig{};
  std::vector<GstEvent *> held;
  held.swap(p->held);
  for (GstEvent *e : held) gst_pad_push_event(self->srcpad, e);
  return std::nullopt;
}

void post_info(GstTensorQueryClient *self, const std::string &text);

// Load-balance mode: resolved requests at the front of lb move to answers/pending (where
// push_answers takes them); lost ones are counted.
void promote_locked(ClientPriv *p) {
  p->lb.pop_ready(
      [p](Pending &pd, nns::edge::Message &&m) {
        p->answers.push_back(std::move(m));
        p->pending.push_back(pd);
      },
      [p](Pending &) { ++p->lost_count; });
}

void make_pool(GstTensorQueryClient *self, const Settings &s, const nns::edge::NodeOptions &o) {
  auto *p = self->priv;
  nns::edge::PoolOptions po;
  po.node = o;
  po.type = s.conn.type();
  if (po.type == nns::edge::ConnectType::kTcp)
    po.endpoints = nns::edge::parse_endpoints(o.dest_host, o.dest_port);
  po.policy = static_cast<nns::edge::Balance>(s.balance);
  po.resend = s.resend;
  nns::edge::PoolCallbacks cb;
  cb.alloc = nns::gst::gst_memory_allocator();
  cb.on_answer = [p](guint64 seq, nns::edge::Message &&m) {
    std::lock_guard<std::mutex> l(p->qlock);
    if (!p->lb.answer(seq, std::move(m))) return;
    promote_locked(p);
    p->qcv.notify_all();
  };
  cb.on_lost = [p](guint64 seq) {
    std::lock_guard<std::mutex> l(p->qlock);
    if (!p->lb.lose(seq)) return;
    promote_locked(p);
    p->qcv.notify_all();
  };
  cb.on_warning = [self](const std::string &text) { NNS_POST_WARNING(self, text); };
  cb.on_info = [self](const std::string &text) { post_info(self, text); };
  cb.accept_caps = [self](const std::string &cap) { return check_server_caps(self, cap); };
  p->answer_caps_set = false;
  p->pool = std::make_unique<nns::edge::ClientPool>(std::move(po), std::move(cb));
}

void make_node(GstTensorQueryClient *self, int timeout_ms) {
  auto *p = self->priv;
  Settings s;
  {
    std::lock_guard<std::mutex> l(p->lock);
    s = p->s;
  }
  nns::gst::require_tcp(s.conn.connect_type);
  nns::edge::NodeOptions o = s.conn.node_options(nns::edge::Role::kQueryClient);
  o.connect_timeout_ms = timeout_ms;
  if (s.balance != 0 ||
      (s.conn.type() == nns::edge::ConnectType::kTcp &&
       o.dest_host.find_first_of(",:") != std::string::npos))  // a list, or host:port
    return make_pool(self, s, o);
  nns::edge::NodeCallbacks cb;
  cb.alloc = nns::gst::gst_memory_allocator();
  cb.on_data = [p](nns::edge::Message &&m) {
    std::lock_guard<std::mutex> l(p->qlock);
    p->answers.push_back(std::move(m));
    p->qcv.notify_all();
  };
  cb.on_closed = [p](const std::string &why, nns::edge::CloseKind kind) {
    std::lock_guard<std::mutex> l(p->qlock);
    p->closed = true;
    p->protocol_error = kind == nns::edge::CloseKind::kProtocol;
    p->closed_why = why;
    p->qcv.notify_all();
  };
  cb.accept_caps = [self](const std::string &cap) { return check_server_caps(self, cap); };
  p->node = nns::edge::make_client(s.conn.type(), o, std::move(cb));
}

void post_info(GstTensorQueryClient *self, const std::string &text) {
  gst_element_message_full(GST_ELEMENT(self), GST_MESSAGE_INFO, GST_CORE_ERROR,
                           GST_CORE_ERROR_FAILED, g_strdup(text.c_str()), nullptr, __FILE__,
                           GST_FUNCTION, __LINE__);
}

// Called on the streaming thread: turns a session end reported by the node into a warning.
void note_loss(GstTensorQueryClient *self) {
  auto *p = self->priv;
  std::string why;
  guint64 in_flight = 0;
  {
    std::lock_guard<std::mutex> l(p->qlock);
    if (!p->closed) return;
    if (p->protocol_error)  // not a network hiccup: reconnecting would meet the same peer
      nns::fail(nns::ErrorKind::kStream,
                "the query server sent an invalid frame: " + p->closed_why);
    p->closed = false;
    why = p->closed_why;
    in_flight = p->pending.size() - std::min(p->pending.size(), p->answers.size());
    // Answers already received stay; the requests without one are lost.
    while (p->pending.size() > p->answers.size()) p->pending.pop_back();
    p->lost_count += in_flight;
  }
  p->lost = true;
  NNS_POST_WARNING(self, "lost the connection to the query server (" + why + "); " +
                             std::to_string(in_flight) +
                             " request(s) in flight lost; reconnecting");
}

// Pushes every received answer; waits up to `wait_ms` for the first one when requests are
// in flight.
GstFlowReturn push_answers(GstTensorQueryClient *self, int wait_ms) {
  auto *p = self->priv;
  GstFlowReturn ret = GST_FLOW_OK;
  for (;;) {
    nns::edge::Message m;
    Pending pend{};
    {
      std::unique_lock<std::mutex> l(p->qlock);
      if (wait_ms > 0 && p->answers.empty() && !p->pending.empty())
        p->qcv.wait_for(l, std::chrono::milliseconds(wait_ms),
                        [&] { return !p->answers.empty() || p->flushing || p->closed; });
      wait_ms = 0;
      if (p->answers.empty() || p->flushing) break;
      m = std::move(p->answers.front());
      p->answers.pop_front();
      if (!p->pending.empty()) {
        pend = p->pending.front();
        p->pending.pop_front();
      } else {
        pend = {GST_CLOCK_TIME_NONE,    GST_CLOCK_TIME_NONE,    GST_CLOCK_TIME_NONE,
                GST_BUFFER_OFFSET_NONE, GST_BUFFER_OFFSET_NONE, Clock::now()};
      }
      ++p->received;
      GST_INFO_OBJECT(self, "answer %" G_GUINT64_FORMAT ": round trip %.0f us", p->received,
                      std::chrono::duration<double, std::micro>(Clock::now() - pend.sent).count());
    }
    if (p->out_pending) set_out_caps_for(self, m);
    GstBuffer *out =
        nns::gst::buffer_from_message(std::move(m), p->out_tensor ? &p->out_config : nullptr);
    GST_BUFFER_PTS(out) = pend.pts;
    GST_BUFFER_DTS(out) = pend.dts;
    GST_BUFFER_DURATION(out) = pend.duration;
    GST_BUFFER_OFFSET(out) = pend.offset;
    GST_BUFFER_OFFSET_END(out) = pend.offset_end;
    ret = gst_pad_push(self->srcpad, out);
    if (ret != GST_FLOW_OK) break;
  }
  return ret;
}

bool try_reconnect(GstTensorQueryClient *self) {
  auto *p = self->priv;
  const auto now = Clock::now();
  if (now - p->last_attempt < std::chrono::milliseconds(kReconnectEveryMs)) return false;
  p->last_attempt = now;
  p->node.reset();  // a fresh session with a short handshake bound, so the chain never stalls
  make_node(self, kReconnectTimeoutMs);
  try {
    p->node->connect();
  } catch (const nns::Error &e) {
    GST_DEBUG_OBJECT(self, "reconnect failed: %s", e.what());
    return false;
  }
  p->lost = false;
  {
    std::lock_guard<std::mutex> l(p->qlock);
    ++p->reconnects;
  }
  post_info(self, "reconnected to the query server " + p->node->server_name() + " (client id " +
                      std::to_string(p->node->client_id()) + ")");
  return true;
}

// Load-balance mode: the window (max-request) full, waits up to `timeout` for the oldest
// answer; then sends to the server the pool picks and pushes the answers ready in input order.
GstFlowReturn chain_pool(GstTensorQueryClient *self, GstBuffer *buf) {
  auto *p = self->priv;
  guint max_request, timeout;
  {
    std::lock_guard<std::mutex> l(p->lock);
    max_request = p->s.max_request;
    timeout = p->s.conn.timeout;
  }
  auto in_flight = [p] { return p->lb.size() + p->pending.size(); };
  if (max_request > 0 && timeout > 0) {
    std::unique_lock<std::mutex> l(p->qlock);
    p->qcv.wait_for(l, std::chrono::milliseconds(timeout), [&] {
      return in_flight() < max_request || !p->answers.empty() || p->flushing;
    });
  }
  GstFlowReturn ret = push_answers(self, 0);
  if (ret != GST_FLOW_OK) return ret;
  guint64 seq;
  {
    std::lock_guard<std::mutex> l(p->qlock);
    if (max_request > 0 && in_flight() >= max_request) {
      ++p->dropped;
      return GST_FLOW_OK;
    }
    seq = p->next_seq++;
    p->lb.add(seq, {GST_BUFFER_PTS(buf), GST_BUFFER_DTS(buf), GST_BUFFER_DURATION(buf),
                    GST_BUFFER_OFFSET(buf), GST_BUFFER_OFFSET_END(buf), Clock::now(), seq});
  }
  auto view = std::make_shared<nns::gst::FrameView>(buf, p->in_tensor);
  std::shared_ptr<const nns::edge::OutFrame> frame(view, &view->frame());
  const bool ok = p->pool->submit(seq, std::move(frame));
  {
    std::lock_guard<std::mutex> l(p->qlock);
    if (ok) {
      ++p->sent;
    } else if (p->lb.lose(seq)) {  // no server connected now
      promote_locked(p);
    }
  }
  return push_answers(self, 0);
}

GstFlowReturn client_chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_QUERY_CLIENT(parent);
  nns::gst::BufferPtr in(buf);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = self->priv;
    if (!p->node && !p->pool)
      nns::fail(nns::ErrorKind::kNegotiation, "a buffer arrived before caps");
    if (p->pool) return chain_pool(self, buf);
    guint max_request, timeout;
    {
      std::lock_guard<std::mutex> l(p->lock);
      max_request = p->s.max_request;
      timeout = p->s.conn.timeout;
    }
    note_loss(self);
    bool send = true;
    if (p->lost && !try_reconnect(self)) {
      std::lock_guard<std::mutex> l(p->qlock);
      ++p->lost_count;
      send = false;
    }
    if (send && max_request > 0) {
      std::lock_guard<std::mutex> l(p->qlock);
      if (p->pending.size() >= max_request) {
        ++p->dropped;
        send = false;
      }
    }
    if (send) {
      {
        std::lock_guard<std::mutex> l(p->qlock);
        p->pending.push_back({GST_BUFFER_PTS(buf), GST_BUFFER_DTS(buf), GST_BUFFER_DURATION(buf),
                              GST_BUFFER_OFFSET(buf), GST_BUFFER_OFFSET_END(buf), Clock::now()});
      }
      nns::gst::FrameView view(buf, p->in_tensor);
      std::string why;
      if (p->node->send(view.frame(), &why)) {
        std::lock_guard<std::mutex> l(p->qlock);
        ++p->sent;
      } else {
        note_loss(self);  // counts this request with the others in flight
      }
    }
    return push_answers(self, static_cast<int>(timeout));
  });
}

void drain(GstTensorQueryClient *self) {
  auto *p = self->priv;
  guint timeout;
  {
    std::lock_guard<std::mutex> l(p->lock);
    timeout = p->s.conn.timeout;
  }
  const auto deadline =
      Clock::now() + std::chrono::milliseconds(timeout ? timeout : kDrainDefaultMs);
  for (;;) {
    {
      std::unique_lock<std::mutex> l(p->qlock);
      p->qcv.wait_until(l, deadline, [&] {
        return p->flushing || p->closed ||
               (p->lb.size() == 0 && p->answers.size() >= p->pending.size());
      });
    }
    if (push_answers(self, 0) != GST_FLOW_OK) return;
    std::lock_guard<std::mutex> l(p->qlock);
    const std::size_t left = p->pending.size() + p->lb.size();
    if (left == 0 || p->flushing || p->closed || Clock::now() >= deadline) {
      if (left && !p->flushing) {
        p->lost_count += left;
        GST_WARNING_OBJECT(self, "EOS: %zu answer(s) never came", left);
        p->pending.clear();
        p->lb.clear();
      }
      return;
    }
  }
}

gboolean client_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_QUERY_CLIENT(parent);
  auto *p = self->priv;
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_CAPS: {
      nns::gst::EventPtr ev(event);
      return nns::gst::guard(self, FALSE, [&]() -> gboolean {
        GstCaps *caps = nullptr;
        gst_event_parse_caps(ev.get(), &caps);
        const std::string s = caps_str(caps);
        if (p->node && s == p->in_caps && p->node->connected()) return TRUE;
        if (p->pool && s == p->in_caps && p->pool->live() > 0) return TRUE;
        p->in_caps = s;
        p->in_tensor = nns::gst::is_tensor_caps(caps);
        if (p->node) p->node->disconnect();
        p->node.reset();
        p->pool.reset();
        make_node(self, 5000);
        try {
          if (p->pool)
            p->pool->start();
          else
            p->node->connect();
        } catch (const nns::Error &e) {
          if (e.kind() == nns::ErrorKind::kNegotiation) throw;
          nns::fail(nns::ErrorKind::kNotFound,
                    std::string("cannot reach the query server: ") + e.what());
        }
        p->lost = false;
        return TRUE;
      });
    }
    case GST_EVENT_SEGMENT:
    case GST_EVENT_TAG:
      if (p->out_pending) {  // caps come with the first answer; keep the sticky order
        p->held.push_back(event);
        return TRUE;
      }
      break;
    case GST_EVENT_EOS:
      nns::gst::guard_void(self, [&] { drain(self); });
      break;
    case GST_EVENT_FLUSH_START: {
      std::lock_guard<std::mutex> l(p->qlock);
      p->flushing = true;
      p->qcv.notify_all();
      break;
    }
    case GST_EVENT_FLUSH_STOP: {
      std::lock_guard<std::mutex> l(p->qlock);
      p->flushing = false;
      p->answers.clear();
      p->pending.clear();
      p->lb.clear();
      break;
    }
    default:
      break;
  }
  return gst_pad_event_default(pad, parent, event);
}

GstStateChangeReturn client_change_state(GstElement *element, GstStateChange t) {
  auto *self = GST_TENSOR_QUERY_CLIENT(element);
  auto *p = self->priv;
  if (t == GST_STATE_CHANGE_PAUSED_TO_READY) {
    std::lock_guard<std::mutex> l(p->qlock);
    p->flushing = true;
    p->qcv.notify_all();
  }
  if (t == GST_STATE_CHANGE_READY_TO_PAUSED) {
    std::lock_guard<std::mutex> l(p->qlock);
    p->flushing = false;
    p->closed = false;
    p->protocol_error = false;
    p->answers.clear();
    p->pending.clear();
    p->lb.clear();
    p->sent = p->received = p->dropped = p->lost_count = p->reconnects = 0;
  }
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_query_client_parent_class)->change_state(element, t);
  if (t == GST_STATE_CHANGE_PAUSED_TO_READY) {
    p->node.reset();  // joins the connection threads
    p->pool.reset();
    p->in_caps.clear();
    p->out_pending = false;
    for (GstEvent *e : p->held) gst_event_unref(e);
    p->held.clear();
    p->lost = false;
    std::lock_guard<std::mutex> l(p->qlock);
    p->answers.clear();
    p->pending.clear();
    p->lb.clear();
  }
  return ret;
}

}  // namespace

static void client_set_property(GObject *object, guint id, const GValue *value, GParamSpec *pspec) {
  auto *p = GST_TENSOR_QUERY_CLIENT(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().set(id, value, &p->s.conn)) return;
  switch (id) {
    case PROP_SILENT:
      p->s.silent = g_value_get_boolean(value);
      break;
    case PROP_MAX_REQUEST:
      p->s.max_request = g_value_get_uint(value);
      break;
    case PROP_LOAD_BALANCE:
      p->s.balance = g_value_get_enum(value);
      break;
    case PROP_RESEND:
      p->s.resend = g_value_get_boolean(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void client_get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec) {
  auto *p = GST_TENSOR_QUERY_CLIENT(object)->priv;
  if (id == PROP_STATS) {
    std::vector<nns::edge::ServerStats> servers;
    if (p->pool) servers = p->pool->stats();
    std::lock_guard<std::mutex> l(p->qlock);
    GstStructure *st = gst_structure_new(
        "application/x-query-client-stats", "sent", G_TYPE_UINT64, p->sent, "received",
        G_TYPE_UINT64, p->received, "dropped", G_TYPE_UINT64, p->dropped, "lost", G_TYPE_UINT64,
        p->lost_count, "reconnects", G_TYPE_UINT64, p->reconnects, nullptr);
    if (p->pool) nns::gst::add_server_stats(st, servers);
    g_value_take_boxed(value, st);
    return;
  }
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().get(id, value, p->s.conn)) return;
  switch (id) {
    case PROP_SILENT:
      g_value_set_boolean(value, p->s.silent);
      break;
    case PROP_MAX_REQUEST:
      g_value_set_uint(value, p->s.max_request);
      break;
    case PROP_LOAD_BALANCE:
      g_value_set_enum(value, p->s.balance);
      break;
    case PROP_RESEND:
      g_value_set_boolean(value, p->s.resend);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void client_finalize(GObject *object) {
  auto *self = GST_TENSOR_QUERY_CLIENT(object);
  for (GstEvent *e : self->priv->held) gst_event_unref(e);
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_query_client_parent_class)->finalize(object);
}

static void gst_tensor_query_client_class_init(GstTensorQueryClientClass *klass) {
  auto *gobject = G_OBJECT_CLASS(klass);
  auto *element = GST_ELEMENT_CLASS(klass);
  gobject->set_property = client_set_property;
  gobject->get_property = client_get_property;
  gobject->finalize = client_finalize;
  element->change_state = client_change_state;
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  conn_props().install(gobject);
  g_object_class_install_property(
      gobject, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Produce verbose output", TRUE, rw));
  g_object_class_install_property(
      gobject, PROP_MAX_REQUEST,
      g_param_spec_uint("max-request", "Maximum number of request",
                        "Sets the maximum number of buffers to request to the query server. If "
                        "the processing speed of query server is slower than the query client, "
                        "the input buffer is dropped. Two buffers are requested by default, and 0 "
                        "means that all buffers are sent to query server without drop. ",
                        0, G_MAXUINT, 2, rw));
  g_object_class_install_property(
      gobject, PROP_LOAD_BALANCE,
      g_param_spec_enum("load-balance", "Load balance",
                        "How requests are spread over the servers (HYBRID: every server announcing "
                        "the topic; TCP: the comma-separated dest-host list): none uses one server "
                        "and fails over, round-robin, least-outstanding",
                        nns::gst::query_load_balance_get_type(), 0, rw));
  g_object_class_install_property(
      gobject, PROP_RESEND,
      g_param_spec_boolean("resend-on-failover", "Resend on fail-over",
                           "With load balancing: requests in flight to a server that goes away "
                           "are sent once more to another server (false: counted as lost)",
                           TRUE, rw));
  g_object_class_install_property(
      gobject, PROP_STATS,
      g_param_spec_boxed("stats", "Statistics",
                         "Requests sent, answers received, inputs dropped by max-request, "
                         "requests lost with the connection, reconnects",
                         GST_TYPE_STRUCTURE,
                         static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  gst_element_class_add_static_pad_template(element, &sink_template);
  gst_element_class_add_static_pad_template(element, &src_template);
  gst_element_class_set_static_metadata(element, "TensorQueryClient", "Filter/Tensor/Query",
                                        "Handle querying tensor data through the network",
                                        "nnstreamer-cpp");
  GST_DEBUG_CATEGORY_INIT(query_client_debug, "tensor_query_client", 0, "Tensor Query Client");
}

static void gst_tensor_query_client_init(GstTensorQueryClient *self) {
  self->priv = new ClientPriv();
  self->priv->s.conn = conn_props().defaults();
  self->sinkpad = gst_pad_new_from_static_template(&sink_template, "sink");
  gst_pad_set_chain_function(self->sinkpad, client_chain);
  gst_pad_set_event_function(self->sinkpad, client_sink_event);
  GST_PAD_SET_PROXY_ALLOCATION(self->sinkpad);
  gst_element_add_pad(GST_ELEMENT(self), self->sinkpad);
  self->srcpad = gst_pad_new_from_static_template(&src_template, "src");
  gst_pad_use_fixed_caps(self->srcpad);
  gst_element_add_pad(GST_ELEMENT(self), self->srcpad);
}
