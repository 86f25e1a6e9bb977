// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/tensor_buffer.h"

#include <cstring>

#include "core/error.h"
#include "gst/gst_ptr.h"

namespace nns::gst {
namespace {

constexpr uint32_t kExtraMagic = 0xf00dc0de;

// Layout of the header at the start of the 16th memory when a frame has > 16 tensors
// (NNStreamer's GstTensorExtraInfo on LP64; `name` pointers are always null here).
struct ExtraTensorInfo {
  char *name;
  uint32_t type;
  uint32_t dims[kRankLimit];
};
struct ExtraHeader {
  uint32_t magic;
  uint32_t version;
  uint32_t num_extra_tensors;
  uint64_t reserved;  // byte size of tensor 15, stored first after the header
  ExtraTensorInfo infos[kTensorLimit - kMemoryMax];
};

bool is_extra(const guint8 *data, gsize size) {
  if (size < sizeof(ExtraHeader)) return false;
  uint32_t magic;
  std::memcpy(&magic, data, sizeof magic);
  return magic == kExtraMagic;
}

std::size_t extra_info_size(const ExtraTensorInfo &e) {
  TensorInfo t;
  t.type = static_cast<TensorType>(e.type);
  for (std::size_t i = 0; i < kRankLimit; ++i) t.dims[i] = e.dims[i];
  return t.byte_size();
}

}  // namespace

std::size_t buffer_tensor_count(GstBuffer *buf) {
  guint n = gst_buffer_n_memory(buf);
  if (n < kMemoryMax) return n;
  GstMemory *last = gst_buffer_peek_memory(buf, n - 1);
  MemoryMap map(last, GST_MAP_READ);
  if (!map.ok() || !is_extra(map.data(), map.size())) return n;
  const auto *h = reinterpret_cast<const ExtraHeader *>(map.data());
  return kMemoryMax + h->num_extra_tensors;
}

GstMemory *buffer_get_tensor(GstBuffer *buf, std::size_t index) {
  guint n = gst_buffer_n_memory(buf);
  if (index + 1 < kMemoryMax || n < kMemoryMax)
    return index < n ? gst_buffer_get_memory(buf, index) : nullptr;
  GstMemory *last = gst_buffer_peek_memory(buf, n - 1);
  MemoryMap map(last, GST_MAP_READ);
  if (!map.ok()) return nullptr;
  if (!is_extra(map.data(), map.size())) return index == n - 1 ? gst_memory_ref(last) : nullptr;
  const auto *h = reinterpret_cast<const ExtraHeader *>(map.data());
  if (index >= kMemoryMax + h->num_extra_tensors) return nullptr;
  gsize offset = sizeof(ExtraHeader);
  if (index == kMemoryMax - 1) return gst_memory_share(last, offset, h->reserved);
  offset += h->reserved;
  for (std::size_t i = 0; i + kMemoryMax < index; ++i) offset += extra_info_size(h->infos[i]);
  return gst_memory_share(last, offset, extra_info_size(h->infos[index - kMemoryMax]));
}

void buffer_append_tensor(GstBuffer *buf, GstMemory *mem, const TensorInfo &info) {
  MemoryPtr incoming(mem);
  guint n = gst_buffer_n_memory(buf);
  if (n < kMemoryMax) {
    gst_buffer_append_memory(buf, incoming.release());
    return;
  }
  // Repack the last memory with the extra header plus the new tensor.
  GstMemory *last = gst_buffer_peek_memory(buf, n - 1);
  MemoryPtr keep_last(gst_memory_ref(last));  // stays valid (and mapped) past the replace below
  MemoryMap lmap(last, GST_MAP_READ);
  MemoryMap imap(incoming.get(), GST_MAP_READ);
  if (!lmap.ok() || !imap.ok()) fail(ErrorKind::kStream, "cannot map tensor memory for packing");
  bool extra = is_extra(lmap.data(), lmap.size());
  gsize head = extra ? 0 : sizeof(ExtraHeader);
  gsize total = head + lmap.size() + imap.size();
  GstMemory *packed = gst_allocator_alloc(nullptr, total, nullptr);
  {
    MemoryMap pmap(packed, GST_MAP_WRITE);
    if (!pmap.ok()) fail(ErrorKind::kStream, "cannot map packed tensor memory");
    if (!extra) {
      ExtraHeader h{};
      h.magic = kExtraMagic;
      h.reserved = lmap.size();
      std::memcpy(pmap.data(), &h, sizeof h);
    }
    std::memcpy(pmap.data() + head, lmap.data(), lmap.size());
    auto *h = reinterpret_cast<ExtraHeader *>(pmap.data());
    if (h->num_extra_tensors >= kTensorLimit - kMemoryMax)
      fail(ErrorKind::kStream, "more than 256 tensors in one frame");
    ExtraTensorInfo &e = h->infos[h->num_extra_tensors++];
    e.name = nullptr;
    e.type = static_cast<uint32_t>(info.type);
    for (std::size_t i = 0; i < kRankLimit; ++i) e.dims[i] = info.dims[i];
    std::memcpy(pmap.data() + head + lmap.size(), imap.data(), imap.size());
  }
  gst_buffer_replace_memory(buf, n - 1, packed);
}

void check_static_buffer(GstBuffer *buf, const TensorsInfo &info) {
  std::size_t count = buffer_tensor_count(buf);
  if (count != info.size())
    fail(ErrorKind::kStream, "buffer has " + std::to_string(count) + " tensor memories, expected " +
                                 std::to_string(info.size()) + " (" + info.to_string() + ")");
  for (std::size_t i = 0; i < count; ++i) {
    MemoryPtr m(buffer_get_tensor(buf, i));
    gsize got = m ? gst_memory_get_sizes(m.get(), nullptr, nullptr) : 0;
    if (got != info[i].byte_size())
      fail(ErrorKind::kStream, "tensor " + std::to_string(i) + " has " + std::to_string(got) +
                                   " bytes, expected " + std::to_string(info[i].byte_size()) +
                                   " for " + info[i].to_string());
  }
}

GstMemory *memory_with_header(const MetaHeader &h, GstMemory *payload) {
  MemoryMap src(payload, GST_MAP_READ);
  if (!src.ok()) fail(ErrorKind::kStream, "cannot map tensor memory");
  GstMemory *out = gst_allocator_alloc(nullptr, kMetaHeaderSize + src.size(), nullptr);
  MemoryMap dst(out, GST_MAP_WRITE);
  write_meta_header(h, dst.data());
  std::memcpy(dst.data() + kMetaHeaderSize, src.data(), src.size());
  return out;
}

MetaHeader memory_header(GstMemory *mem) {
  MemoryMap map(mem, GST_MAP_READ);
  if (!map.ok()) fail(ErrorKind::kStream, "cannot map tensor memory");
  return parse_meta_header(map.data(), map.size());
}

}  // namespace nns::gst
