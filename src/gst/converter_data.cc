// SPDX-License-Identifier: LGPL-2.1-only
// tensor_converter data path: one input buffer -> tensor buffers pushed downstream.
#include "core/error.h"
#include "core/c_tensor_info.h"
#include "gst/converter_state.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

#define GST_CAT_DEFAULT nns_tensor_converter_debug

namespace nns::gst {
namespace {

GstBuffer *shell_with(GstBuffer *in, GstMemory *mem) {
  GstBuffer *out = gst_buffer_new();
  gst_buffer_append_memory(out, mem);
  gst_buffer_copy_into(
      out, in, static_cast<GstBufferCopyFlags>(GST_BUFFER_COPY_FLAGS | GST_BUFFER_COPY_TIMESTAMPS),
      0, static_cast<gsize>(-1));
  return out;
}

// The whole buffer as one memory: its only memory (a new ref) or a merged copy.
GstMemory *single_memory(GstBuffer *buf, gsize size) {
  GstMemory *mem = gst_buffer_n_memory(buf) == 1 ? gst_buffer_get_memory(buf, 0)
                                                 : gst_buffer_get_all_memory(buf);
  if (gst_memory_get_sizes(mem, nullptr, nullptr) != size) {
    GstMemory *sub = gst_memory_share(mem, 0, size);
    gst_memory_unref(mem);
    mem = sub;
  }
  return mem;
}

}  // namespace

void push_segment(ConverterState *p) {
  if (!p->need_segment) return;
  p->need_segment = false;
  if (p->segment.format == GST_FORMAT_BYTES) {
    GstSegment seg;
    gst_segment_init(&seg, GST_FORMAT_TIME);
    const auto &c = p->sent;
    if (c.rate_n > 0 && c.rate_d > 0 && p->segment.start > 0 && p->media.frame_size > 0) {
      seg.start = seg.time = gst_util_uint64_scale(p->segment.start * c.rate_d, GST_SECOND,
                                                   p->media.frame_size * c.rate_n);
    }
    p->segment = seg;
  }
  gst_pad_push_event(p->srcpad, gst_event_new_segment(&p->segment));
}

namespace {

void stamp(ConverterState *p, GstBuffer *buf, guint frames_in) {
  if (p->set_ts) {
    const auto &c = p->sent;
    const bool rate = c.rate_n > 0 && c.rate_d > 0;
    GstClockTime dur = GST_BUFFER_DURATION(buf);
    if (!GST_CLOCK_TIME_IS_VALID(dur) && rate) {
      dur = gst_util_uint64_scale_int(static_cast<guint64>(frames_in) * c.rate_d, GST_SECOND,
                                      c.rate_n);
      GST_BUFFER_DURATION(buf) = dur;
    }
    if (!GST_BUFFER_PTS_IS_VALID(buf)) {
      GstClockTime pts = p->segment.start;
      if (rate) {
        if (GST_CLOCK_TIME_IS_VALID(p->old_ts) && GST_CLOCK_TIME_IS_VALID(dur))
          pts = p->old_ts + dur;
      } else if (GstClock *clock = gst_element_get_clock(p->element)) {
        GstClockTime base = gst_element_get_base_time(p->element);
        GstClockTime now = gst_clock_get_time(clock);
        pts = base < now ? now - base : 0;
        gst_object_unref(clock);
      }
      GST_BUFFER_PTS(buf) = pts;
    }
  }
  p->old_ts = GST_BUFFER_PTS(buf);
}

// Final shaping (octet split, flexible headers) and push.
GstFlowReturn push_out(ConverterState *p, GstBuffer *buf) {
  BufferPtr out(buf);
  const TensorsInfo &info = p->sent.info;
  if (p->media.kind == MediaKind::kOctet && info.format == TensorFormat::kStatic &&
      (info.size() > 1 || gst_buffer_n_memory(out.get()) > 1)) {
    MemoryPtr all(gst_buffer_get_all_memory(out.get()));
    BufferPtr split(gst_buffer_new());
    gsize off = 0;
    for (const auto &t : info.tensors) {
      buffer_append_tensor(split.get(), gst_memory_share(all.get(), off, t.byte_size()), t);
      off += t.byte_size();
    }
    gst_buffer_copy_into(split.get(), out.get(), GST_BUFFER_COPY_METADATA, 0, -1);
    out = std::move(split);
  }
  if (p->out_flexible && !p->headers_ready) {
    BufferPtr flex(gst_buffer_new());
    guint n = gst_buffer_n_memory(out.get());
    for (guint i = 0; i < n; ++i) {
      GstMemory *mem = gst_buffer_peek_memory(out.get(), i);
      const bool described = i < info.size() && info.format == TensorFormat::kStatic;
      // Octet stream without a description: the whole buffer as bytes.
      const nns::MetaHeader h = nns::flexible_header(
          described ? info[i].type : nns::TensorType::kUInt8,
          described
              ? info[i].dims
              : nns::make_dims(
                    {static_cast<uint32_t>(gst_memory_get_sizes(mem, nullptr, nullptr)), 1, 1, 1}),
          media_type_of(p->media.kind));
      gst_buffer_append_memory(flex.get(), memory_with_header(h, mem));
    }
    gst_buffer_copy_into(flex.get(), out.get(), GST_BUFFER_COPY_METADATA, 0, -1);
    out = std::move(flex);
  }
  return gst_pad_push(p->srcpad, out.release());
}

GstFlowReturn push_chunks(ConverterState *p, GstBuffer *inbuf, guint frames_in) {
  const auto &c = p->sent;
  const bool rate = c.rate_n > 0 && c.rate_d > 0;
  const std::size_t fsize = p->media.frame_size;
  GstClockTime dur = GST_BUFFER_DURATION(inbuf);
  if (GST_CLOCK_TIME_IS_VALID(dur)) dur = gst_util_uint64_scale_int(dur, p->frames_out, frames_in);
  gst_adapter_push(p->adapter, inbuf);
  const gsize out_size = static_cast<gsize>(p->frames_out) * fsize;
  GstFlowReturn ret = GST_FLOW_OK;
  while (ret == GST_FLOW_OK && gst_adapter_available(p->adapter) >= out_size) {
    guint64 pdist = 0, ddist = 0;
    GstClockTime pts = gst_adapter_prev_pts(p->adapter, &pdist);
    GstClockTime dts = gst_adapter_prev_dts(p->adapter, &ddist);
    if (frames_in > 1 && rate) {
      if (GST_CLOCK_TIME_IS_VALID(pts))
        pts += gst_util_uint64_scale(pdist * c.rate_d, GST_SECOND, c.rate_n * fsize);
      if (GST_CLOCK_TIME_IS_VALID(dts))
        dts += gst_util_uint64_scale(ddist * c.rate_d, GST_SECOND, c.rate_n * fsize);
    }
    GstBuffer *out = gst_buffer_make_writable(gst_adapter_take_buffer(p->adapter, out_size));
    GST_BUFFER_PTS(out) = pts;
    GST_BUFFER_DTS(out) = dts;
    GST_BUFFER_DURATION(out) = dur;
    ret = push_out(p, out);
  }
  return ret;
}

// Flexible tensors in: strip the headers (sharing the payload), static out.
GstBuffer *from_flexible(ConverterState *p, GstBuffer *in) {
  guint n = gst_buffer_n_memory(in);
  if (p->props_valid && n != p->props.size())
    fail(ErrorKind::kStream, "flexible buffer has " + std::to_string(n) + " tensors, " +
                                 props_string(p) + " describe " + std::to_string(p->props.size()));
  TensorsConfig cfg;
  cfg.rate_n = p->in_rate_n;
  cfg.rate_d = p->in_rate_d;
  BufferPtr out(gst_buffer_new());
  for (guint i = 0; i < n; ++i) {
    GstMemory *mem = gst_buffer_peek_memory(in, i);
    nns::MetaHeader h = memory_header(mem);
    gsize payload = gst_memory_get_sizes(mem, nullptr, nullptr) - nns::kMetaHeaderSize;
    nns::TensorInfo t = p->props_valid ? p->props[i] : h.info();
    if (payload != t.byte_size() || h.payload_size() != payload)
      fail(ErrorKind::kStream, "flexible tensor " + std::to_string(i) + " carries " +
                                   std::to_string(payload) +
                                   " bytes (header: " + h.info().to_string() + "), expected " +
                                   std::to_string(t.byte_size()) + " for " + t.to_string() +
                                   (p->props_valid ? " from " + props_string(p) : ""));
    cfg.info.tensors.push_back(t);
    buffer_append_tensor(out.get(), gst_memory_share(mem, nns::kMetaHeaderSize, payload), t);
  }
  gst_buffer_copy_into(out.get(), in, GST_BUFFER_COPY_METADATA, 0, -1);
  send_caps(p, cfg);
  return out.release();
}

// custom-code callback or converter sub-plugin.
GstBuffer *from_custom(ConverterState *p, GstBuffer *in, bool *owns_in) {
  CTensorsConfig c;
  GstBuffer *out = p->custom.func ? p->custom.func(in, p->custom.data, c.get())
                                  : p->ext->convert(in, c.get(), p->ext_priv);
  const std::string who = p->media.describe;
  if (!out) {
    // Why: the sub-plugin's error slot (python3), else its thread-local last error
    // (nns_converter_subplugin_last_error, the wire converters).
    std::string why = p->custom.func ? std::string() : subplugin_reason(p->ext_priv);
    if (why.empty() && p->ext) {
      if (auto fn = ConverterRegistry::instance().last_error_fn(p->ext)) {
        const char *m = fn();
        if (m) why = m;
      }
    }
    fail(ErrorKind::kStream, who + " returned no buffer" + (why.empty() ? "" : ": " + why));
  }
  if (out == in) *owns_in = false;  // the element's reference moved to the output
  BufferPtr guard_out(out);
  TensorsConfig cfg = from_c(c.get());
  if (cfg.rate_n < 0 || cfg.rate_d <= 0) cfg.rate_n = p->in_rate_n, cfg.rate_d = p->in_rate_d;
  if (cfg.info.format == TensorFormat::kStatic) {
    if (!cfg.info.valid() || cfg.info.tensors.empty())
      fail(ErrorKind::kStream, who + " described invalid tensors: " + cfg.info.to_string());
    try {
      check_static_buffer(out, cfg.info);
    } catch (const nns::Error &e) {
      fail(ErrorKind::kStream, who + ": " + e.what());
    }
  }
  p->headers_ready = cfg.info.format != TensorFormat::kStatic;
  send_caps(p, cfg);
  return guard_out.release();
}

}  // namespace

GstFlowReturn process_buffer(ConverterState *p, GstBuffer *buf) {
  BufferPtr in(buf);
  if (!p->configured) fail(ErrorKind::kNegotiation, "received a buffer before caps were set");
  const gsize size = gst_buffer_get_size(buf);
  const auto &m = p->media;
  guint frames_in = 1;
  GstBuffer *conv = nullptr;  // owned result of the media step
  switch (m.kind) {
    case MediaKind::kVideo: {
      VideoLayout l = buffer_video_layout(buf, m.video);
      if (size != l.size && !(gst_buffer_get_video_meta(buf) && size > l.size))
        fail(ErrorKind::kStream, "buffer has " + std::to_string(size) + " bytes, expected " +
                                     std::to_string(l.size) + " for " + m.describe);
      conv = l.contiguous() ? shell_with(buf, single_memory(buf, m.frame_size))
                            : shell_with(buf, copy_video_frame(buf, l));
      break;
    }
    case MediaKind::kAudio:
      if (size == 0 || size % m.frame_size)
        fail(ErrorKind::kStream, "buffer has " + std::to_string(size) +
                                     " bytes, expected a multiple of " +
                                     std::to_string(m.frame_size) +
                                     " (one sample of each "
                                     "channel) for " +
                                     m.describe);
      frames_in = static_cast<guint>(size / m.frame_size);
      conv = m.swap_width ? shell_with(buf, copy_swapped(buf, m.swap_width))
                          : shell_with(buf, single_memory(buf, size));
      break;
    case MediaKind::kText:
      conv = size == m.frame_size ? shell_with(buf, single_memory(buf, size))
                                  : shell_with(buf, copy_resized(buf, m.frame_size));
      break;
    case MediaKind::kOctet:
      if (m.config.info.format == TensorFormat::kStatic) {
        if (size == 0 || size % m.frame_size)
          fail(ErrorKind::kStream, "buffer has " + std::to_string(size) + " bytes, expected " +
                                       std::to_string(m.frame_size) + " (or a multiple) for " +
                                       m.config.info.to_string() + " from " + props_string(p));
        frames_in = static_cast<guint>(size / m.frame_size);
      } else if (size == 0) {
        fail(ErrorKind::kStream, "received an empty octet-stream buffer");
      }
      conv = shell_with(buf, single_memory(buf, size));
      break;
    case MediaKind::kFlexTensor:
      if (p->flex_passthrough) {
        conv = in.release();
      } else {
        conv = from_flexible(p, buf);
      }
      break;
    default: {
      bool owns = true;
      conv = from_custom(p, buf, &owns);
      if (!owns) (void)in.release();
      break;
    }
  }
  BufferPtr out(conv);
  in.reset();
  if (!p->caps_sent) send_caps(p, m.config);
  push_segment(p);
  out.reset(gst_buffer_make_writable(out.release()));
  stamp(p, out.get(), frames_in);
  if (frames_in == p->frames_out) return push_out(p, out.release());
  return push_chunks(p, out.release(), frames_in);
}

}  // namespace nns::gst
