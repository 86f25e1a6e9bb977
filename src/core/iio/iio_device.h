// SPDX-License-Identifier: LGPL-2.1-only
// A Linux IIO device as seen through sysfs (<iio-base-dir>/iio:deviceN) and its buffered
// character device (<dev-dir>/iio:deviceN): finding it by name or number, reading and enabling
// its scan channels, trigger, sampling frequency and buffer length, and putting every setting
// back as it was found. Every error names the file involved. GStreamer-free.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/iio/iio_channel.h"

namespace nns::iio {

struct DeviceSettings {
  std::string base_dir = "/sys/bus/iio/devices";
  std::string dev_dir = "/dev";
  std::string device;       // name (sysfs "name" file), or empty
  int device_number = -1;   // used when `device` is empty
  std::string trigger;      // name, or empty
  int trigger_number = -1;  // used when `trigger` is empty; -1 = no trigger
  // Channel selection: "auto" (those enabled, or all when none is), "all", or index list.
  enum class Channels { kAuto, kAll, kList } channels = Channels::kAuto;
  std::set<unsigned> channel_list;
  unsigned buffer_capacity = 1;
  uint64_t frequency = 0;  // 0: the first available one (or the current one)
};

// Parses the `channels` property ("auto", "all", "0,2,3"); throws naming the bad token.
void parse_channels(const std::string &text, DeviceSettings &s);
std::string channels_to_string(const DeviceSettings &s);

class Device {
 public:
  // Finds the device and trigger and reads every channel; changes nothing yet.
  explicit Device(const DeviceSettings &s);
  ~Device();  // restore() if configure() ran
  Device(const Device &) = delete;
  Device &operator=(const Device &) = delete;

  // Buffered mode: enables the chosen channels, sets the trigger, the sampling frequency and
  // the buffer length, lays out the scan. Throws naming the file that failed.
  void configure_buffered();
  // One-shot mode: chooses the channels (nothing is written) and checks each has a _raw file.
  void configure_one_shot();
  // Puts channels, trigger, frequency and buffer length back as found. Never throws.
  void restore() noexcept;

  void enable_buffer(bool on);  // buffer/enable
  // Opens <dev-dir>/iio:deviceN non-blocking; returns the fd (owned by the caller).
  int open_buffer() const;
  // Reads <device>/<channel>_raw of every output channel and converts it (one-shot mode).
  void read_one_shot(float *out) const;

  const std::string &name() const { return name_; }
  int number() const { return number_; }
  const std::string &dir() const { return dir_; }
  std::string buffer_path() const;
  bool has_trigger() const { return !trigger_name_.empty(); }
  uint64_t frequency() const { return frequency_; }
  std::size_t scan_size() const { return scan_size_; }
  // Channels that produce output (enabled, not the timestamp), in index order.
  const std::vector<const Channel *> &outputs() const { return outputs_; }

 private:
  void read_channels();
  void choose_channels(bool write);
  void setup_trigger();
  void setup_frequency();
  void collect_outputs();

  DeviceSettings s_;
  std::string name_;
  int number_ = -1;
  std::string dir_;
  std::string trigger_name_;
  std::vector<Channel> channels_;
  std::vector<const Channel *> outputs_;
  std::size_t scan_size_ = 0;
  uint64_t frequency_ = 0;
  // What restore() puts back.
  bool configured_ = false;
  std::optional<std::string> old_trigger_;
  std::optional<std::string> old_frequency_;
  std::optional<std::string> old_length_;
};

// Small sysfs helpers (exposed for tests): whole-file read without the trailing newline, and a
// write of `value`. Both throw nns::Error naming `path`.
std::string read_attr(const std::string &path);
void write_attr(const std::string &path, const std::string &value);

}  // namespace nns::iio
