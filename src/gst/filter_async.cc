// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/filter_async.h"

#include <cerrno>
#include <cstring>
#include <unordered_map>

#include "core/error.h"
#include "core/filter_desc.h"
#include "core/meta_header.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"

GST_DEBUG_CATEGORY_STATIC(filter_async_debug);
#define GST_CAT_DEFAULT filter_async_debug

namespace nns::gst {
namespace {

constexpr int kMaxWarnings = 3;  // bad dispatches posted on the bus; the rest only logged

// Every open dispatcher by id. Entries hold a reference so a dispatch that found one can use it
// after a concurrent close() removed it (close() then waits for that dispatch).
std::mutex g_mu;
uint64_t g_next_id = 1;
std::unordered_map<uint64_t, std::shared_ptr<AsyncDispatcher>> &table() {
  static auto *t = new std::unordered_map<uint64_t, std::shared_ptr<AsyncDispatcher>>();
  return *t;
}

std::shared_ptr<AsyncDispatcher> lookup(uint64_t id) {
  std::lock_guard lk(g_mu);
  auto it = table().find(id);
  return it == table().end() ? nullptr : it->second;
}

void write_msg(char *err, size_t errlen, const std::string &msg) {
  if (!err || errlen == 0) return;
  std::size_t n = std::min(msg.size(), errlen - 1);
  std::memcpy(err, msg.data(), n);
  err[n] = '\0';
}

}  // namespace

std::shared_ptr<AsyncDispatcher> AsyncDispatcher::create(GstBaseTransform *element) {
  static std::once_flag once;
  std::call_once(once, [] {
    GST_DEBUG_CATEGORY_INIT(filter_async_debug, "tensor_filter_async", 0,
                            "tensor_filter invoke-async outputs");
  });
  std::shared_ptr<AsyncDispatcher> d(new AsyncDispatcher(element));
  std::lock_guard lk(g_mu);
  d->id_ = g_next_id++;
  table()[d->id_] = d;
  return d;
}

AsyncDispatcher::AsyncDispatcher(GstBaseTransform *element) : element_(element) {}

AsyncDispatcher::~AsyncDispatcher() = default;

void AsyncDispatcher::close() {
  {
    std::lock_guard lk(g_mu);
    table().erase(id_);  // new dispatches now fail; `this` lives on through the caller's ref
  }
  std::unique_lock lk(mu_);
  closed_ = true;
  cv_.notify_all();
  cv_.wait(lk, [this] { return in_flight_ == 0; });
  for (auto &d : deferred_)
    if (d.buf) gst_buffer_unref(d.buf);
  deferred_.clear();
}

void AsyncDispatcher::configure(const TensorsInfo &model_out, bool flexible) {
  std::lock_guard lk(fmt_mu_);
  model_out_ = model_out;
  flexible_ = flexible;
  configured_ = true;
}

nns_filter_async_ctx AsyncDispatcher::begin_input(GstBuffer *inbuf) {
  nns_filter_async_ctx c{};
  c.dispatch = &AsyncDispatcher::dispatch;
  c.target = id_;
  c.pts = GST_BUFFER_PTS(inbuf);
  c.dts = GST_BUFFER_DTS(inbuf);
  c.duration = GST_BUFFER_DURATION(inbuf);
  std::lock_guard lk(mu_);
  c.input = next_input_++;
  pending_.insert(c.input);  // until invoke_async returns 0 or the back end sends LAST
  in_invoke_ = true;
  invoker_ = std::this_thread::get_id();
  return c;
}

void AsyncDispatcher::end_input(const nns_filter_async_ctx &ctx, int rc) {
  {
    std::lock_guard lk(mu_);
    in_invoke_ = false;
  }
  if (rc == NNS_FILTER_ASYNC_PENDING) return;
  // Ended now, unless an output of it still waits in deferred_ (push_deferred ends it).
  {
    std::lock_guard lk(mu_);
    for (auto it = deferred_.rbegin(); it != deferred_.rend(); ++it)
      if (it->input == ctx.input) {
        it->last = true;
        return;
      }
  }
  finish_input(ctx.input);
}

void AsyncDispatcher::push_deferred() {
  std::vector<Deferred> todo;
  {
    std::lock_guard lk(mu_);
    if (deferred_.empty()) return;
    todo.swap(deferred_);
  }
  std::lock_guard out_lk(out_mu_);
  for (auto &d : todo) {
    std::string msg;
    if (d.buf) push_buffer(d.buf, msg);
    if (d.last) finish_input(d.input);
  }
}

void AsyncDispatcher::finish_input(uint64_t input) {
  std::lock_guard lk(mu_);
  if (pending_.erase(input)) cv_.notify_all();
}

void AsyncDispatcher::flush() {
  std::lock_guard lk(mu_);
  first_valid_ = next_input_;
  pending_.clear();
  flow_ = GST_FLOW_OK;
  cv_.notify_all();
}

bool AsyncDispatcher::pads_flushing() const {
  return GST_PAD_IS_FLUSHING(GST_BASE_TRANSFORM_SRC_PAD(element_)) ||
         GST_PAD_IS_FLUSHING(GST_BASE_TRANSFORM_SINK_PAD(element_));
}

void AsyncDispatcher::wait_drained() {
  std::unique_lock lk(mu_);
  while (!closed_ && !pending_.empty()) {
    // Deactivating the pads (state change) sets them flushing without an event: poll.
    if (pads_flushing()) return;
    GST_LOG_OBJECT(element_, "EOS waits for %zu pending input(s)", pending_.size());
    cv_.wait_for(lk, std::chrono::milliseconds(50));
  }
}

GstFlowReturn AsyncDispatcher::take_flow() {
  std::lock_guard lk(mu_);
  GstFlowReturn f = flow_;
  flow_ = GST_FLOW_OK;
  return f;
}

std::size_t AsyncDispatcher::pending() const {
  std::lock_guard lk(mu_);
  return pending_.size();
}

uint64_t AsyncDispatcher::pushed() const {
  std::lock_guard lk(mu_);
  return pushed_;
}

int AsyncDispatcher::dispatch(const nns_filter_async_ctx *ctx, const nns_tensors_desc *info,
                              const GstTensorMemory *out, uint32_t num_out, uint32_t flags,
                              char *err, size_t errlen) {
  if (!ctx) return -EINVAL;
  std::shared_ptr<AsyncDispatcher> d = lookup(ctx->target);
  if (!d) {
    write_msg(err, errlen, "tensor_filter has stopped: output dropped");
    return -ESHUTDOWN;
  }
  std::string msg;
  int rc;
  try {
    rc = d->deliver(*ctx, info, out, num_out, flags, msg);
  } catch (const std::exception &e) {
    msg = std::string("internal error: ") + e.what();
    rc = -EIO;
  }
  if (rc != 0) write_msg(err, errlen, msg);
  return rc;
}

int AsyncDispatcher::deliver(const nns_filter_async_ctx &ctx, const nns_tensors_desc *info,
                             const GstTensorMemory *out, uint32_t num_out, uint32_t flags,
                             std::string &msg) {
  bool stale;
  {
    std::lock_guard lk(mu_);
    if (closed_) {
      msg = "tensor_filter has stopped: output dropped";
      return -ESHUTDOWN;
    }
    ++in_flight_;
    stale = ctx.input < first_valid_;
  }
  struct Leave {
    AsyncDispatcher *d;
    ~Leave() {
      std::lock_guard lk(d->mu_);
      if (--d->in_flight_ == 0) d->cv_.notify_all();
    }
  } leave{this};

  int rc = 0;
  if (stale) {
    msg = "the stream was flushed after this input: output dropped";
    rc = -ECANCELED;
  } else if (out || num_out > 0) {
    GstBuffer *buf = build(ctx, info, out, num_out, msg);
    if (!buf) {
      rc = -EINVAL;
    } else {
      bool defer;
      {
        std::lock_guard lk(mu_);
        defer = in_invoke_ && invoker_ == std::this_thread::get_id();
        if (defer) deferred_.push_back(Deferred{buf, ctx.input, false});
      }
      if (!defer) {
        std::lock_guard out_lk(out_mu_);
        rc = push_buffer(buf, msg);
      }
    }
    if (rc == -EINVAL) {
      std::string text = "invoke-async: output not pushed: " + msg;
      bool post;
      {
        std::lock_guard lk(mu_);
        post = warnings_++ < kMaxWarnings;
      }
      if (post)
        NNS_POST_WARNING(element_, text);
      else
        GST_WARNING_OBJECT(element_, "%s", text.c_str());
    }
  }
  if (flags & NNS_FILTER_ASYNC_LAST) {
    bool queued = false;
    {
      std::lock_guard lk(mu_);
      for (auto it = deferred_.rbegin(); it != deferred_.rend() && !queued; ++it)
        if (it->input == ctx.input) queued = it->last = true;  // ends after its outputs
    }
    if (!queued) finish_input(ctx.input);
  }
  return rc;
}

GstBuffer *AsyncDispatcher::build(const nns_filter_async_ctx &ctx, const nns_tensors_desc *info,
                                  const GstTensorMemory *out, uint32_t n, std::string &msg) {
  TensorsInfo negotiated;
  bool flexible, configured;
  {
    std::lock_guard lk(fmt_mu_);
    negotiated = model_out_;
    flexible = flexible_;
    configured = configured_;
  }
  if (!configured) {
    msg = "the output caps are not negotiated yet";
    return nullptr;
  }
  TensorsInfo got;
  if (info) {
    try {
      got = info_from_desc(*info);
    } catch (const Error &e) {
      msg = e.what();
      return nullptr;
    }
  } else if (negotiated.size() > 0) {
    got = negotiated;
  } else {
    msg =
        "the output is flexible (invoke-dynamic), so each dispatch must describe its tensors "
        "(info is NULL)";
    return nullptr;
  }
  got.format = TensorFormat::kStatic;
  if (n == 0 || !out || got.size() != n) {
    msg = "dispatched " + std::to_string(n) + " tensor(s), but the description has " +
          std::to_string(got.size());
    return nullptr;
  }
  if (!got.valid()) {
    msg = "dispatched tensors have an invalid description: " + got.to_string();
    return nullptr;
  }
  if (!flexible && !got.same_as(negotiated)) {
    msg = "dispatched " + got.to_string() + ", but the negotiated output is " +
          negotiated.to_string();
    return nullptr;
  }
  for (uint32_t i = 0; i < n; ++i) {
    std::size_t want = got[i].byte_size();
    if (out[i].size != want || (want > 0 && !out[i].data)) {
      msg = "dispatched tensor " + std::to_string(i) + " has " + std::to_string(out[i].size) +
            " bytes" + (out[i].data ? "" : " and no data") + ", expected " + std::to_string(want) +
            " for " + got[i].to_string();
      return nullptr;
    }
  }

  GstBuffer *buf = gst_buffer_new();
  const std::size_t hsize = flexible ? kMetaHeaderSize : 0;
  for (uint32_t i = 0; i < n; ++i) {
    GstMemory *m = gst_allocator_alloc(nullptr, hsize + out[i].size, nullptr);
    {
      MemoryMap mm(m, GST_MAP_WRITE);
      if (hsize)  // invoke-dynamic (no negotiated tensors) marks it, as NNStreamer does
        write_meta_header(flexible_header(got[i].type, got[i].dims, MediaType::kTensor,
                                          negotiated.size() == 0 ? FlexHeaderKind::kMarkedFlexible
                                                                 : FlexHeaderKind::kFromInfo),
                          mm.data());
      if (out[i].size) std::memcpy(mm.data() + hsize, out[i].data, out[i].size);
    }
    if (n <= kMemoryMax)
      gst_buffer_append_memory(buf, m);
    else
      buffer_append_tensor(buf, m, got[i]);
  }
  GST_BUFFER_PTS(buf) = ctx.pts;
  GST_BUFFER_DTS(buf) = ctx.dts;
  GST_BUFFER_DURATION(buf) = ctx.duration;
  return buf;
}

int AsyncDispatcher::push_buffer(GstBuffer *buf, std::string &msg) {
  GstFlowReturn fr = gst_pad_push(GST_BASE_TRANSFORM_SRC_PAD(element_), buf);
  std::lock_guard lk(mu_);
  if (fr == GST_FLOW_OK) {
    ++pushed_;
    return 0;
  }
  msg = std::string("downstream returned ") + gst_flow_get_name(fr);
  GST_DEBUG_OBJECT(element_, "async push: %s", gst_flow_get_name(fr));
  if (fr == GST_FLOW_FLUSHING) return -ECANCELED;
  if (flow_ == GST_FLOW_OK) flow_ = fr;
  return -EPIPE;
}

}  // namespace nns::gst
