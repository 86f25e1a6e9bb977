// SPDX-License-Identifier: LGPL-2.1-only
// The element shell tensor_sparse_enc and tensor_sparse_dec share: one always sink pad and one
// always src pad (fixed caps), a `silent` property, a CAPS handler and a buffer-to-buffer chain,
// both run inside guard() so errors are posted under the element's own name.
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>

namespace nns::gst::sparse {

enum { PROP_0, PROP_SILENT };

// Installs `silent` (PROP_SILENT), the metadata and both pad templates.
void class_init(GObjectClass *gobject_class, GstElementClass *element_class, const char *longname,
                const char *description, GstStaticPadTemplate *sink, GstStaticPadTemplate *src);
void set_silent(GObject *object, guint id, const GValue *value, GParamSpec *pspec,
                std::atomic<bool> &silent);
void get_silent(GObject *object, guint id, GValue *value, GParamSpec *pspec,
                const std::atomic<bool> &silent);

// Creates and adds the two pads; `proxy_allocation` proxies allocation queries on the sink pad.
void add_pads(GstElement *element, GstStaticPadTemplate *sink, GstStaticPadTemplate *src,
              GstPadEventFunction event, GstPadChainFunction chain, bool proxy_allocation,
              GstPad **sinkpad, GstPad **srcpad);

// Sink events: CAPS is consumed, `on_caps` runs inside guard() (FALSE when it throws); every
// other event goes to the default handler.
gboolean sink_event(GstElement *element, GstPad *pad, GstEvent *event,
                    const std::function<void(GstCaps *)> &on_caps);

// Chain: takes `in`; inside guard() `convert(in, out)` fills a new buffer, which gets `in`'s
// metadata (timestamps, flags) and is pushed on `srcpad`.
GstFlowReturn chain(GstElement *element, GstPad *srcpad, GstBuffer *in,
                    const std::function<void(GstBuffer *in, GstBuffer *out)> &convert);

// Appends a new `size`-byte memory to `out`; `write` fills it.
void append_written(GstBuffer *out, std::size_t size, const std::function<void(uint8_t *)> &write);

}  // namespace nns::gst::sparse
