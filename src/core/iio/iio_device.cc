// SPDX-License-Identifier: LGPL-2.1-only
#include "core/iio/iio_device.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/tensor_info.h"

namespace nns::iio {

namespace {

bool is_dir(const std::string &p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool is_file(const std::string &p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && !S_ISDIR(st.st_mode);
}

std::vector<std::string> list_dir(const std::string &dir) {
  std::vector<std::string> names;
  DIR *d = ::opendir(dir.c_str());
  if (!d) fail(ErrorKind::kNotFound, "cannot open folder " + dir + ": " + std::strerror(errno));
  while (const dirent *e = ::readdir(d)) {
    if (e->d_name[0] != '.') names.emplace_back(e->d_name);
  }
  ::closedir(d);
  std::sort(names.begin(), names.end());
  return names;
}

bool ends_with(const std::string &s, const std::string &suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// "<prefix><digits>" -> digits as int, else -1.
int numbered(const std::string &entry, const std::string &prefix) {
  if (entry.compare(0, prefix.size(), prefix) != 0 || entry.size() == prefix.size()) return -1;
  int v = 0;
  for (std::size_t i = prefix.size(); i < entry.size(); ++i) {
    if (entry[i] < '0' || entry[i] > '9' || v > 100000000) return -1;
    v = v * 10 + (entry[i] - '0');
  }
  return v;
}

uint64_t parse_u64(const std::string &text, const std::string &path) {
  errno = 0;
  char *end = nullptr;
  unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (errno || end == text.c_str() || (*end && *end != ' ' && *end != '\n'))
    fail(ErrorKind::kSettings, "expected an unsigned number in " + path + ", got '" + text + "'");
  return v;
}

float parse_float(const std::string &text, const std::string &path) {
  errno = 0;
  char *end = nullptr;
  double v = std::strtod(text.c_str(), &end);
  if (errno || end == text.c_str())
    fail(ErrorKind::kSettings, "expected a number in " + path + ", got '" + text + "'");
  return static_cast<float>(v);
}

// The names an attribute of `channel` may be found under, most specific first: "in_voltage0",
// then without the channel number ("in_voltage"), then without the last modifier
// ("in_accel_x" -> "in_accel"), as the kernel shares attributes between channels.
std::vector<std::string> attr_names(const std::string &channel) {
  std::vector<std::string> out{channel};
  std::string s = channel;
  while (!s.empty() && s.back() >= '0' && s.back() <= '9') s.pop_back();
  if (!s.empty() && s != channel) out.push_back(s);
  auto us = s.rfind('_');
  if (us != std::string::npos && us > 0) {
    std::string shorter = s.substr(0, us);
    if (shorter.find('_') != std::string::npos && shorter != out.back()) out.push_back(shorter);
  }
  return out;
}

// Value of the first existing <dir>/<name><suffix> among attr_names(channel), or nullopt.
std::optional<std::string> shared_attr(const std::string &dir, const std::string &channel,
                                       const std::string &suffix, std::string *path_out) {
  for (const auto &n : attr_names(channel)) {
    std::string p = dir + "/" + n + suffix;
    if (is_file(p)) {
      if (path_out) *path_out = p;
      return read_attr(p);
    }
  }
  return std::nullopt;
}

bool is_timestamp(const std::string &name) {
  return name == "timestamp" || ends_with(name, "_timestamp");
}

}  // namespace

std::string read_attr(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) fail(ErrorKind::kNotFound, "cannot read " + path + ": " + std::strerror(errno));
  std::ostringstream ss;
  ss << f.rdbuf();
  std::string s = ss.str();
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  return s;
}

void write_attr(const std::string &path, const std::string &value) {
  int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0) fail(ErrorKind::kLibrary, "cannot write " + path + ": " + std::strerror(errno));
  ssize_t n = ::write(fd, value.data(), value.size());
  int err = errno;
  ::close(fd);
  if (n != static_cast<ssize_t>(value.size()))
    fail(ErrorKind::kLibrary, "cannot write '" + value + "' to " + path + ": " +
                                  (n < 0 ? std::strerror(err) : "short write"));
}

void parse_channels(const std::string &text, DeviceSettings &s) {
  std::string t = trim(text);
  if (t == "auto" || t.empty()) {
    s.channels = DeviceSettings::Channels::kAuto;
    return;
  }
  if (t == "all") {
    s.channels = DeviceSettings::Channels::kAll;
    return;
  }
  std::set<unsigned> list;
  for (const auto &tok : split(t, ",;")) {
    char *end = nullptr;
    errno = 0;
    long v = std::strtol(tok.c_str(), &end, 10);
    if (tok.empty() || errno || *end || v < 0 || v > 65535)
      fail(ErrorKind::kSettings, "channels: '" + tok + "' in '" + text +
                                     "' is not a channel index (expected auto, all, or a "
                                     "list of indices such as 0,1,3)");
    list.insert(static_cast<unsigned>(v));
  }
  s.channels = DeviceSettings::Channels::kList;
  s.channel_list = std::move(list);
}

std::string channels_to_string(const DeviceSettings &s) {
  if (s.channels == DeviceSettings::Channels::kAll) return "all";
  if (s.channels == DeviceSettings::Channels::kAuto) return "auto";
  std::vector<std::string> v;
  for (unsigned i : s.channel_list) v.push_back(std::to_string(i));
  return join(v, ",");
}

Device::Device(const DeviceSettings &s) : s_(s) {
  if (!is_dir(s_.base_dir))
    fail(ErrorKind::kNotFound, "iio-base-dir " + s_.base_dir + " is not a folder");
  if (!s_.device.empty()) {
    for (const auto &e : list_dir(s_.base_dir)) {
      int n = numbered(e, "iio:device");
      if (n < 0 || !is_file(s_.base_dir + "/" + e + "/name")) continue;
      if (read_attr(s_.base_dir + "/" + e + "/name") == s_.device) {
        number_ = n;
        break;
      }
    }
    if (number_ < 0)
      fail(ErrorKind::kNotFound, "device: no IIO device named '" + s_.device + "' in " +
                                     s_.base_dir + " (no iio:deviceN/name holds that name)");
    name_ = s_.device;
  } else if (s_.device_number >= 0) {
    number_ = s_.device_number;
    std::string p = s_.base_dir + "/iio:device" + std::to_string(number_) + "/name";
    if (!is_file(p))
      fail(ErrorKind::kNotFound, "device-number: no IIO device " + std::to_string(number_) + " (" +
                                     p + " does not exist)");
    name_ = read_attr(p);
  } else {
    fail(ErrorKind::kSettings, "set the device property (IIO device name) or device-number");
  }
  dir_ = s_.base_dir + "/iio:device" + std::to_string(number_);
  read_channels();
}

Device::~Device() {
  restore();
}

std::string Device::buffer_path() const {
  return s_.dev_dir + "/iio:device" + std::to_string(number_);
}

void Device::read_channels() {
  const std::string scan = dir_ + "/scan_elements";
  if (!is_dir(scan))
    fail(ErrorKind::kNotFound,
         "IIO device '" + name_ + "' has no " + scan + " folder (not a buffered device)");
  for (const auto &e : list_dir(scan)) {
    if (!ends_with(e, "_en")) continue;
    Channel ch;
    ch.name = e.substr(0, e.size() - 3);
    ch.timestamp = is_timestamp(ch.name);
    const std::string en_path = scan + "/" + e;
    std::string en = read_attr(en_path);
    if (en != "0" && en != "1")
      fail(ErrorKind::kSettings, "expected 0 or 1 in " + en_path + ", got '" + en + "'");
    ch.enabled = ch.was_enabled = en == "1";
    const std::string idx_path = scan + "/" + ch.name + "_index";
    ch.index = static_cast<unsigned>(parse_u64(read_attr(idx_path), idx_path));
    std::string type_path;
    auto type = shared_attr(scan, ch.name, "_type", &type_path);
    if (!type)
      fail(ErrorKind::kNotFound, "channel " + ch.name + " has no type file (" + scan + "/" +
                                     ch.name + "_type does not exist)");
    ch.type = parse_channel_type(*type, type_path);
    std::string p;
    if (auto v = shared_attr(dir_, ch.name, "_scale", &p)) ch.scale = parse_float(*v, p);
    if (auto v = shared_attr(dir_, ch.name, "_offset", &p)) ch.offset = parse_float(*v, p);
    channels_.push_back(std::move(ch));
  }
  std::stable_sort(channels_.begin(), channels_.end(),
                   [](const Channel &a, const Channel &b) { return a.index < b.index; });
}

void Device::choose_channels(bool write) {
  const bool any_enabled = std::any_of(channels_.begin(), channels_.end(),
                                       [](const Channel &c) { return c.enabled && !c.timestamp; });
  std::set<unsigned> known;
  for (auto &ch : channels_) {
    known.insert(ch.index);
    if (ch.timestamp) continue;  // left as found: laid out when enabled, never output
    bool want = ch.enabled;
    switch (s_.channels) {
      case DeviceSettings::Channels::kAll:
        want = true;
        break;
      case DeviceSettings::Channels::kAuto:
        want = any_enabled ? ch.enabled : true;
        break;
      case DeviceSettings::Channels::kList:
        want = s_.channel_list.count(ch.index) > 0;
        break;
    }
    if (write && want != ch.enabled) {
      write_attr(dir_ + "/scan_elements/" + ch.name + "_en", want ? "1" : "0");
      configured_ = true;  // restore() now has something to put back
    }
    ch.enabled = want;
  }
  if (s_.channels == DeviceSettings::Channels::kList) {
    for (unsigned i : s_.channel_list) {
      if (!known.count(i)) {
        std::vector<std::string> idx;
        for (unsigned k : known) idx.push_back(std::to_string(k));
        fail(ErrorKind::kSettings, "channels: IIO device '" + name_ + "' has no channel index " +
                                       std::to_string(i) + " (its indices: " + join(idx, ",") +
                                       ")");
      }
    }
  }
  collect_outputs();
  if (outputs_.empty())
    fail(ErrorKind::kSettings, "IIO device '" + name_ + "': no channel to read (" + dir_ +
                                   "/scan_elements has no usable *_en channel)");
}

void Device::collect_outputs() {
  outputs_.clear();
  for (const auto &ch : channels_)
    if (ch.enabled && !ch.timestamp) outputs_.push_back(&ch);
}

void Device::setup_trigger() {
  if (s_.trigger.empty() && s_.trigger_number < 0) return;
  const std::string tdir = dir_ + "/trigger";
  if (!is_dir(tdir))
    fail(ErrorKind::kSettings,
         "trigger: IIO device '" + name_ + "' takes no trigger (" + tdir + " does not exist)");
  std::string tname;
  if (!s_.trigger.empty()) {
    for (const auto &e : list_dir(s_.base_dir)) {
      // "triggerN" as the kernel names it; "iio:triggerN" as NNStreamer's tests (and element)
      // name it.
      if ((numbered(e, "trigger") < 0 && numbered(e, "iio:trigger") < 0) ||
          !is_file(s_.base_dir + "/" + e + "/name"))
        continue;
      if (read_attr(s_.base_dir + "/" + e + "/name") == s_.trigger) tname = s_.trigger;
    }
    if (tname.empty())
      fail(ErrorKind::kNotFound, "trigger: no IIO trigger named '" + s_.trigger + "' in " +
                                     s_.base_dir + " (no triggerN/name holds that name)");
  } else {
    std::string p = s_.base_dir + "/trigger" + std::to_string(s_.trigger_number) + "/name";
    const std::string upstream_p =
        s_.base_dir + "/iio:trigger" + std::to_string(s_.trigger_number) + "/name";
    if (!is_file(p) && is_file(upstream_p)) p = upstream_p;
    if (!is_file(p))
      fail(ErrorKind::kNotFound, "trigger-number: no IIO trigger " +
                                     std::to_string(s_.trigger_number) + " (" + p +
                                     " does not exist)");
    tname = read_attr(p);
  }
  const std::string cur = tdir + "/current_trigger";
  old_trigger_ = is_file(cur) ? read_attr(cur) : std::string();
  configured_ = true;
  write_attr(cur, tname);
  trigger_name_ = tname;
}

void Device::setup_frequency() {
  const std::string avail = dir_ + "/sampling_frequency_available";
  const std::string cur = dir_ + "/sampling_frequency";
  uint64_t current = 0;
  if (is_file(cur)) {
    old_frequency_ = read_attr(cur);
    // Some drivers report a fractional rate ("100.000000"): take the integer part. An empty file
    // (NNStreamer's test trees) means unknown.
    if (!old_frequency_->empty())
      current = static_cast<uint64_t>(parse_float(*old_frequency_, cur));
  }
  uint64_t f = s_.frequency;
  if (is_file(avail)) {
    auto list = split(read_attr(avail), " \t");
    if (list.empty()) fail(ErrorKind::kSettings, avail + " lists no sampling frequency");
    if (f == 0) {
      f = static_cast<uint64_t>(parse_float(list[0], avail));
    } else {
      bool ok = std::any_of(list.begin(), list.end(), [&](const std::string &x) {
        return static_cast<uint64_t>(parse_float(x, avail)) == f;
      });
      if (!ok)
        fail(ErrorKind::kSettings, "frequency " + std::to_string(f) + " is not supported by '" +
                                       name_ + "' (" + avail + ": " + join(list, " ") + ")");
    }
  } else if (f == 0) {
    f = current;
  }
  if (f == 0)
    fail(ErrorKind::kSettings, "frequency: the sampling frequency of '" + name_ +
                                   "' is unknown (neither " + avail + " nor " + cur +
                                   " gives one); set the frequency property");
  if (is_file(cur) && f != current) {
    configured_ = true;
    write_attr(cur, std::to_string(f));
  }
  frequency_ = f;
}

void Device::configure_buffered() {
  setup_trigger();
  setup_frequency();
  choose_channels(true);
  scan_size_ = layout_scan(channels_);
  collect_outputs();  // layout_scan keeps the order; refresh the pointers anyway
  const std::string len = dir_ + "/buffer/length";
  if (!is_file(len))
    fail(ErrorKind::kNotFound,
         "IIO device '" + name_ + "' has no " + len + " (not a buffered device)");
  old_length_ = read_attr(len);
  configured_ = true;
  write_attr(len, std::to_string(s_.buffer_capacity));
}

void Device::configure_one_shot() {
  setup_frequency();
  choose_channels(false);
  for (const auto *ch : outputs_) {
    std::string p = dir_ + "/" + ch->name + "_raw";
    if (!is_file(p))
      fail(ErrorKind::kNotFound, "mode=one-shot: channel " + ch->name + " has no " + p);
  }
}

void Device::read_one_shot(float *out) const {
  std::size_t i = 0;
  for (const auto *ch : outputs_) {
    std::string p = dir_ + "/" + ch->name + "_raw";
    std::string text = read_attr(p);
    errno = 0;
    char *end = nullptr;
    long long raw = std::strtoll(text.c_str(), &end, 10);
    if (errno || end == text.c_str() || *end)
      fail(ErrorKind::kStream, "expected an integer in " + p + ", got '" + text + "'");
    out[i++] = (static_cast<float>(raw) + ch->offset) * ch->scale;
  }
}

void Device::enable_buffer(bool on) {
  write_attr(dir_ + "/buffer/enable", on ? "1" : "0");
}

int Device::open_buffer() const {
  const std::string p = buffer_path();
  int fd = ::open(p.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0)
    fail(ErrorKind::kNotFound, "cannot open the buffer of IIO device '" + name_ + "' (" + p +
                                   "): " + std::strerror(errno));
  return fd;
}

void Device::restore() noexcept {
  if (!configured_) return;
  configured_ = false;
  auto put = [](const std::string &path, const std::string &v) {
    try {
      write_attr(path, v);
    } catch (...) {
    }
  };
  for (auto &ch : channels_) {
    if (ch.timestamp || ch.enabled == ch.was_enabled) continue;
    put(dir_ + "/scan_elements/" + ch.name + "_en", ch.was_enabled ? "1" : "0");
    ch.enabled = ch.was_enabled;
  }
  if (old_frequency_) put(dir_ + "/sampling_frequency", *old_frequency_);
  if (old_length_) put(dir_ + "/buffer/length", *old_length_);
  if (old_trigger_) put(dir_ + "/trigger/current_trigger", *old_trigger_);
  old_frequency_.reset();
  old_length_.reset();
  old_trigger_.reset();
}

}  // namespace nns::iio
