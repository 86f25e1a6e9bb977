// SPDX-License-Identifier: LGPL-2.1-only
#include "core/time_sync.h"

#include <algorithm>
#include <array>
#include <charconv>

#include "core/error.h"
#include "core/tensor_info.h"

namespace nns {
namespace {

constexpr std::array<std::string_view, 4> kModeNames = {"nosync", "slowest", "basepad", "refresh"};

uint64_t absdiff(uint64_t a, uint64_t b) {
  return a > b ? a - b : b - a;
}

uint64_t parse_u64(std::string_view tok, std::string_view what) {
  std::string t = trim(tok);
  uint64_t v = 0;
  auto [p, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc() || p != t.data() + t.size())
    fail(ErrorKind::kSettings,
         "sync-option: " + std::string(what) + " '" + t + "' is not a non-negative integer");
  return v;
}

}  // namespace

std::optional<SyncMode> sync_mode_from_name(std::string_view s) {
  std::string t = trim(s);
  for (std::size_t i = 0; i < kModeNames.size(); ++i)
    if (t == kModeNames[i]) return static_cast<SyncMode>(i);
  return std::nullopt;
}

std::string_view sync_mode_name(SyncMode m) {
  return kModeNames[static_cast<std::size_t>(m)];
}

SyncOption parse_sync_option(SyncMode mode, std::string_view s) {
  SyncOption o;
  if (mode != SyncMode::kBasePad || trim(s).empty()) return o;
  auto parts = split(s, ":", true);
  if (parts.size() > 2)
    fail(ErrorKind::kSettings, "sync-option '" + std::string(s) +
                                   "' must be <sink_id>:<duration_ns> for sync-mode=basepad");
  uint64_t id = parse_u64(parts[0], "sink id");
  if (id > UINT32_MAX) fail(ErrorKind::kSettings, "sync-option: sink id is too large");
  o.sink_id = static_cast<uint32_t>(id);
  if (parts.size() == 2) o.duration = parse_u64(parts[1], "duration");
  return o;
}

bool TimeSync::pick_time(SyncInputs &in) {
  std::size_t empty = 0;
  const std::size_t n = in.count();
  for (std::size_t i = 0; i < n; ++i) {
    auto h = in.head_pts(i);
    if (!h) {
      ++empty;
      continue;
    }
    bool update = mode_ == SyncMode::kBasePad ? i == option_.sink_id : current_ < *h;
    if (update) {
      current_ = *h;
      in.set_time_source(i);
    }
  }
  return mode_ == SyncMode::kRefresh ? empty < n : empty == 0;
}

SyncResult TimeSync::step(SyncInputs &in) {
  const std::size_t n = in.count();
  if (n == 0) return SyncResult::kEos;
  if (need_time_) {
    if (!pick_time(in)) return SyncResult::kEos;
    need_time_ = false;
  }

  // basepad: a new buffer of another pad is used only within this distance of the base time,
  // at most the base pad's own gap between its queued and its last buffer (minus 1 ns).
  uint64_t tolerance = 0;
  if (mode_ == SyncMode::kBasePad && option_.sink_id < n) {
    auto h = in.head_pts(option_.sink_id);
    auto l = in.last_pts(option_.sink_id);
    if (h && l) {
      int64_t gap = static_cast<int64_t>(absdiff(*h, *l)) - 1;
      int64_t limit = option_.duration > static_cast<uint64_t>(INT64_MAX)
                          ? INT64_MAX
                          : static_cast<int64_t>(option_.duration);
      tolerance = static_cast<uint64_t>(std::min(limit, gap));
    }
  }

  std::size_t empty = 0;
  for (std::size_t i = 0; i < n; ++i) {
    switch (mode_) {
      case SyncMode::kSlowest:
      case SyncMode::kBasePad: {
        auto h = in.head_pts(i);
        if (h) {
          if (*h < current_) {
            in.take_head(i);  // older than the base time: drop the previous, keep this one
            return SyncResult::kNeedData;
          }
          auto l = in.last_pts(i);
          bool keep_last = false;
          if (l && mode_ == SyncMode::kSlowest)
            keep_last = absdiff(current_, *l) < absdiff(current_, *h);
          else if (l)
            keep_last = absdiff(current_, *h) > tolerance;
          if (!keep_last) in.take_head(i);
        }
        if (!in.last_pts(i)) ++empty;
        break;
      }
      case SyncMode::kNoSync:
        if (in.head_pts(i))
          in.take_head(i);
        else
          ++empty;
        break;
      case SyncMode::kRefresh:
        // New buffers replace the last ones; a pad without any buffer yet blocks the output
        // (checked below, after every new buffer has been kept).
        if (in.head_pts(i))
          in.take_head(i);
        else
          ++empty;
        break;
    }
  }
  if (mode_ == SyncMode::kRefresh) {
    // Every pad ended, some of them without ever having data: no output can be built, and
    // waiting for data would wait forever.
    if (empty == n) return SyncResult::kEos;
    for (std::size_t i = 0; i < n; ++i)
      if (!in.last_pts(i)) return SyncResult::kNeedData;  // not every pad has data yet
  }
  bool eos = mode_ == SyncMode::kRefresh ? empty == n : empty > 0;
  if (eos) return SyncResult::kEos;
  need_time_ = true;
  return SyncResult::kOutput;
}

}  // namespace nns
