// SPDX-License-Identifier: LGPL-2.1-only
// How tensor_filter hands its invoke times to the nnsprofile tracer. tensor_filter times each
// invoke once (one clock read before and after); that one figure feeds its latency /
// throughput / latency-report properties and, when the tracer is active, this probe.
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <cstdint>

namespace nns::profile {

extern std::atomic<bool> g_invoke_probe_on;

// True while an nnsprofile tracer is active in this process (one relaxed load).
inline bool invoke_probe_on() {
  return g_invoke_probe_on.load(std::memory_order_relaxed);
}

// One invoke of `dur_ns` nanoseconds by `element`. No allocation, no lock.
void note_invoke(GstElement *element, int64_t dur_ns);

}  // namespace nns::profile
