// SPDX-License-Identifier: LGPL-2.1-only
// Internals of the Pipeline API (include/nnstreamer/nnstreamer.h): the pipeline, its named
// nodes and the handles given to the application.
//
// Locking:
// - g_mu (registry_lock()) guards the set of live pipelines and handles and each pipeline's
//   node table. API calls validate their handle under it, then take a Use (the pipeline's
//   in-flight counter) and release it before calling into GStreamer, so callbacks that run
//   synchronously (state changes) may call the API again.
// - Node::cb_mu (recursive) is held while sink callbacks run. Unregister and destroy take it,
//   so they wait for a running callback, and no callback starts after they return. A callback
//   may register or unregister sinks of its own node (same thread, recursive lock). Neither
//   holds g_mu while it waits, so a callback may call any API function meanwhile.
// - Src event callbacks run with a per-handle counter; release waits for it to drop to zero.
// - Pipeline::state_mu (recursive) is held while the state callback runs; destroy takes it.
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "api/ml_handles.h"
#include "core/tensor_info.h"
#include "nnstreamer.h"

namespace nns::capi {

GST_DEBUG_CATEGORY_EXTERN(capi_debug);

enum class NodeKind {
  kTensorSink,
  kAppSink,
  kAppSrc,
  kValve,
  kInputSelector,
  kOutputSelector,
  kCommon
};
enum class HandleKind { kSink, kSrc, kSwitch, kValve, kElement };

const char *handle_kind_name(HandleKind k);  // "sink", "src", ...
const char *node_kind_name(NodeKind k);      // "tensor_sink", ...

struct Pipeline;
struct Node;

constexpr uint32_t kPipeMagic = 0x6d6c7031;    // "mlp1"
constexpr uint32_t kHandleMagic = 0x6d6c6831;  // "mlh1"

struct Handle {
  uint32_t magic = kHandleMagic;
  HandleKind kind = HandleKind::kElement;
  Pipeline *pipe = nullptr;
  Node *node = nullptr;
  // Sink (guarded by node->cb_mu).
  ml_pipeline_sink_cb sink_cb = nullptr;
  void *sink_user = nullptr;
  bool dead = false;  // unregistered from inside its own callback; freed by the dispatcher
  // Src event callbacks (guarded by src_mu, never held while a callback runs; `src_alive` false
  // once released). A released src handle is kept (Node::retired) until the pipeline is freed,
  // since appsrc may be about to call it.
  std::mutex src_mu;
  std::condition_variable src_cv;
  ml_pipeline_src_callbacks_s src_cb{};
  void *src_user = nullptr;
  bool src_alive = true;
  int src_running = 0;
};

struct Node {
  Pipeline *pipe = nullptr;
  GstElement *element = nullptr;  // owned reference
  std::string name;
  std::string factory;  // "tensor_sink", ...
  NodeKind kind = NodeKind::kCommon;
  std::vector<Handle *> handles;  // every live handle on this node (g_mu)
  std::vector<Handle *> retired;  // released src handles, freed with the pipeline (g_mu)

  // Sink dispatch (cb_mu).
  std::recursive_mutex cb_mu;
  std::vector<Handle *> sinks;
  gulong signal_id = 0;
  std::thread::id dispatch_thread;
  bool dispatching = false;
  bool closed = false;  // close_sinks() ran: no more sinks
  bool have_format = false;
  std::atomic<bool> format_stale{true};  // set by the sink pad's notify::caps
  GstPad *caps_pad = nullptr;            // owned reference while connected
  gulong caps_id = 0;
  bool flexible = false;
  api::TensorsInfoHandle info;  // handed to callbacks
  api::TensorsDataHandle data;  // buffers point into mapped memory during a callback

  // custom-easy model or tensor_if condition this node uses (released at destroy).
  std::string custom_easy;
  std::string if_custom;
};

struct Pipeline {
  uint32_t magic = kPipeMagic;
  uint64_t id = 0;
  GstElement *bin = nullptr;
  std::map<std::string, std::unique_ptr<Node>> nodes;  // g_mu

  std::recursive_mutex state_mu;
  ml_pipeline_state_cb state_cb = nullptr;
  void *state_user = nullptr;
  std::atomic<int> state{ML_PIPELINE_STATE_UNKNOWN};
  std::atomic<bool> eos{false};

  std::mutex err_mu;
  std::string last_error;  // "<element>: <message> (<debug>)": first bus error since take_error()

  // Calls in progress that run without g_mu (destroy waits for them).
  std::mutex use_mu;
  std::condition_variable use_cv;
  int uses = 0;
  bool dying = false;

  std::string describe() const;  // "pipeline #3"
  std::string take_error();      // that error, "" if none; clears it
};

std::mutex &registry_lock();
// Live-object checks (g_mu held). Return nullptr after reporting ML_ERROR_INVALID_PARAMETER
// with a message naming `func` and what was wrong.
Pipeline *live_pipeline(ml_pipeline_h h, const char *func);
Handle *live_handle(void *h, HandleKind want, const char *func, const char *arg);
void add_handle(Handle *h);     // g_mu held
void remove_handle(Handle *h);  // g_mu held; does not free

// Marks the pipeline in use (g_mu held to start); ends on destruction.
class Use {
 public:
  explicit Use(Pipeline *p);
  ~Use();
  Use(const Use &) = delete;
  Use &operator=(const Use &) = delete;

 private:
  Pipeline *p_;
};

// Records an error (ml_error() of this thread) and returns code.
int fail(int code, const std::string &msg);
// Initialises GStreamer once; ML_ERROR_STREAMS_PIPE when it cannot be.
int ensure_gst(const char *func);

// Pipeline the current thread is dispatching a sink callback for, if any.
Pipeline *dispatching_pipeline();

// sink_src.cc: stops dispatch on a node (waits for a running callback) and frees sink handles.
void close_sinks(Node *n);
// sink_src.cc: detaches src event callbacks of a handle (waits for a running one).
void close_src(Handle *h);

// custom.cc: reference counts of the application's custom-easy models and tensor_if
// conditions, taken by pipelines that use them.
void custom_easy_ref(const std::string &name, int delta);
bool custom_easy_known(const std::string &name);
void if_custom_ref(const std::string &name, int delta);
bool if_custom_known(const std::string &name);

// TensorsInfo -> info handle contents (extended when a tensor has rank > 4).
void fill_info_handle(api::TensorsInfoHandle &h, const TensorsInfo &info);

}  // namespace nns::capi

#define NNS_CAPI extern "C" __attribute__((visibility("default")))
