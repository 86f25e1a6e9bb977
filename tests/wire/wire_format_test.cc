// SPDX-License-Identifier: LGPL-2.1-only
// nns_wire: exact round trips (every type, ranks 1..16, many tensors, flexible format),
// a protobuf golden encoding, and corrupt inputs (truncation, bit flips, wrong value types,
// huge declared sizes) that must end in WireError, never a crash.
#include <gtest/gtest.h>

#ifdef NNS_HAVE_WIRE
#include <flatbuffers/flexbuffers.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "wire.h"

namespace {

using nns::wire::Format;
using nns::wire::Frame;
using nns::wire::Tensor;
using nns::wire::WireError;

constexpr Format kFormats[] = {Format::kProtobuf, Format::kFlatbuf, Format::kFlexbuf};

struct Owned {
  Frame frame;
  std::vector<std::vector<uint8_t>> bytes;
};

Owned make_frame(const std::vector<std::pair<uint32_t, std::vector<uint32_t>>> &specs,
                 uint32_t seed = 1) {
  Owned o;
  o.frame.rate_n = 30;
  o.frame.rate_d = 1;
  o.bytes.resize(specs.size());
  std::mt19937 rng(seed);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    Tensor t;
    t.name = i % 2 ? "" : "t" + std::to_string(i);
    t.type = specs[i].first;
    std::size_t n = nns::wire::type_size(t.type);
    for (std::size_t k = 0; k < specs[i].second.size(); ++k) {
      t.dims[k] = specs[i].second[k];
      n *= t.dims[k];
    }
    o.bytes[i].resize(n);
    for (auto &b : o.bytes[i]) b = static_cast<uint8_t>(rng());
    t.data = o.bytes[i].data();
    t.size = n;
    o.frame.tensors.push_back(t);
  }
  return o;
}

void expect_same(const Frame &a, const Frame &b) {
  EXPECT_EQ(a.format, b.format);
  EXPECT_EQ(a.rate_n, b.rate_n);
  EXPECT_EQ(a.rate_d, b.rate_d);
  ASSERT_EQ(a.tensors.size(), b.tensors.size());
  for (std::size_t i = 0; i < a.tensors.size(); ++i) {
    const Tensor &x = a.tensors[i], &y = b.tensors[i];
    EXPECT_EQ(x.name, y.name) << i;
    EXPECT_EQ(x.type, y.type) << i;
    EXPECT_EQ(x.dims, y.dims) << i;
    ASSERT_EQ(x.size, y.size) << i;
    EXPECT_EQ(0, std::memcmp(x.data, y.data, x.size)) << i;
  }
}

TEST(WireFormat, RoundTripEveryTypeAndRank) {
  for (Format fmt : kFormats) {
    for (uint32_t type = 0; type < nns::wire::kTypeEnd; ++type) {
      for (std::size_t rank = 1; rank <= 16; ++rank) {
        std::vector<uint32_t> dims(rank, 1);
        dims[0] = 3;
        if (rank > 1) dims[1] = 2;
        if (rank > 4) dims[rank - 1] = 2;
        Owned o = make_frame({{type, dims}}, type * 100 + rank);
        std::vector<uint8_t> bytes;
        nns::wire::encode(fmt, o.frame, bytes);
        Frame back = nns::wire::decode(fmt, bytes.data(), bytes.size());
        SCOPED_TRACE(std::string(nns::wire::format_name(fmt)) + " type " + std::to_string(type) +
                     " rank " + std::to_string(rank));
        expect_same(o.frame, back);
      }
    }
  }
}

TEST(WireFormat, RoundTripManyTensorsAndFlexible) {
  std::vector<std::pair<uint32_t, std::vector<uint32_t>>> specs;
  for (uint32_t i = 0; i < 40; ++i) specs.push_back({i % 11, {i + 1, 2}});
  Owned o = make_frame(specs, 7);
  o.frame.rate_n = 15;
  o.frame.rate_d = 2;
  for (Format fmt : kFormats) {
    std::vector<uint8_t> bytes;
    nns::wire::encode(fmt, o.frame, bytes);
    expect_same(o.frame, nns::wire::decode(fmt, bytes.data(), bytes.size()));
  }
  // Flexible: each tensor's bytes start with a 128-byte header; sizes are not checked here.
  Owned flex = make_frame({{5, {200}}, {7, {40}}}, 9);
  flex.frame.format = 1;
  for (Format fmt : kFormats) {
    std::vector<uint8_t> bytes;
    nns::wire::encode(fmt, flex.frame, bytes);
    expect_same(flex.frame, nns::wire::decode(fmt, bytes.data(), bytes.size()));
  }
}

TEST(WireFormat, FlatbufAndFlexbufAreZeroCopy) {
  Owned o = make_frame({{5, {224, 224, 3}}});
  for (Format fmt : {Format::kFlatbuf, Format::kFlexbuf}) {
    std::vector<uint8_t> bytes;
    nns::wire::encode(fmt, o.frame, bytes);
    Frame f = nns::wire::decode(fmt, bytes.data(), bytes.size());
    EXPECT_GE(f.tensors[0].data, bytes.data());
    EXPECT_LE(f.tensors[0].data + f.tensors[0].size, bytes.data() + bytes.size());
  }
}

// The protobuf bytes for a one-tensor frame, worked out by hand from nnstreamer.proto.
TEST(WireFormat, ProtobufGoldenBytes) {
  Frame f;
  f.rate_n = 30;
  f.rate_d = 1;
  const uint8_t data[2] = {1, 2};
  Tensor t;
  t.name = "a";
  t.type = 5;  // NNS_UINT8
  t.dims[0] = 2;
  t.data = data;
  t.size = 2;
  f.tensors.push_back(t);
  std::vector<uint8_t> want = {0x08, 0x01,                          // num_tensor = 1
                               0x12, 0x04, 0x08, 0x1e, 0x10, 0x01,  // fr {30, 1}
                               0x1a, 0x1b,                          // tensor, 27 bytes
                               0x0a, 0x01, 'a',                     // name
                               0x10, 0x05,                          // type
                               0x1a, 0x10, 0x02};                   // dimension (packed, 16)
  want.insert(want.end(), 15, 0x00);
  want.insert(want.end(), {0x22, 0x02, 0x01, 0x02});  // data
  std::vector<uint8_t> got;
  nns::wire::encode_protobuf(f, got);
  EXPECT_EQ(want, got);
  // Upstream's older writers put 1s after the rank: still accepted (trailing 1s are rank).
  want[18] = 0x01;
  want[19] = 0x01;
  Frame back = nns::wire::decode_protobuf(want.data(), want.size());
  EXPECT_EQ(1u, back.tensors[0].dims[2]);
  EXPECT_EQ(0u, back.tensors[0].dims[3]);
}

TEST(WireFormat, EncodeRejectsInvalidFrames) {
  std::vector<uint8_t> out;
  Frame empty;
  for (Format fmt : kFormats) EXPECT_THROW(nns::wire::encode(fmt, empty, out), WireError);
  Owned o = make_frame({{5, {4}}});
  o.frame.tensors[0].size = 3;
  EXPECT_THROW(nns::wire::encode(Format::kFlatbuf, o.frame, out), WireError);
  o.frame.tensors[0].size = 4;
  o.frame.tensors[0].type = 11;
  EXPECT_THROW(nns::wire::encode(Format::kFlexbuf, o.frame, out), WireError);
}

// Every prefix and many random corruptions of a valid encoding: WireError or a valid frame.
TEST(WireFormat, CorruptInputNeverCrashes) {
  Owned o = make_frame({{7, {4, 3}}, {5, {5}}, {9, {2, 2, 2}}});
  std::mt19937 rng(42);
  for (Format fmt : kFormats) {
    std::vector<uint8_t> good;
    nns::wire::encode(fmt, o.frame, good);
    std::size_t rejected = 0;
    for (std::size_t n = 1; n < good.size(); ++n) {
      std::vector<uint8_t> cut(good.begin(), good.begin() + n);
      try {
        nns::wire::validate(nns::wire::decode(fmt, cut.data(), cut.size()));
      } catch (const WireError &) {
        ++rejected;
      }
    }
    EXPECT_GT(rejected, good.size() / 2) << nns::wire::format_name(fmt);
    for (int i = 0; i < 3000; ++i) {
      std::vector<uint8_t> bad = good;
      for (int k = 0; k < 1 + i % 4; ++k) bad[rng() % bad.size()] ^= 1u << (rng() % 8);
      try {
        nns::wire::Frame f = nns::wire::decode(fmt, bad.data(), bad.size());
        for (const Tensor &t : f.tensors) {
          volatile uint8_t sink = 0;
          for (std::size_t b = 0; b < t.size; ++b) sink = sink + t.data[b];
        }
      } catch (const WireError &) {
      }
    }
    EXPECT_THROW(nns::wire::decode(fmt, nullptr, 0), WireError);
  }
}

TEST(WireFormat, HugeDeclaredSizesAreErrors) {
  // A tensor that claims 65536^3 float64 elements but carries 8 bytes.
  Owned o = make_frame({{6, {1}}});
  o.frame.tensors[0].dims = {65536, 65536, 65536};
  EXPECT_THROW(nns::wire::validate(o.frame), WireError);
  // Protobuf: a length-delimited field announcing 2^31 bytes.
  const uint8_t pb[] = {0x1a, 0x80, 0x80, 0x80, 0x80, 0x08, 0x0a};
  EXPECT_THROW(nns::wire::decode_protobuf(pb, sizeof(pb)), WireError);
  // Protobuf: num_tensor says 1000 but no tensors follow.
  const uint8_t pb2[] = {0x08, 0xe8, 0x07};
  EXPECT_THROW(nns::wire::decode_protobuf(pb2, sizeof(pb2)), WireError);
  // Flatbuf: a root offset pointing far outside the buffer.
  const uint8_t fb[] = {0xff, 0xff, 0xff, 0x7f, 0, 0, 0, 0};
  EXPECT_THROW(nns::wire::decode_flatbuf(fb, sizeof(fb)), WireError);
  // Flexbuf: dims 65536^3 uint8 with a 1-byte blob -> size mismatch.
  flexbuffers::Builder b;
  b.Map([&]() {
    b.UInt("num_tensors", 1);
    b.Vector("tensor_0", [&]() {
      b.String("x");
      b.Int(5);
      const uint32_t d[3] = {65536, 65536, 65536};
      b.Vector(d, 3);
      const uint8_t one = 1;
      b.Blob(&one, 1);
    });
  });
  b.Finish();
  EXPECT_THROW(nns::wire::decode_flexbuf(b.GetBuffer().data(), b.GetSize()), WireError);
}

TEST(WireFormat, FlexbufWrongValueTypes) {
  auto build = [](auto &&fill) {
    flexbuffers::Builder b;
    b.Map([&]() { fill(b); });
    b.Finish();
    return b.GetBuffer();
  };
  const uint8_t one = 1;
  auto tensor = [&](flexbuffers::Builder &b, auto &&name, int64_t type, auto &&dims, bool blob) {
    b.Vector("tensor_0", [&]() {
      name(b);
      b.Int(type);
      dims(b);
      if (blob)
        b.Blob(&one, 1);
      else
        b.Int(1);
    });
  };
  auto str_name = [](flexbuffers::Builder &b) { b.String("x"); };
  auto int_name = [](flexbuffers::Builder &b) { b.Int(3); };
  auto good_dims = [](flexbuffers::Builder &b) {
    const uint32_t d[1] = {1};
    b.Vector(d, 1);
  };
  auto str_dims = [](flexbuffers::Builder &b) { b.String("1:1"); };
  std::vector<std::vector<uint8_t>> cases = {
      build([&](auto &b) { b.String("num_tensors", "1"); }),
      build([&](auto &b) {
        b.UInt("num_tensors", 1);
        b.String("rate_n", "30");
        tensor(b, str_name, 5, good_dims, true);
      }),
      build([&](auto &b) {
        b.UInt("num_tensors", 1);
        tensor(b, int_name, 5, good_dims, true);
      }),
      build([&](auto &b) {
        b.UInt("num_tensors", 1);
        tensor(b, str_name, 99, good_dims, true);
      }),
      build([&](auto &b) {
        b.UInt("num_tensors", 1);
        tensor(b, str_name, 5, str_dims, true);
      }),
      build([&](auto &b) {
        b.UInt("num_tensors", 1);
        tensor(b, str_name, 5, good_dims, false);
      }),
      build([&](auto &b) {
        b.UInt("num_tensors", 2);
        tensor(b, str_name, 5, good_dims, true);
      }),
  };
  for (std::size_t i = 0; i < cases.size(); ++i)
    EXPECT_THROW(nns::wire::decode_flexbuf(cases[i].data(), cases[i].size()), WireError) << i;
  // The same map with correct types decodes.
  auto ok = build([&](auto &b) {
    b.UInt("num_tensors", 1);
    tensor(b, str_name, 5, good_dims, true);
  });
  EXPECT_NO_THROW(nns::wire::decode_flexbuf(ok.data(), ok.size()));
  // Root not a map.
  flexbuffers::Builder v;
  v.Int(3);
  v.Finish();
  EXPECT_THROW(nns::wire::decode_flexbuf(v.GetBuffer().data(), v.GetSize()), WireError);
}

// Inputs the fuzzers (fuzz/, docs/fuzzing.md) found crashing, kept in fuzz/regressions/: each
// must now end in WireError or a frame that validates.
TEST(WireFormat, FuzzRegressionsAreRefusedCleanly) {
  namespace fs = std::filesystem;
  const fs::path root = fs::path(NNS_SOURCE_DIR) / "fuzz" / "regressions";
  int seen = 0;
  for (Format fmt : kFormats) {
    const fs::path dir = root / (std::string("wire_") + nns::wire::format_name(fmt));
    if (!fs::is_directory(dir)) continue;
    for (const auto &e : fs::directory_iterator(dir)) {
      SCOPED_TRACE(e.path().string());
      std::ifstream in(e.path(), std::ios::binary);
      std::vector<uint8_t> raw((std::istreambuf_iterator<char>(in)), {});
      // 8-byte aligned copy, as GstMemory gives.
      std::vector<uint64_t> aligned((raw.size() + 7) / 8 + 1);
      std::memcpy(aligned.data(), raw.data(), raw.size());
      try {
        Frame f =
            nns::wire::decode(fmt, reinterpret_cast<const uint8_t *>(aligned.data()), raw.size());
        EXPECT_NO_THROW(nns::wire::validate(f));
      } catch (const WireError &) {
      }
      ++seen;
    }
  }
  EXPECT_GE(seen, 1);
}

// Fuzz finding 2: the flatbuf verifier ran without alignment checks, so a crafted offset made
// the accessors read a misaligned vector (UB). Misaligned tables are refused now, and so is a
// misaligned input pointer (the converter copies such input to aligned memory first).
TEST(WireFormat, FlatbufMisalignedInputRefused) {
  Owned o = make_frame({{5, {4}}});
  std::vector<uint8_t> bytes;
  nns::wire::encode(Format::kFlatbuf, o.frame, bytes);
  std::vector<uint64_t> store(bytes.size() / 8 + 2);
  auto *base = reinterpret_cast<uint8_t *>(store.data());
  std::memcpy(base + 1, bytes.data(), bytes.size());
  try {
    nns::wire::decode_flatbuf(base + 1, bytes.size());
    ADD_FAILURE() << "misaligned input accepted";
  } catch (const WireError &e) {
    EXPECT_NE(std::string::npos, std::string(e.what()).find("aligned")) << e.what();
  }
  std::memcpy(base, bytes.data(), bytes.size());
  EXPECT_NO_THROW(nns::wire::decode_flatbuf(base, bytes.size()));
}

}  // namespace
#else
TEST(WireFormat, Skipped) {
  GTEST_SKIP() << "protobuf/flatbuffers not found: nns_wire not built";
}
#endif
