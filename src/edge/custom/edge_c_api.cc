// SPDX-License-Identifier: LGPL-2.1-only
// libnnstreamer-edge.so.0.2.6 of this project: nnstreamer-edge's data-handle and event C API
// (nns_edge_abi.h), the part a connect-type CUSTOM library calls. edgesrc/edgesink link it,
// so it is loaded (under upstream's SONAME) before any custom library, and a library built
// against nnstreamer-edge 0.2.6 finds these functions here. Only the C functions are exported
// (the target is built with hidden visibility); serialization reuses edge_data.cc.
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "edge/custom/nns_edge_abi.h"
#include "edge/edge_data.h"

#define NNS_EXPORT extern "C" __attribute__((visibility("default")))

namespace {

constexpr uint32_t kLive = 0xfeeedeedU, kDead = 0xdeaddeadU;

struct Mem {
  void *data;
  nns_size_t len;
  nns_edge_data_destroy_cb destroy;
};

struct Data {
  uint32_t magic = kLive;
  std::mutex lock;
  std::vector<Mem> mems;
  nns::edge::Metadata meta;
};

struct Event {
  uint32_t magic = kLive;
  nns_edge_event_e type = NNS_EDGE_EVENT_UNKNOWN;
  void *data = nullptr;
  nns_size_t len = 0;
  nns_edge_data_destroy_cb destroy = nullptr;
};

Data *data_of(nns_edge_data_h h) {
  auto *d = static_cast<Data *>(h);
  return d && d->magic == kLive ? d : nullptr;
}
Event *event_of(nns_edge_event_h h) {
  auto *e = static_cast<Event *>(h);
  return e && e->magic == kLive ? e : nullptr;
}
bool valid_str(const char *s) {
  return s && *s;
}

char *dup_string(const std::string &s) {
  char *out = static_cast<char *>(std::malloc(s.size() + 1));
  if (out) std::memcpy(out, s.c_str(), s.size() + 1);
  return out;
}

void release_mems(Data *d) {
  for (auto &m : d->mems)
    if (m.destroy) m.destroy(m.data);
  d->mems.clear();
}

}  // namespace

NNS_EXPORT int nns_edge_data_create(nns_edge_data_h *data_h) {
  if (!data_h) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  *data_h = new (std::nothrow) Data();
  return *data_h ? NNS_EDGE_ERROR_NONE : NNS_EDGE_ERROR_OUT_OF_MEMORY;
}

NNS_EXPORT int nns_edge_data_destroy(nns_edge_data_h data_h) {
  Data *d = data_of(data_h);
  if (!d) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  {
    std::lock_guard<std::mutex> l(d->lock);
    d->magic = kDead;
    release_mems(d);
  }
  delete d;
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT void nns_edge_data_release_handle(void *data) {
  if (data) nns_edge_data_destroy(data);
}

NNS_EXPORT int nns_edge_data_is_valid(nns_edge_data_h data_h) {
  return data_of(data_h) ? NNS_EDGE_ERROR_NONE : NNS_EDGE_ERROR_INVALID_PARAMETER;
}

NNS_EXPORT int nns_edge_data_copy(nns_edge_data_h data_h, nns_edge_data_h *new_data_h) {
  Data *d = data_of(data_h);
  if (!d || !new_data_h) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  auto *c = new (std::nothrow) Data();
  if (!c) return NNS_EDGE_ERROR_OUT_OF_MEMORY;
  std::lock_guard<std::mutex> l(d->lock);
  for (const auto &m : d->mems) {
    void *p = std::malloc(m.len ? m.len : 1);
    if (!p) {
      nns_edge_data_destroy(c);
      return NNS_EDGE_ERROR_OUT_OF_MEMORY;
    }
    std::memcpy(p, m.data, m.len);
    c->mems.push_back({p, m.len, std::free});
  }
  c->meta = d->meta;
  *new_data_h = c;
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_add(nns_edge_data_h data_h, void *data, nns_size_t data_len,
                                 nns_edge_data_destroy_cb destroy_cb) {
  Data *d = data_of(data_h);
  if (!d || !data || data_len == 0) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  if (d->mems.size() >= NNS_EDGE_DATA_LIMIT) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  d->mems.push_back({data, data_len, destroy_cb});
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_clear(nns_edge_data_h data_h) {
  Data *d = data_of(data_h);
  if (!d) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  release_mems(d);
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_get(nns_edge_data_h data_h, unsigned int index, void **data,
                                 nns_size_t *data_len) {
  Data *d = data_of(data_h);
  if (!d || !data || !data_len) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  if (index >= d->mems.size()) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  *data = d->mems[index].data;
  *data_len = d->mems[index].len;
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_get_count(nns_edge_data_h data_h, unsigned int *count) {
  Data *d = data_of(data_h);
  if (!d || !count) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  *count = static_cast<unsigned int>(d->mems.size());
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_set_info(nns_edge_data_h data_h, const char *key, const char *value) {
  Data *d = data_of(data_h);
  if (!d || !valid_str(key) || !valid_str(value)) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  d->meta.set(key, value);
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_get_info(nns_edge_data_h data_h, const char *key, char **value) {
  Data *d = data_of(data_h);
  if (!d || !valid_str(key) || !value) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  const auto v = d->meta.get(key);
  if (!v) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  *value = dup_string(*v);
  return *value ? NNS_EDGE_ERROR_NONE : NNS_EDGE_ERROR_OUT_OF_MEMORY;
}

NNS_EXPORT int nns_edge_data_clear_info(nns_edge_data_h data_h) {
  Data *d = data_of(data_h);
  if (!d) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  d->meta = nns::edge::Metadata();
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_serialize_meta(nns_edge_data_h data_h, void **data,
                                            nns_size_t *data_len) {
  Data *d = data_of(data_h);
  if (!d || !data || !data_len) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  const auto bytes = d->meta.serialize();
  *data = nullptr;
  *data_len = 0;
  if (bytes.empty()) return NNS_EDGE_ERROR_NONE;  // no metadata: no bytes (as upstream)
  *data = std::malloc(bytes.size());
  if (!*data) return NNS_EDGE_ERROR_OUT_OF_MEMORY;
  std::memcpy(*data, bytes.data(), bytes.size());
  *data_len = bytes.size();
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_deserialize_meta(nns_edge_data_h data_h, const void *data,
                                              const nns_size_t data_len) {
  Data *d = data_of(data_h);
  if (!d || !data || data_len == 0) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  auto meta = nns::edge::Metadata::parse(static_cast<const uint8_t *>(data), data_len, nullptr);
  if (!meta) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  d->meta = std::move(*meta);
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_serialize(nns_edge_data_h data_h, void **data, nns_size_t *len) {
  Data *d = data_of(data_h);
  if (!d || !data || !len) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::vector<uint8_t> bytes;
  {
    std::lock_guard<std::mutex> l(d->lock);
    nns::edge::OutFrame f;
    for (const auto &m : d->mems) f.mems.push_back({m.data, m.len});
    f.meta = d->meta;
    bytes = nns::edge::serialize_data(f);  // at most 256 memories (add() enforces it)
  }
  *data = std::malloc(bytes.size());
  if (!*data) return NNS_EDGE_ERROR_OUT_OF_MEMORY;
  std::memcpy(*data, bytes.data(), bytes.size());
  *len = bytes.size();
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_data_is_serialized(const void *data, const nns_size_t data_len) {
  if (!data) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  nns::edge::Message m;
  // Checks only: a counting allocator that hands out nothing would also work, but the memories
  // are small enough to parse for real here.
  return nns::edge::parse_data(static_cast<const uint8_t *>(data), data_len, {}, {}, &m, nullptr)
             ? NNS_EDGE_ERROR_NONE
             : NNS_EDGE_ERROR_INVALID_PARAMETER;
}

NNS_EXPORT int nns_edge_data_deserialize(nns_edge_data_h data_h, const void *data,
                                         const nns_size_t data_len) {
  Data *d = data_of(data_h);
  if (!d || !data) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  nns::edge::Message m;
  if (!nns::edge::parse_data(static_cast<const uint8_t *>(data), data_len, {}, {}, &m, nullptr))
    return NNS_EDGE_ERROR_INVALID_PARAMETER;
  std::lock_guard<std::mutex> l(d->lock);
  release_mems(d);
  for (auto &p : m.mems) {
    void *copy = std::malloc(p->size() ? p->size() : 1);
    if (!copy) return NNS_EDGE_ERROR_OUT_OF_MEMORY;
    std::memcpy(copy, p->data(), p->size());
    d->mems.push_back({copy, p->size(), std::free});
  }
  d->meta = std::move(m.meta);
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_event_create(nns_edge_event_e event, nns_edge_event_h *event_h) {
  if (!event_h || event == NNS_EDGE_EVENT_UNKNOWN) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  auto *e = new (std::nothrow) Event();
  if (!e) return NNS_EDGE_ERROR_OUT_OF_MEMORY;
  e->type = event;
  *event_h = e;
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_event_destroy(nns_edge_event_h event_h) {
  Event *e = event_of(event_h);
  if (!e) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  e->magic = kDead;
  if (e->destroy) e->destroy(e->data);
  delete e;
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_event_set_data(nns_edge_event_h event_h, void *data, nns_size_t data_len,
                                       nns_edge_data_destroy_cb destroy_cb) {
  Event *e = event_of(event_h);
  if (!e || !data || data_len == 0) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  if (e->destroy) e->destroy(e->data);
  e->data = data;
  e->len = data_len;
  e->destroy = destroy_cb;
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_event_get_data(nns_edge_event_h event_h, void **data,
                                       nns_size_t *data_len) {
  Event *e = event_of(event_h);
  if (!e || !data || !data_len) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  *data = e->data;
  *data_len = e->len;
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_event_get_type(nns_edge_event_h event_h, nns_edge_event_e *event) {
  Event *e = event_of(event_h);
  if (!e || !event) return NNS_EDGE_ERROR_INVALID_PARAMETER;
  *event = e->type;
  return NNS_EDGE_ERROR_NONE;
}

NNS_EXPORT int nns_edge_event_parse_new_data(nns_edge_event_h event_h, nns_edge_data_h *data_h) {
  Event *e = event_of(event_h);
  if (!e || !data_h || e->type != NNS_EDGE_EVENT_NEW_DATA_RECEIVED)
    return NNS_EDGE_ERROR_INVALID_PARAMETER;
  return nns_edge_data_copy(e->data, data_h);  // the caller owns the copy
}

NNS_EXPORT int nns_edge_event_parse_capability(nns_edge_event_h event_h, char **capability) {
  Event *e = event_of(event_h);
  if (!e || !capability || e->type != NNS_EDGE_EVENT_CAPABILITY || !e->data)
    return NNS_EDGE_ERROR_INVALID_PARAMETER;
  *capability = dup_string(static_cast<const char *>(e->data));
  return *capability ? NNS_EDGE_ERROR_NONE : NNS_EDGE_ERROR_OUT_OF_MEMORY;
}

NNS_EXPORT int nns_edge_event_invoke_callback(nns_edge_event_cb event_cb, void *user_data,
                                              nns_edge_event_e event, void *data,
                                              nns_size_t data_len,
                                              nns_edge_data_destroy_cb destroy_cb) {
  if (!event_cb) return NNS_EDGE_ERROR_NONE;  // nobody listens: not an error (as upstream)
  nns_edge_event_h e = nullptr;
  int ret = nns_edge_event_create(event, &e);
  if (ret != NNS_EDGE_ERROR_NONE) return ret;
  if (data) ret = nns_edge_event_set_data(e, data, data_len, destroy_cb);
  if (ret == NNS_EDGE_ERROR_NONE) ret = event_cb(e, user_data);
  nns_edge_event_destroy(e);
  return ret;
}
