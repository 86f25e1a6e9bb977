// SPDX-License-Identifier: LGPL-2.1-only
// Writes the seed corpus of the fuzz targets: valid encodings of many shapes (every type, ranks
// 1..16, 1, 2, 16 and 17 tensors, names, flexible format, odd rates) for each wire format, and
// valid flexible/sparse headers. usage: nns_fuzz_corpus <out-dir>  (makes <out-dir>/<target>/)
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/meta_header.h"
#include "mqtt/mqtt_message.h"
#include "edge/edge_data.h"
#include "edge/edge_wire.h"
#include "wire.h"

namespace {

namespace fs = std::filesystem;
using nns::wire::Format;

void save(const fs::path &dir, int n, const uint8_t *p, std::size_t size) {
  std::ofstream(dir / ("seed_" + std::to_string(n)), std::ios::binary)
      .write(reinterpret_cast<const char *>(p), static_cast<std::streamsize>(size));
}

struct Spec {
  uint32_t type;
  std::vector<uint32_t> dims;
  std::string name;
};

std::vector<std::vector<Spec>> frames() {
  std::vector<std::vector<Spec>> out;
  for (uint32_t t = 0; t < nns::wire::kTypeEnd; ++t) out.push_back({{t, {3, 2}, ""}});
  for (uint32_t r = 1; r <= nns::wire::kRankLimit; ++r)
    out.push_back({{5, std::vector<uint32_t>(r, r == 1 ? 5 : 1), "rank" + std::to_string(r)}});
  out.push_back({{5, {4}, "a"}, {7, {2, 2, 2}, ""}});
  for (std::size_t n : {16u, 17u}) {
    std::vector<Spec> many;
    for (std::size_t i = 0; i < n; ++i) many.push_back({static_cast<uint32_t>(i % 11), {2}, ""});
    out.push_back(many);
  }
  out.push_back({{9, {1, 1, 1, 1}, std::string(40, 'n')}});
  return out;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <out-dir>\n", argv[0]);
    return 2;
  }
  const fs::path root = argv[1];
  for (Format fmt : {Format::kProtobuf, Format::kFlatbuf, Format::kFlexbuf}) {
    const fs::path dir = root / (std::string("wire_") + nns::wire::format_name(fmt));
    fs::create_directories(dir);
    int n = 0;
    for (const auto &specs : frames()) {
      for (int rate = 0; rate < 2; ++rate) {
        nns::wire::Frame f;
        f.rate_n = rate ? 30 : 0;
        f.rate_d = rate ? 1 : 1;
        std::vector<std::vector<uint8_t>> blobs;
        for (const Spec &s : specs) {
          nns::wire::Tensor t;
          t.name = s.name;
          t.type = s.type;
          std::size_t bytes = nns::wire::type_size(s.type);
          for (std::size_t k = 0; k < s.dims.size(); ++k) t.dims[k] = s.dims[k], bytes *= s.dims[k];
          blobs.emplace_back(bytes);
          for (std::size_t k = 0; k < bytes; ++k)
            blobs.back()[k] = static_cast<uint8_t>(k * 13 + n);
          f.tensors.push_back(t);
        }
        for (std::size_t i = 0; i < specs.size(); ++i)
          f.tensors[i].data = blobs[i].data(), f.tensors[i].size = blobs[i].size();
        std::vector<uint8_t> bytes;
        nns::wire::encode(fmt, f, bytes);
        save(dir, n++, bytes.data(), bytes.size());
      }
    }
    // A flexible frame: each tensor memory starts with its 128-byte header.
    std::vector<uint8_t> mem(nns::kMetaHeaderSize + 6);
    nns::MetaHeader h;
    h.type = nns::TensorType::kUInt8;
    h.dims[0] = 6;
    h.format = nns::TensorFormat::kFlexible;
    nns::write_meta_header(h, mem.data());
    nns::wire::Frame f;
    f.format = 1;
    nns::wire::Tensor t;
    t.type = 5;
    t.dims[0] = 6;
    t.data = mem.data();
    t.size = mem.size();
    f.tensors.push_back(t);
    std::vector<uint8_t> bytes;
    nns::wire::encode(fmt, f, bytes);
    save(dir, n++, bytes.data(), bytes.size());
  }
  const fs::path dir = root / "meta_header";
  fs::create_directories(dir);
  int n = 0;
  for (int t = 0; t < 11; ++t) {
    for (int fmt = 0; fmt < 3; ++fmt) {
      nns::MetaHeader h;
      h.type = static_cast<nns::TensorType>(t);
      h.format = static_cast<nns::TensorFormat>(fmt);
      for (int k = 0; k <= t % 5; ++k) h.dims[k] = static_cast<uint32_t>(k + 2);
      h.nnz = fmt == 2 ? 3 : 0;
      uint8_t buf[nns::kMetaHeaderSize];
      nns::write_meta_header(h, buf);
      save(dir, n++, buf, sizeof buf);
    }
  }
  const fs::path mdir = root / "mqtt_message";
  fs::create_directories(mdir);
  n = 0;
  for (std::size_t mems = 0; mems <= nns::mqtt::kMaxMems; mems += 3) {
    nns::mqtt::MessageHeader h;
    for (std::size_t k = 0; k < mems; ++k) h.mem_sizes.push_back(k * 5 + 1);
    h.base_time_epoch = 1700000000000000000LL;
    h.sent_time_epoch = h.base_time_epoch + static_cast<int64_t>(mems) * 1000;
    h.pts = mems * 33333333ULL;
    h.duration = 33333333ULL;
    h.caps = mems % 2 ? "other/tensors,format=static,num_tensors=1,dimensions=4,types=uint8"
                      : "video/x-raw,format=RGB,width=4,height=2";
    std::vector<uint8_t> m(nns::mqtt::kHeaderSize + h.payload_size(), 0x42);
    nns::mqtt::write_header(h, m.data());
    save(mdir, n++, m.data(), m.size());
  }
  const fs::path iio = root / "iio_channel";
  fs::create_directories(iio);
  n = 0;
  for (const char *seed :
       {"le:s12/16>>4\n\x12\x34", "be:u10/16>>6\n\xff\xc0", "le:s24/32>>8\n\x01\x02\x03\x84",
        "le:s64/64>>0\n01234567", "be:s8/8>>0\n\x80", "le:u24/24>>0\n\x01\x02\x83"}) {
    save(iio, n++, reinterpret_cast<const uint8_t *>(seed), std::strlen(seed));
  }
  {  // nnstreamer-edge TCP frames: handshake frames, a data frame with metadata, a goodbye.
    const fs::path edir = root / "edge_frame";
    fs::create_directories(edir);
    namespace e = nns::edge;
    auto frame = [](e::Cmd cmd, std::vector<std::vector<uint8_t>> mems, e::Metadata meta) {
      e::Header h;
      h.cmd = cmd;
      h.client_id = 1234;
      for (auto &m : mems) h.mem_sizes.push_back(m.size());
      const auto mb = meta.serialize();
      h.meta_size = mb.size();
      const auto hb = e::encode_header(h);
      std::vector<uint8_t> out(hb.begin(), hb.end());
      for (auto &m : mems) out.insert(out.end(), m.begin(), m.end());
      out.insert(out.end(), mb.begin(), mb.end());
      return out;
    };
    const std::string caps = "@query_server_src_caps@ANY@query_server_sink_caps@ANY";
    e::Metadata meta;
    meta.set("client_id", "1234");
    std::vector<std::vector<uint8_t>> seeds = {
        frame(e::Cmd::kCapability, {std::vector<uint8_t>(caps.begin(), caps.end())}, {}),
        frame(e::Cmd::kHostInfo, {{'1', '2', '7', '.', '0', '.', '0', '.', '1', ':', '9', 0}}, {}),
        frame(e::Cmd::kTransferData, {std::vector<uint8_t>(64, 7), {1, 2, 3}}, meta),
        frame(e::Cmd::kError, {}, {})};
    std::vector<uint8_t> two = seeds[2];
    two.insert(two.end(), seeds[3].begin(), seeds[3].end());
    seeds.push_back(two);
    int k = 0;
    for (auto &b : seeds) save(edir, k++, b.data(), b.size());
  }
  {  // nnstreamer-edge serialized edge data (MQTT payloads): 0, 1, 3 and 16 memories.
    const fs::path ddir = root / "edge_data";
    fs::create_directories(ddir);
    int k = 0;
    for (std::size_t mems : {0, 1, 3, 16}) {
      std::vector<std::vector<uint8_t>> bufs;
      nns::edge::OutFrame f;
      for (std::size_t i = 0; i < mems; ++i) bufs.emplace_back(i * 3 + 1, static_cast<uint8_t>(i));
      for (auto &b : bufs) f.mems.push_back({b.data(), b.size()});
      if (mems % 2) f.meta.set("caps", "video/x-raw,format=GRAY8,width=4,height=2");
      const auto bytes = nns::edge::serialize_data(f);
      save(ddir, k++, bytes.data(), bytes.size());
    }
  }
  std::printf("seed corpus written to %s\n", root.c_str());
  return 0;
}
