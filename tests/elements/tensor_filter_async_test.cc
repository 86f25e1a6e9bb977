// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter invoke-async=true: outputs dispatched by the back end (custom-easy, cpp, custom
// and C++ FilterBackend filters), from worker threads or during invoke; timestamps, EOS after
// announced outputs, flush, bad dispatches, dispatches after the element stopped, back ends
// without invoke_async, and PLAYING/NULL cycles while a worker keeps dispatching.
#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <functional>
#include <list>
#include <mutex>
#include <thread>

#include "core/filter_registry.h"
#include "core/meta_header.h"
#include "elements/filter_test_util.h"
#include "nns_filter_backend.hh"
#include "nnstreamer_plugin_api_filter.h"
#include "tensor_filter_cpp.hh"

using namespace nns::test;
using Bytes = std::vector<uint8_t>;

namespace {

constexpr GstClockTime kStep = 10 * GST_MSECOND;

// Runs jobs in order on its own thread.
class Worker {
 public:
  Worker() : t_([this] { run(); }) {}
  ~Worker() {
    {
      std::lock_guard lk(mu_);
      stop_ = true;
    }
    cv_.notify_all();
    t_.join();
  }
  void post(std::function<void()> f) {
    {
      std::lock_guard lk(mu_);
      q_.push_back(std::move(f));
    }
    cv_.notify_all();
  }
  // Waits until every posted job ran.
  bool idle(std::chrono::seconds timeout = std::chrono::seconds(20)) {
    std::unique_lock lk(mu_);
    return cv_.wait_for(lk, timeout, [this] { return q_.empty() && !busy_; });
  }

 private:
  void run() {
    std::unique_lock lk(mu_);
    for (;;) {
      cv_.wait(lk, [this] { return stop_ || !q_.empty(); });
      if (q_.empty()) return;
      auto f = std::move(q_.front());
      q_.pop_front();
      busy_ = true;
      lk.unlock();
      f();
      lk.lock();
      busy_ = false;
      cv_.notify_all();
    }
  }
  std::mutex mu_;
  std::condition_variable cv_;
  std::deque<std::function<void()>> q_;
  bool stop_ = false, busy_ = false;
  std::thread t_;
};

GstTensorsInfo uint8_4() {
  return gst_info(_NNS_UINT8, {4, 1, 1, 1});
}

// Input i: bytes {v, v+1, v+2, v+3}, PTS/DTS i * 10 ms, duration 10 ms.
GstBuffer *input(uint8_t v, int i) {
  GstBuffer *b = tensor_buffer(
      {{v, static_cast<uint8_t>(v + 1), static_cast<uint8_t>(v + 2), static_cast<uint8_t>(v + 3)}});
  GST_BUFFER_PTS(b) = GST_BUFFER_DTS(b) = i * kStep;
  GST_BUFFER_DURATION(b) = kStep;
  return b;
}

Bytes plus(const Bytes &b, int k) {
  Bytes o(b);
  for (auto &x : o) x = static_cast<uint8_t>(x + k);
  return o;
}

Bytes bytes_of(const GstTensorMemory &m) {
  auto *p = static_cast<const uint8_t *>(m.data);
  return Bytes(p, p + m.size);
}

std::string warning_text(FilterHarness &fh) {
  std::string out;
  while (GstMessage *m = gst_bus_pop_filtered(fh.bus, GST_MESSAGE_WARNING)) {
    GError *e = nullptr;
    gchar *dbg = nullptr;
    gst_message_parse_warning(m, &e, &dbg);
    out += std::string(e->message) + "\n";
    g_error_free(e);
    g_free(dbg);
    gst_message_unref(m);
  }
  return out;
}

// True when the harness got EOS (after the sticky events before it).
bool got_eos(GstHarness *h) {
  bool eos = false;
  while (GstEvent *e = gst_harness_try_pull_event(h)) {
    eos = eos || GST_EVENT_TYPE(e) == GST_EVENT_EOS;
    gst_event_unref(e);
  }
  return eos;
}

void push_inputs(FilterHarness &fh, const std::vector<uint8_t> &values) {
  for (std::size_t i = 0; i < values.size(); ++i)
    ASSERT_EQ(gst_harness_push(fh.h.get(), input(values[i], static_cast<int>(i))), GST_FLOW_OK)
        << fh.error_text();
}

// --- custom-easy: three outputs per input from a worker thread (handle extension) ---------

std::atomic<int> g_three_errors{0};

int three_per_input(void *data, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
                    GstTensorMemory *) {
  auto *w = static_cast<Worker *>(data);
  if (!prop->invoke_async) return -1;
  GstTensorFilterAsyncHandle h;
  if (nnstreamer_filter_async_capture(prop, &h) != 0) return -2;
  Bytes b = bytes_of(in[0]);
  w->post([h, b] {
    for (int k = 0; k < 3; ++k) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));  // EOS would overtake
      Bytes o = plus(b, 10 * k);
      GstTensorMemory m{o.data(), o.size()};
      if (nnstreamer_filter_async_dispatch(&h, nullptr, &m, k == 2) != 0) g_three_errors++;
    }
  });
  return 0;
}

TEST(TensorFilterAsync, CustomEasyWorkerEmitsThreePerInputBeforeEos) {
  Worker worker;
  GstTensorsInfo info = uint8_4();
  ASSERT_EQ(NNS_custom_easy_register("async_three", three_per_input, &worker, &info, &info), 0);
  {
    FilterHarness fh("tensor_filter framework=custom-easy model=async_three invoke-async=true",
                     tensors_caps("uint8", "4"));
    const std::vector<uint8_t> values = {0, 40, 80, 120};
    push_inputs(fh, values);
    // EOS is held back until the worker has ended every announced input.
    ASSERT_TRUE(gst_harness_push_event(fh.h.get(), gst_event_new_eos()));
    EXPECT_EQ(gst_harness_buffers_received(fh.h.get()), 3 * values.size());
    EXPECT_TRUE(got_eos(fh.h.get()));
    for (std::size_t i = 0; i < values.size(); ++i) {
      Bytes in = {values[i], static_cast<uint8_t>(values[i] + 1),
                  static_cast<uint8_t>(values[i] + 2), static_cast<uint8_t>(values[i] + 3)};
      for (int k = 0; k < 3; ++k) {
        GstBuffer *out = gst_harness_pull(fh.h.get());
        ASSERT_NE(out, nullptr);
        EXPECT_EQ(gst_buffer_n_memory(out), 1u);
        EXPECT_EQ(memory_bytes(out, 0), plus(in, 10 * k)) << "input " << i << " output " << k;
        EXPECT_EQ(GST_BUFFER_PTS(out), i * kStep);
        EXPECT_EQ(GST_BUFFER_DTS(out), i * kStep);
        EXPECT_EQ(GST_BUFFER_DURATION(out), kStep);
        gst_buffer_unref(out);
      }
    }
    GstCaps *caps = gst_pad_get_current_caps(fh.h->sinkpad);
    ASSERT_NE(caps, nullptr);
    GstStructure *st = gst_caps_get_structure(caps, 0);
    EXPECT_STREQ(gst_structure_get_string(st, "format"), "static");
    EXPECT_STREQ(gst_structure_get_string(st, "types"), "uint8");
    gst_caps_unref(caps);
    EXPECT_EQ(fh.error_text(), "");
  }
  EXPECT_EQ(g_three_errors.load(), 0);
  EXPECT_EQ(NNS_custom_easy_unregister("async_three"), 0);
}

// --- custom-easy: NNStreamer's call during invoke, zero outputs for some inputs -------------

int even_twice(void *, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
               GstTensorMemory *out) {
  std::memset(out[0].data, 0xEE, out[0].size);  // written anyway: must not become a buffer
  auto *p = static_cast<const uint8_t *>(in[0].data);
  if (p[0] % 2) return 0;  // odd input: no output at all
  for (int k = 1; k <= 2; ++k) {
    GstTensorMemory m{std::malloc(in[0].size), in[0].size};  // released by tensor_filter
    for (std::size_t i = 0; i < m.size; ++i) static_cast<uint8_t *>(m.data)[i] = p[i] + k;
    int rc =
        nnstreamer_filter_dispatch_output_async(const_cast<GstTensorFilterProperties *>(prop), &m);
    if (rc != 0) return rc;
    if (m.data) return -100;  // handed over: the call clears it
  }
  return 1;  // NNStreamer's async filters drop the regular output; ignored here anyway
}

TEST(TensorFilterAsync, UpstreamDispatchDuringInvokeZeroOrTwoOutputs) {
  GstTensorsInfo info = uint8_4();
  ASSERT_EQ(NNS_custom_easy_register("async_even", even_twice, nullptr, &info, &info), 0);
  {
    FilterHarness fh("tensor_filter framework=custom-easy model=async_even invoke-async=true",
                     tensors_caps("uint8", "4"));
    // Downstream asking upstream about caps while it handles an output (as elements do on
    // reconfigure): outputs dispatched during invoke must reach it without the filter's
    // locks held, else this would deadlock.
    GstPad *src = gst_element_get_static_pad(fh.element(), "src");
    std::atomic<int> queried{0};
    gst_pad_add_probe(
        src, GST_PAD_PROBE_TYPE_BUFFER,
        [](GstPad *pad, GstPadProbeInfo *, gpointer data) {
          if (GstCaps *c = gst_pad_query_caps(pad, nullptr)) gst_caps_unref(c);
          ++*static_cast<std::atomic<int> *>(data);
          return GST_PAD_PROBE_OK;
        },
        &queried, nullptr);
    gst_object_unref(src);
    push_inputs(fh, {2, 3, 5, 8});
    EXPECT_EQ(queried.load(), 4);
    ASSERT_EQ(gst_harness_buffers_received(fh.h.get()), 4u);
    const std::vector<std::pair<uint8_t, int>> expect = {{2, 0}, {8, 3}};  // value, input index
    for (auto [v, i] : expect)
      for (int k = 1; k <= 2; ++k) {
        GstBuffer *out = gst_harness_pull(fh.h.get());
        ASSERT_NE(out, nullptr);
        Bytes want = {static_cast<uint8_t>(v + k), static_cast<uint8_t>(v + 1 + k),
                      static_cast<uint8_t>(v + 2 + k), static_cast<uint8_t>(v + 3 + k)};
        EXPECT_EQ(memory_bytes(out, 0), want);
        EXPECT_EQ(GST_BUFFER_PTS(out), static_cast<GstClockTime>(i) * kStep);
        gst_buffer_unref(out);
      }
    EXPECT_EQ(fh.error_text(), "");
  }
  EXPECT_EQ(NNS_custom_easy_unregister("async_even"), 0);
}

// --- custom-easy with invoke-dynamic: output_meta set per dispatch (llamacpp style) ---------

int llama_style(void *, const GstTensorFilterProperties *cprop, const GstTensorMemory *in,
                GstTensorMemory *) {
  auto *prop = const_cast<GstTensorFilterProperties *>(cprop);
  for (int round = 0; round < 2; ++round) {
    GstTensorMemory out[3];
    prop->output_meta.num_tensors = 3;
    prop->output_meta.format = _NNS_TENSOR_FORMAT_FLEXIBLE;
    for (unsigned i = 0; i < 3; ++i) {
      GstTensorInfo &t = prop->output_meta.info[i];
      std::memset(t.dimension, 0, sizeof t.dimension);
      t.type = _NNS_UINT8;
      t.dimension[0] = static_cast<uint32_t>(in[0].size + i);
      if (round == 1 && i == 1) t.type = _NNS_END;  // invalid: this output set is refused
      out[i].size = in[0].size + i;
      out[i].data = std::calloc(1, out[i].size);
      std::memcpy(out[i].data, in[0].data, in[0].size);
    }
    nnstreamer_filter_dispatch_output_async(prop, out);
  }
  return 0;
}

TEST(TensorFilterAsync, FlexibleOutputsTakeOutputMetaAndBadOnesAreDroppedWithWarning) {
  GstTensorsInfo info = uint8_4();
  ASSERT_EQ(NNS_custom_easy_register("async_llama", llama_style, nullptr, &info, &info), 0);
  {
    FilterHarness fh(
        "tensor_filter framework=custom-easy model=async_llama invoke-dynamic=true "
        "invoke-async=true",
        tensors_caps("uint8", "4"));
    gst_harness_set_sink_caps_str(fh.h.get(), "other/tensors,format=flexible");
    push_inputs(fh, {7});
    ASSERT_EQ(gst_harness_buffers_received(fh.h.get()), 1u);
    GstBuffer *out = gst_harness_pull(fh.h.get());
    ASSERT_EQ(gst_buffer_n_memory(out), 3u);
    for (guint i = 0; i < 3; ++i) {
      Bytes m = memory_bytes(out, i);
      ASSERT_EQ(m.size(), nns::kMetaHeaderSize + 4 + i);
      nns::MetaHeader h = nns::parse_meta_header(m.data(), m.size());
      EXPECT_EQ(h.type, nns::TensorType::kUInt8);
      EXPECT_EQ(h.dims[0], 4 + i);
      EXPECT_EQ(m[nns::kMetaHeaderSize], 7);
    }
    gst_buffer_unref(out);
    std::string w = warning_text(fh);
    EXPECT_NE(w.find("invoke-async: output not pushed"), std::string::npos) << w;
    EXPECT_EQ(fh.error_text(), "");
  }
  EXPECT_EQ(NNS_custom_easy_unregister("async_llama"), 0);
}

// --- handles: bad sizes, flush, use after the element went to NULL --------------------------

GstTensorFilterAsyncHandle g_handle;

int capture_only(void *, const GstTensorFilterProperties *prop, const GstTensorMemory *,
                 GstTensorMemory *) {
  return nnstreamer_filter_async_capture(prop, &g_handle);
}

TEST(TensorFilterAsync, BadDispatchIsRefusedWithWarningAndHandleIsHarmlessAfterNull) {
  GstTensorsInfo info = uint8_4();
  ASSERT_EQ(NNS_custom_easy_register("async_capture", capture_only, nullptr, &info, &info), 0);
  Bytes three = {1, 2, 3}, four = {9, 8, 7, 6};
  GstTensorMemory bad{three.data(), three.size()}, good{four.data(), four.size()};
  {
    FilterHarness fh("tensor_filter framework=custom-easy model=async_capture invoke-async=true",
                     tensors_caps("uint8", "4"));
    push_inputs(fh, {1});
    EXPECT_EQ(nnstreamer_filter_async_dispatch(&g_handle, nullptr, &bad, 0), -EINVAL);
    std::string w = warning_text(fh);
    EXPECT_NE(w.find("dispatched tensor 0 has 3 bytes, expected 4 for uint8 4"), std::string::npos)
        << w;
    EXPECT_EQ(nnstreamer_filter_async_dispatch(&g_handle, nullptr, &good, 1), 0);
    ASSERT_EQ(gst_harness_buffers_received(fh.h.get()), 1u);
    GstBuffer *out = gst_harness_pull(fh.h.get());
    EXPECT_EQ(memory_bytes(out, 0), four);
    gst_buffer_unref(out);
  }
  // The element is gone (NULL, finalized): the handle is still safe to use.
  EXPECT_EQ(nnstreamer_filter_async_dispatch(&g_handle, nullptr, &good, 0), -ESHUTDOWN);
  EXPECT_EQ(nnstreamer_filter_async_dispatch(&g_handle, nullptr, nullptr, 1), -ESHUTDOWN);
  // Not captured during an invoke: refused.
  GstTensorFilterAsyncHandle junk{};
  EXPECT_EQ(nnstreamer_filter_async_dispatch(&junk, nullptr, &good, 0), -EINVAL);
  EXPECT_EQ(NNS_custom_easy_unregister("async_capture"), 0);
}

TEST(TensorFilterAsync, FlushDropsOutputsOfEarlierInputs) {
  GstTensorsInfo info = uint8_4();
  ASSERT_EQ(NNS_custom_easy_register("async_flush", capture_only, nullptr, &info, &info), 0);
  Bytes four = {9, 8, 7, 6};
  GstTensorMemory good{four.data(), four.size()};
  {
    FilterHarness fh("tensor_filter framework=custom-easy model=async_flush invoke-async=true",
                     tensors_caps("uint8", "4"));
    push_inputs(fh, {1});
    ASSERT_TRUE(gst_harness_push_event(fh.h.get(), gst_event_new_flush_start()));
    ASSERT_TRUE(gst_harness_push_event(fh.h.get(), gst_event_new_flush_stop(TRUE)));
    EXPECT_EQ(nnstreamer_filter_async_dispatch(&g_handle, nullptr, &good, 1), -ECANCELED);
    EXPECT_EQ(gst_harness_buffers_received(fh.h.get()), 0u);
  }
  EXPECT_EQ(NNS_custom_easy_unregister("async_flush"), 0);
}

// --- framework=custom (.so) and framework=cpp ----------------------------------------------

TEST(TensorFilterAsync, CustomSoDispatchesAndBlocksAreReleasedWithDestroyNotify) {
  std::string so = filter_dir() + "/libcustom_async.so";
  FilterHarness fh("tensor_filter framework=custom invoke-async=true model=" + so,
                   tensors_caps("uint8", "4"));
  push_inputs(fh, {10, 20, 30});
  ASSERT_EQ(gst_harness_buffers_received(fh.h.get()), 6u) << fh.error_text();
  for (int i = 0; i < 3; ++i)
    for (int k = 1; k <= 2; ++k) {
      GstBuffer *out = gst_harness_pull(fh.h.get());
      uint8_t v = static_cast<uint8_t>(10 * (i + 1) + k);
      EXPECT_EQ(memory_bytes(out, 0),
                (Bytes{v, static_cast<uint8_t>(v + 1), static_cast<uint8_t>(v + 2),
                       static_cast<uint8_t>(v + 3)}));
      EXPECT_EQ(GST_BUFFER_PTS(out), static_cast<GstClockTime>(i) * kStep);
      gst_buffer_unref(out);
    }
  void *h = dlopen(so.c_str(), RTLD_NOW | RTLD_NOLOAD);  // still open: the filter runs
  ASSERT_NE(h, nullptr);
  auto released = reinterpret_cast<int (*)()>(dlsym(h, "custom_async_released"));
  ASSERT_NE(released, nullptr);
  EXPECT_EQ(released(), 6);
  dlclose(h);
}

class CppTwice : public tensor_filter_cpp {
 public:
  CppTwice() : tensor_filter_cpp("async_cpp_twice") {}
  int getInputDim(GstTensorsInfo *i) override { return set(i); }
  int getOutputDim(GstTensorsInfo *i) override { return set(i); }
  int setInputDim(const GstTensorsInfo *, GstTensorsInfo *) override { return -EINVAL; }
  bool isAllocatedBeforeInvoke() override { return true; }
  int invoke(const GstTensorMemory *in, GstTensorMemory *) override {
    for (int k = 0; k < 2; ++k) {
      GstTensorMemory m{std::malloc(in[0].size), in[0].size};
      for (std::size_t i = 0; i < m.size; ++i)
        static_cast<uint8_t *>(m.data)[i] = static_cast<const uint8_t *>(in[0].data)[i] * (k + 2);
      int rc = nnstreamer_filter_dispatch_output_async(
          const_cast<GstTensorFilterProperties *>(prop), &m);
      if (rc != 0) return rc;
    }
    return 0;
  }

 private:
  static int set(GstTensorsInfo *i) {
    *i = uint8_4();
    return 0;
  }
};

TEST(TensorFilterAsync, CppFilterDispatchesThroughProp) {
  CppTwice f;
  ASSERT_EQ(f._register(), 0);
  {
    FilterHarness fh("tensor_filter framework=cpp model=async_cpp_twice invoke-async=true",
                     tensors_caps("uint8", "4"));
    push_inputs(fh, {3});
    ASSERT_EQ(gst_harness_buffers_received(fh.h.get()), 2u) << fh.error_text();
    for (int k = 0; k < 2; ++k) {
      GstBuffer *out = gst_harness_pull(fh.h.get());
      uint8_t m = static_cast<uint8_t>(k + 2);
      EXPECT_EQ(memory_bytes(out, 0),
                (Bytes{static_cast<uint8_t>(3 * m), static_cast<uint8_t>(4 * m),
                       static_cast<uint8_t>(5 * m), static_cast<uint8_t>(6 * m)}));
      gst_buffer_unref(out);
    }
  }
  EXPECT_EQ(f._unregister(), 0);
}

// --- C++ FilterBackend: emitters kept by a worker that keeps dispatching --------------------

// Keeps every queued job emitting (one output per round, 1 ms apart) until it has emitted
// `per_job` outputs (then finish()) or its filter is gone (-ESHUTDOWN).
class Spinner {
 public:
  Spinner() : t_([this] { run(); }) {}
  ~Spinner() {
    stop_ = true;
    t_.join();
  }
  void add(const nns::AsyncEmitter &e, Bytes data) {
    std::lock_guard lk(mu_);
    jobs_.push_back(Job{e, std::move(data), 0});
  }
  std::size_t jobs() {
    std::lock_guard lk(mu_);
    return jobs_.size();
  }
  bool wait(const std::function<bool()> &cond, double seconds = 20) {
    auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (!cond()) {
      if (std::chrono::steady_clock::now() > end) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
  }
  std::atomic<int> per_job{3};
  std::atomic<int> ok{0}, shutdown{0}, cancelled{0}, other{0};

 private:
  struct Job {
    nns::AsyncEmitter e;
    Bytes data;
    int emitted;
  };
  void run() {
    while (!stop_) {
      {
        std::lock_guard lk(mu_);
        for (auto it = jobs_.begin(); it != jobs_.end();) {
          Bytes o = plus(it->data, it->emitted);
          GstTensorMemory m{o.data(), o.size()};
          bool last = it->emitted + 1 >= per_job;
          int rc = it->e.emit(&m, 1, nullptr, last);
          it->emitted++;
          if (rc == 0)
            ok++;
          else if (rc == -ESHUTDOWN)
            shutdown++;
          else if (rc == -ECANCELED)  // pushed while the pads were flushing (stopping)
            cancelled++;
          else
            other++;
          if (rc != 0 || last)
            it = jobs_.erase(it);
          else
            ++it;
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  std::mutex mu_;
  std::list<Job> jobs_;
  std::atomic<bool> stop_{false};
  std::thread t_;
};

Spinner *g_spinner = nullptr;

// uint8 4 in and out, output = input.
class EchoBase : public nns::FilterBackend {
 public:
  explicit EchoBase(const nns_filter_props &p) : async_(p.invoke_async != 0) {}
  bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) override {
    in = nns_tensors_desc{};
    in.num_tensors = 1;
    in.tensors[0].type = _NNS_UINT8;
    in.tensors[0].dims[0] = 4;
    out = in;
    return true;
  }
  void invoke(const GstTensorMemory *in, uint32_t, GstTensorMemory *out, uint32_t) override {
    std::memcpy(out[0].data, in[0].data, in[0].size);
  }

 protected:
  bool async_;
};

// "syncbe": no invoke_async.
class SyncBackend : public EchoBase {
 public:
  using EchoBase::EchoBase;
};

// "asyncbe": invoke_async hands the input to g_spinner (at most 8 jobs queued; beyond that it
// emits once during the call and is done).
class AsyncBackend : public EchoBase {
 public:
  using EchoBase::EchoBase;
  bool invoke_async(const nns_tensors_desc &in_info, const GstTensorMemory *in, uint32_t num_in,
                    const nns::AsyncEmitter &out) override {
    if (!async_) throw nns::FilterError("props.invoke_async was not set");
    if (num_in != 1 || in_info.num_tensors != 1 || in_info.tensors[0].dims[0] != 4)
      throw nns::FilterError("unexpected input description");
    Bytes b = bytes_of(in[0]);
    if (g_spinner && g_spinner->jobs() < 8) {
      g_spinner->add(out, b);
      return true;  // outputs follow
    }
    GstTensorMemory m{b.data(), b.size()};
    if (out.emit(&m, 1) != 0) throw nns::FilterError(out.error());
    return false;
  }
};

struct RegisterBackends {
  RegisterBackends() {
    static const nns_filter_backend_i a = nns::FilterBackendAdapter<AsyncBackend>::make(
        "asyncbe", NNS_FILTER_FLAG_RUN_WITHOUT_MODEL, nullptr);
    static const nns_filter_backend_i s = nns::FilterBackendAdapter<SyncBackend>::make(
        "syncbe", NNS_FILTER_FLAG_RUN_WITHOUT_MODEL, nullptr);
    nns::FilterRegistry::get().add_builtin(&a);
    nns::FilterRegistry::get().add_builtin(&s);
  }
} g_register;

TEST(TensorFilterAsync, FilterBackendEmitterFromWorkerHoldsEosUntilFinished) {
  static_assert(nns::FilterBackendAdapter<AsyncBackend>::kAsync);
  Spinner spinner;
  spinner.per_job = 3;
  g_spinner = &spinner;
  {
    FilterHarness fh("tensor_filter framework=asyncbe invoke-async=true",
                     tensors_caps("uint8", "4"));
    push_inputs(fh, {0, 100});
    ASSERT_TRUE(gst_harness_push_event(fh.h.get(), gst_event_new_eos()));
    EXPECT_EQ(gst_harness_buffers_received(fh.h.get()), 6u);
    EXPECT_TRUE(got_eos(fh.h.get()));
    // One spinner round emits for every job: outputs of the two inputs interleave.
    std::vector<Bytes> got;
    while (GstBuffer *out = gst_harness_try_pull(fh.h.get())) {
      got.push_back(memory_bytes(out, 0));
      uint8_t first = got.back()[0];
      EXPECT_EQ(GST_BUFFER_PTS(out), first >= 100 ? kStep : 0) << int(first);
      gst_buffer_unref(out);
    }
    std::sort(got.begin(), got.end(),
              [](const Bytes &a, const Bytes &b) { return a.at(0) < b.at(0); });
    EXPECT_EQ(got, (std::vector<Bytes>{{0, 1, 2, 3},
                                       {1, 2, 3, 4},
                                       {2, 3, 4, 5},
                                       {100, 101, 102, 103},
                                       {101, 102, 103, 104},
                                       {102, 103, 104, 105}}));
  }
  g_spinner = nullptr;
  EXPECT_EQ(spinner.other.load(), 0);
  EXPECT_EQ(spinner.cancelled.load(), 0);
}

TEST(TensorFilterAsync, BackendWithoutInvokeAsyncFallsBackWithWarning) {
  static_assert(!nns::FilterBackendAdapter<SyncBackend>::kAsync);
  // The warning comes when the element starts: watch the bus before (FilterHarness attaches
  // its bus after the harness started the element).
  GstElement *e = gst_parse_launch("tensor_filter framework=syncbe invoke-async=true", nullptr);
  GstBus *bus = gst_bus_new();
  gst_element_set_bus(e, bus);
  HarnessPtr h(gst_harness_new_with_element(e, "sink", "src"));
  gst_object_unref(e);
  gst_harness_set_src_caps_str(h.get(), tensors_caps("uint8", "4").c_str());
  for (uint8_t v : {5, 6}) ASSERT_EQ(gst_harness_push(h.get(), input(v, 0)), GST_FLOW_OK);
  EXPECT_EQ(gst_harness_buffers_received(h.get()), 2u);  // one output per input
  GstBuffer *out = gst_harness_pull(h.get());
  EXPECT_EQ(memory_bytes(out, 0), (Bytes{5, 6, 7, 8}));
  gst_buffer_unref(out);
  gboolean async = FALSE;
  g_object_get(h->element, "invoke-async", &async, nullptr);
  EXPECT_TRUE(async);
  std::string w;
  while (GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_WARNING)) {
    GError *err = nullptr;
    gst_message_parse_warning(m, &err, nullptr);
    w += err->message;
    g_error_free(err);
    gst_message_unref(m);
  }
  GstMessage *error = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
  EXPECT_EQ(error, nullptr);
  if (error) gst_message_unref(error);
  gst_bus_set_flushing(bus, TRUE);
  h.reset();
  gst_object_unref(bus);
  EXPECT_NE(w.find("invoke-async=true, but framework 'syncbe' does not support asynchronous "
                   "invoke (no invoke_async); invoking synchronously, one output per input"),
            std::string::npos)
      << w;
}

TEST(TensorFilterAsync, OutputCombinationIsRefused) {
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4"), 1) +
                        "tensor_filter framework=asyncbe invoke-async=true "
                        "output-combination=i0,o0 ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("output-combination='i0,o0' cannot be used with "
                              "invoke-async=true"),
            std::string::npos)
      << r.error_text;
}

// PLAYING <-> NULL while the spinner keeps dispatching into every filter it ever saw.
TEST(TensorFilterAsync, PlayingNullCyclesWhileWorkerDispatches) {
  Spinner spinner;
  spinner.per_job = 1 << 30;  // jobs outlive their pipeline run
  g_spinner = &spinner;
  GstElement *pipe = gst_parse_launch((fake_source(4, tensors_caps("uint8", "4"), -1) +
                                       "tensor_filter framework=asyncbe invoke-async=true ! "
                                       "fakesink sync=false")
                                          .c_str(),
                                      nullptr);
  ASSERT_NE(pipe, nullptr);
  for (int cycle = 0; cycle < 5; ++cycle) {
    int before = spinner.ok.load();
    ASSERT_NE(gst_element_set_state(pipe, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
    EXPECT_TRUE(spinner.wait([&] { return spinner.ok.load() >= before + 20; })) << cycle;
    ASSERT_EQ(gst_element_set_state(pipe, GST_STATE_NULL), GST_STATE_CHANGE_SUCCESS);
  }
  // Every job left belongs to a stopped filter: each gets -ESHUTDOWN once and is dropped.
  EXPECT_TRUE(spinner.wait([&] { return spinner.jobs() == 0; }));
  EXPECT_GE(spinner.shutdown.load(), 5);
  EXPECT_EQ(spinner.other.load(), 0);
  gst_object_unref(pipe);
  g_spinner = nullptr;
}

}  // namespace
