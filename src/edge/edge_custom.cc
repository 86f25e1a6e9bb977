// SPDX-License-Identifier: LGPL-2.1-only
// connect-type CUSTOM, driven as nnstreamer-edge drives it (docs/edge-custom.md): the library
// named by custom-lib is dlopen()ed, nns_edge_custom_get_instance() gives its callback table
// (custom/nns_edge_abi.h), and we call it in upstream's order:
//   create -> set_info(HOST, PORT, DEST_HOST, DEST_PORT, TOPIC) -> set_event_cb -> start
//   publisher:  set_info(CAPS, "@edge_sink_caps@<caps>") on caps; per buffer is_connected,
//               then send_data (a data handle over the mapped memories, valid during the call)
//   subscriber: is_connected, connect (unless already connected); NEW_DATA_RECEIVED events
//               become buffers, CONNECTION_CLOSED ends the stream
//   stop -> close -> dlclose.
// Data and event handles are those of our libnnstreamer-edge.so.0.2.6 (custom/edge_c_api.cc),
// dlopen()ed before the first custom library (so the library's NEEDED on that SONAME binds to
// it) and called through dlsym: nothing else in the project depends on it.
#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <type_traits>
#include <vector>

#include "core/error.h"
#include "edge/custom/nns_edge_abi.h"
#include "edge/edge_node.h"

namespace nns::edge {

namespace {

using GetInstance = const nns_edge_custom_s *(*)();

// The functions of libnnstreamer-edge we call ourselves.
struct CApi {
  decltype(&nns_edge_data_create) data_create;
  decltype(&nns_edge_data_destroy) data_destroy;
  decltype(&nns_edge_data_add) data_add;
  decltype(&nns_edge_data_set_info) data_set_info;
  decltype(&nns_edge_data_is_valid) data_is_valid;
  decltype(&nns_edge_data_get_count) data_get_count;
  decltype(&nns_edge_data_get) data_get;
  decltype(&nns_edge_data_serialize_meta) data_serialize_meta;
  decltype(&nns_edge_event_get_type) event_get_type;
  decltype(&nns_edge_event_get_data) event_get_data;
};

// Loads libnnstreamer-edge.so.0.2.6 once (kept for the process): $NNS_EDGE_CAPI_LIB, the
// installed one, the build tree's, then the loader's search path.
const CApi &capi() {
  static std::mutex m;
  static std::unique_ptr<CApi> api;
  static std::string error;
  std::lock_guard<std::mutex> l(m);
  if (api) return *api;
  if (!error.empty()) fail(ErrorKind::kNotFound, error);
  std::vector<std::string> tried;
  if (const char *env = std::getenv("NNS_EDGE_CAPI_LIB"); env && *env) tried.push_back(env);
  for (const char *p :
       {NNS_EDGE_CAPI_INSTALLED, NNS_EDGE_CAPI_BUILT, "libnnstreamer-edge.so.0.2.6"})
    tried.push_back(p);
  void *dl = nullptr;
  std::string why;
  for (const auto &p : tried) {
    dl = dlopen(p.c_str(), RTLD_NOW | RTLD_GLOBAL);
    if (dl) break;
    const char *e = dlerror();
    why += "; " + p + ": " + (e ? e : "?");
  }
  auto out = std::make_unique<CApi>();
  const char *missing = nullptr;
  auto sym = [&](auto *dst, const char *name) {
    if (!dl) return;
    *dst = reinterpret_cast<std::remove_pointer_t<decltype(dst)>>(dlsym(dl, name));
    if (!*dst && !missing) missing = name;
  };
  sym(&out->data_create, "nns_edge_data_create");
  sym(&out->data_destroy, "nns_edge_data_destroy");
  sym(&out->data_add, "nns_edge_data_add");
  sym(&out->data_set_info, "nns_edge_data_set_info");
  sym(&out->data_is_valid, "nns_edge_data_is_valid");
  sym(&out->data_get_count, "nns_edge_data_get_count");
  sym(&out->data_get, "nns_edge_data_get");
  sym(&out->data_serialize_meta, "nns_edge_data_serialize_meta");
  sym(&out->event_get_type, "nns_edge_event_get_type");
  sym(&out->event_get_data, "nns_edge_event_get_data");
  if (!dl || missing) {
    error =
        "connect-type CUSTOM: cannot load libnnstreamer-edge.so.0.2.6 (nnstreamer-edge's "
        "data API the custom libraries call): " +
        (dl ? std::string("it has no ") + missing : why.substr(2));
    fail(ErrorKind::kNotFound, error);
  }
  api = std::move(out);
  return *api;
}

// The loaded library and its instance; closes both on destruction.
class CustomLib {
 public:
  explicit CustomLib(const std::string &path) : path_(path) {
    if (path.empty())
      fail(ErrorKind::kSettings,
           "connect-type CUSTOM needs the custom-lib property (the connection library)");
    capi();  // first: the library's NEEDED libnnstreamer-edge.so.0.2.6 binds to ours
    dl_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!dl_) {
      const char *e = dlerror();
      fail(ErrorKind::kNotFound,
           "cannot load custom-lib '" + path + "': " + (e ? e : "unknown dlopen error"));
    }
    auto get = reinterpret_cast<GetInstance>(dlsym(dl_, "nns_edge_custom_get_instance"));
    if (!get) {
      dlclose(dl_);
      fail(ErrorKind::kNotFound, "custom-lib '" + path +
                                     "' has no symbol nns_edge_custom_get_instance (not an "
                                     "nnstreamer-edge custom connection library)");
    }
    c_ = get();
    const char *missing = nullptr;
    if (!c_) missing = "nns_edge_custom_get_instance() returned NULL";
#define NNS_REQUIRE_CB(f) else if (!c_->f) missing = #f " is NULL";
    NNS_REQUIRE_CB(nns_edge_custom_create)
    NNS_REQUIRE_CB(nns_edge_custom_close)
    NNS_REQUIRE_CB(nns_edge_custom_start)
    NNS_REQUIRE_CB(nns_edge_custom_stop)
    NNS_REQUIRE_CB(nns_edge_custom_connect)
    NNS_REQUIRE_CB(nns_edge_custom_is_connected)
    NNS_REQUIRE_CB(nns_edge_custom_set_event_cb)
    NNS_REQUIRE_CB(nns_edge_custom_send_data)
#undef NNS_REQUIRE_CB
    if (missing) {
      dlclose(dl_);
      fail(ErrorKind::kNotFound, "custom-lib '" + path + "': " + missing);
    }
    const int rc = c_->nns_edge_custom_create(&priv_);
    if (rc != NNS_EDGE_ERROR_NONE) {
      dlclose(dl_);
      fail(ErrorKind::kLibrary,
           "custom-lib '" + path + "': nns_edge_custom_create failed (" + std::to_string(rc) + ")");
    }
  }
  ~CustomLib() {
    c_->nns_edge_custom_close(priv_);
    dlclose(dl_);
  }
  CustomLib(const CustomLib &) = delete;
  CustomLib &operator=(const CustomLib &) = delete;

  const nns_edge_custom_s *c() const {
    return c_;
  }
  void *priv() const {
    return priv_;
  }
  const std::string &path() const {
    return path_;
  }
  std::string describe() const {
    const char *d =
        c_->nns_edge_custom_get_description ? c_->nns_edge_custom_get_description() : nullptr;
    return "custom-lib '" + path_ + "'" + (d ? std::string(" (") + d + ")" : "");
  }
  // Errors are ignored as upstream does (a library need not know every key).
  void set_info(const char *key, const std::string &value) {
    if (c_->nns_edge_custom_set_info && !value.empty())
      c_->nns_edge_custom_set_info(priv_, key, value.c_str());
  }
  void call(int (*f)(void *), const char *what) {
    const int rc = f(priv_);
    if (rc != NNS_EDGE_ERROR_NONE)
      fail(ErrorKind::kLibrary, describe() + ": " + what + " failed (" + std::to_string(rc) + ")");
  }

 private:
  std::string path_;
  void *dl_ = nullptr;
  const nns_edge_custom_s *c_ = nullptr;
  void *priv_ = nullptr;
};

void pass_settings(CustomLib &lib, const NodeOptions &o, bool own_address) {
  if (own_address) {
    lib.set_info("HOST", o.host);
    if (o.port) lib.set_info("PORT", std::to_string(o.port));
  }
  lib.set_info("DEST_HOST", o.dest_host);
  if (o.dest_port) lib.set_info("DEST_PORT", std::to_string(o.dest_port));
  lib.set_info("TOPIC", o.topic);
}

class CustomPublisher final : public ServerNode {
 public:
  CustomPublisher(const NodeOptions &o, NodeCallbacks cb) : o_(o), cb_(std::move(cb)) {}
  ~CustomPublisher() override { stop(); }

  void start() override {
    lib_ = std::make_unique<CustomLib>(o_.custom_lib);
    pass_settings(*lib_, o_, true);
    if (lib_->c()->nns_edge_custom_set_event_cb(lib_->priv(), &CustomPublisher::on_event, this) !=
        NNS_EDGE_ERROR_NONE)
      fail(ErrorKind::kLibrary, lib_->describe() + ": nns_edge_custom_set_event_cb failed");
    lib_->call(lib_->c()->nns_edge_custom_start, "nns_edge_custom_start");
    started_ = true;
  }
  uint16_t port() const override { return o_.port; }
  bool send_to(int64_t, const OutFrame &f, std::string *why) override {
    if (broadcast(f)) return true;
    if (why) *why = "not sent through the custom connection";
    return false;
  }
  std::size_t broadcast(const OutFrame &f) override {
    std::lock_guard<std::mutex> l(m_);
    if (!started_) return 0;
    if (const std::string caps = cb_.caps ? cb_.caps() : std::string(); caps != sent_caps_) {
      lib_->set_info("CAPS", caps);
      sent_caps_ = caps;
    }
    if (lib_->c()->nns_edge_custom_is_connected(lib_->priv()) != NNS_EDGE_ERROR_NONE) return 0;
    nns_edge_data_h d = nullptr;
    if (capi().data_create(&d) != NNS_EDGE_ERROR_NONE) return 0;
    bool ok = true;
    for (const auto &m : f.mems)
      ok = ok &&
           capi().data_add(d, const_cast<void *>(m.data), m.size, nullptr) == NNS_EDGE_ERROR_NONE;
    for (const auto &[k, v] : f.meta.items()) capi().data_set_info(d, k.c_str(), v.c_str());
    ok = ok && lib_->c()->nns_edge_custom_send_data(lib_->priv(), d) == NNS_EDGE_ERROR_NONE;
    capi().data_destroy(d);
    return ok ? 1 : 0;
  }
  std::size_t client_count() const override {
    std::lock_guard<std::mutex> l(m_);
    return started_ && lib_->c()->nns_edge_custom_is_connected(lib_->priv()) == NNS_EDGE_ERROR_NONE
               ? 1
               : 0;
  }
  void stop() override {
    std::lock_guard<std::mutex> l(m_);
    if (started_) lib_->c()->nns_edge_custom_stop(lib_->priv());
    started_ = false;
    lib_.reset();
  }

 private:
  // A library may report CONNECTION_COMPLETED (a peer is there): wakes wait-connection.
  static int on_event(nns_edge_event_h e, void *self) {
    auto *me = static_cast<CustomPublisher *>(self);
    nns_edge_event_e type = NNS_EDGE_EVENT_UNKNOWN;
    if (capi().event_get_type(e, &type) == NNS_EDGE_ERROR_NONE &&
        type == NNS_EDGE_EVENT_CONNECTION_COMPLETED && me->cb_.on_connected) {
      try {
        me->cb_.on_connected(0, me->o_.custom_lib);
      } catch (...) {
      }
    }
    return NNS_EDGE_ERROR_NONE;
  }

  NodeOptions o_;
  NodeCallbacks cb_;
  mutable std::mutex m_;
  std::unique_ptr<CustomLib> lib_;
  bool started_ = false;
  std::string sent_caps_;
};

class CustomSubscriber final : public ClientNode {
 public:
  CustomSubscriber(const NodeOptions &o, NodeCallbacks cb) : o_(o), cb_(std::move(cb)) {}
  ~CustomSubscriber() override { disconnect(); }

  void connect() override {
    disconnect();
    lib_ = std::make_unique<CustomLib>(o_.custom_lib);
    pass_settings(*lib_, o_, false);
    if (lib_->c()->nns_edge_custom_set_event_cb(lib_->priv(), &CustomSubscriber::on_event, this) !=
        NNS_EDGE_ERROR_NONE)
      fail(ErrorKind::kLibrary, lib_->describe() + ": nns_edge_custom_set_event_cb failed");
    lib_->call(lib_->c()->nns_edge_custom_start, "nns_edge_custom_start");
    started_ = true;
    if (lib_->c()->nns_edge_custom_is_connected(lib_->priv()) != NNS_EDGE_ERROR_NONE)
      lib_->call(lib_->c()->nns_edge_custom_connect, "nns_edge_custom_connect");
  }
  bool connected() const override {
    return lib_ && lib_->c()->nns_edge_custom_is_connected(lib_->priv()) == NNS_EDGE_ERROR_NONE;
  }
  bool send(const OutFrame &, std::string *why) override {
    if (why) *why = "an edgesrc does not send";
    return false;
  }
  int64_t client_id() const override { return 0; }
  std::string server_caps() const override { return ""; }
  std::string server_name() const override { return lib_ ? lib_->describe() : o_.custom_lib; }
  void disconnect() override {
    if (!lib_) return;
    if (started_) lib_->c()->nns_edge_custom_stop(lib_->priv());  // then close, as upstream
    started_ = false;
    lib_.reset();
  }

 private:
  static int on_event(nns_edge_event_h e, void *self) {
    try {
      return static_cast<CustomSubscriber *>(self)->event(e);
    } catch (...) {
      return NNS_EDGE_ERROR_UNKNOWN;  // never let an exception into the library
    }
  }

  int event(nns_edge_event_h e) {
    nns_edge_event_e type = NNS_EDGE_EVENT_UNKNOWN;
    if (capi().event_get_type(e, &type) != NNS_EDGE_ERROR_NONE)
      return NNS_EDGE_ERROR_INVALID_PARAMETER;
    if (type == NNS_EDGE_EVENT_CONNECTION_CLOSED) {
      if (cb_.on_closed)
        cb_.on_closed("the custom connection of " + o_.custom_lib + " closed", CloseKind::kBroken);
      return NNS_EDGE_ERROR_NONE;
    }
    if (type != NNS_EDGE_EVENT_NEW_DATA_RECEIVED) return NNS_EDGE_ERROR_NONE;
    void *ptr = nullptr;
    nns_size_t len = 0;
    if (capi().event_get_data(e, &ptr, &len) != NNS_EDGE_ERROR_NONE ||
        capi().data_is_valid(ptr) != NNS_EDGE_ERROR_NONE)
      return NNS_EDGE_ERROR_INVALID_PARAMETER;
    unsigned int count = 0;
    capi().data_get_count(ptr, &count);
    Message m;
    m.header.cmd = Cmd::kTransferData;
    uint64_t total = 0;
    for (unsigned int i = 0; i < count; ++i) {
      void *mem = nullptr;
      nns_size_t n = 0;
      capi().data_get(ptr, i, &mem, &n);
      total += n;
      if (total > o_.limits.max_frame_bytes) {
        if (cb_.on_closed)
          cb_.on_closed(o_.custom_lib + " delivered more than the frame limit of " +
                            std::to_string(o_.limits.max_frame_bytes) + " bytes",
                        CloseKind::kProtocol);
        return NNS_EDGE_ERROR_INVALID_PARAMETER;
      }
      PayloadPtr p = cb_.alloc ? cb_.alloc(n) : heap_payload(n);
      if (n) std::memcpy(p->data(), mem, n);
      m.header.mem_sizes.push_back(n);
      m.mems.push_back(std::move(p));
    }
    void *meta = nullptr;
    nns_size_t meta_len = 0;
    if (capi().data_serialize_meta(ptr, &meta, &meta_len) == NNS_EDGE_ERROR_NONE && meta) {
      if (auto parsed = Metadata::parse(static_cast<const uint8_t *>(meta), meta_len, nullptr))
        m.meta = std::move(*parsed);
      std::free(meta);
    }
    if (cb_.on_data) cb_.on_data(std::move(m));
    return NNS_EDGE_ERROR_NONE;
  }

  NodeOptions o_;
  NodeCallbacks cb_;
  std::unique_ptr<CustomLib> lib_;
  bool started_ = false;
};

}  // namespace

std::unique_ptr<ServerNode> make_custom_server(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<CustomPublisher>(opts, std::move(cb));
}

std::unique_ptr<ClientNode> make_custom_client(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<CustomSubscriber>(opts, std::move(cb));
}

}  // namespace nns::edge
