// SPDX-License-Identifier: LGPL-2.1-only
#include "common.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <stdexcept>

#include "../common/run_to_eos.h"
#include "core/meta_header.h"
#include "core/tensor_info.h"

namespace paper {

RecordFile::RecordFile(const std::string &path, std::size_t record_bytes) : bytes_(record_bytes) {
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0) throw std::runtime_error("cannot open recorded input " + path);
  struct stat st {};
  fstat(fd_, &st);
  count_ = static_cast<std::size_t>(st.st_size) / bytes_;
}

RecordFile::~RecordFile() {
  if (fd_ >= 0) ::close(fd_);
}

void RecordFile::read(std::size_t i, void *dst) const {
  const auto off = static_cast<off_t>(i * bytes_);
  if (::pread(fd_, dst, bytes_, off) != static_cast<ssize_t>(bytes_))
    throw std::runtime_error("short read of record " + std::to_string(i));
}

Dumper::~Dumper() {
  for (auto &[k, f] : files_) std::fclose(f);
}

void Dumper::write(const std::string &name, const float *v, std::size_t n) {
  if (!on()) return;
  std::lock_guard lk(mu_);
  FILE *&f = files_[name];
  if (!f) f = std::fopen((prefix_ + "." + name + ".f32").c_str(), "wb");
  if (f) std::fwrite(v, sizeof(float), n, f);
}

void Dumper::write(const std::string &name, const Ort::Value &v) {
  if (!on()) return;
  std::vector<float> f = to_floats(v);
  write(name, f.data(), f.size());
}

namespace {

Ort::Env &env() {
  static Ort::Env e(ORT_LOGGING_LEVEL_WARNING, "paper");
  return e;
}

template <typename T>
void append(const void *p, std::size_t n, std::vector<float> &out) {
  const T *t = static_cast<const T *>(p);
  for (std::size_t i = 0; i < n; ++i) out.push_back(static_cast<float>(t[i]));
}

void append_nns(nns::TensorType t, const uint8_t *p, std::size_t bytes, std::vector<float> &out) {
  using nns::TensorType;
  const std::size_t n = bytes / std::max<std::size_t>(1, nns::type_size(t));
  switch (t) {
    case TensorType::kInt32:
      append<int32_t>(p, n, out);
      break;
    case TensorType::kUInt32:
      append<uint32_t>(p, n, out);
      break;
    case TensorType::kInt16:
      append<int16_t>(p, n, out);
      break;
    case TensorType::kUInt16:
      append<uint16_t>(p, n, out);
      break;
    case TensorType::kInt8:
      append<int8_t>(p, n, out);
      break;
    case TensorType::kUInt8:
      append<uint8_t>(p, n, out);
      break;
    case TensorType::kFloat64:
      append<double>(p, n, out);
      break;
    case TensorType::kFloat32:
      append<float>(p, n, out);
      break;
    case TensorType::kInt64:
      append<int64_t>(p, n, out);
      break;
    case TensorType::kUInt64:
      append<uint64_t>(p, n, out);
      break;
    default:
      break;
  }
}

}  // namespace

std::vector<float> to_floats(const Ort::Value &v) {
  auto info = v.GetTensorTypeAndShapeInfo();
  const std::size_t n = info.GetElementCount();
  const void *p = v.GetTensorRawData();
  std::vector<float> out;
  out.reserve(n);
  switch (info.GetElementType()) {
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_FLOAT:
      append<float>(p, n, out);
      break;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_UINT8:
      append<uint8_t>(p, n, out);
      break;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT8:
      append<int8_t>(p, n, out);
      break;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT16:
      append<int16_t>(p, n, out);
      break;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT32:
      append<int32_t>(p, n, out);
      break;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_UINT32:
      append<uint32_t>(p, n, out);
      break;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT64:
      append<int64_t>(p, n, out);
      break;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_DOUBLE:
      append<double>(p, n, out);
      break;
    default:
      throw std::runtime_error("dump: unsupported ONNX element type");
  }
  return out;
}

OrtModel::OrtModel(const std::string &path) {
  Ort::SessionOptions so;
  so.SetIntraOpNumThreads(ort_threads());
  so.SetInterOpNumThreads(1);
  session_ = std::make_unique<Ort::Session>(env(), path.c_str(), so);
  Ort::AllocatorWithDefaultOptions a;
  for (std::size_t i = 0; i < session_->GetInputCount(); ++i)
    in_names_.push_back(session_->GetInputNameAllocated(i, a).get());
  for (std::size_t i = 0; i < session_->GetOutputCount(); ++i)
    out_names_.push_back(session_->GetOutputNameAllocated(i, a).get());
  for (auto &s : in_names_) in_ptrs_.push_back(s.c_str());
  for (auto &s : out_names_) out_ptrs_.push_back(s.c_str());
}

std::vector<Ort::Value> OrtModel::run(const std::vector<Ort::Value> &inputs) {
  if (inputs.size() != in_ptrs_.size())
    throw std::runtime_error("model takes " + std::to_string(in_ptrs_.size()) + " inputs, got " +
                             std::to_string(inputs.size()));
  return session_->Run(Ort::RunOptions{nullptr}, in_ptrs_.data(), inputs.data(), inputs.size(),
                       out_ptrs_.data(), out_ptrs_.size());
}

const OrtMemoryInfo *OrtModel::cpu() {
  static Ort::MemoryInfo m = Ort::MemoryInfo::CreateCpu(OrtArenaAllocator, OrtMemTypeDefault);
  return m;
}

std::vector<std::vector<float>> buffer_tensors(GstBuffer *buf, GstCaps *caps) {
  std::vector<nns::TensorType> types;
  if (caps && gst_caps_get_size(caps) > 0) {
    const GstStructure *s = gst_caps_get_structure(caps, 0);
    const char *t = gst_structure_get_string(s, "types");
    if (!t) t = gst_structure_get_string(s, "type");
    if (t)
      for (const auto &name : nns::split(t, ",")) types.push_back(nns::parse_type(nns::trim(name)));
  }
  std::vector<std::vector<float>> out;
  for (guint i = 0; i < gst_buffer_n_memory(buf); ++i) {
    GstMemory *mem = gst_buffer_peek_memory(buf, i);
    GstMapInfo map;
    if (!gst_memory_map(mem, &map, GST_MAP_READ)) continue;
    std::vector<float> v;
    if (nns::has_meta_header(map.data, map.size)) {
      nns::MetaHeader h = nns::parse_meta_header(map.data, map.size);
      append_nns(h.type, map.data + nns::kMetaHeaderSize, map.size - nns::kMetaHeaderSize, v);
    } else if (i < types.size()) {
      append_nns(types[i], map.data, map.size, v);
    }
    gst_memory_unmap(mem, &map);
    out.push_back(std::move(v));
  }
  return out;
}

struct GstRun::SinkCtx {
  GstRun *run = nullptr;
  std::string name;
  std::size_t count = 0;
  std::function<void(GstBuffer *)> fn;
};

struct GstRun::StampCtx {
  GstRun *run = nullptr;
  int slot = 0;
};

GstRun::GstRun(const std::string &description) {
  GError *err = nullptr;
  pipeline_ = gst_parse_launch(description.c_str(), &err);
  if (err) {
    std::string m = err->message;
    g_error_free(err);
    if (pipeline_) gst_object_unref(pipeline_);
    pipeline_ = nullptr;
    throw std::runtime_error("pipeline does not parse: " + m + "\n  " + description);
  }
}

GstRun::~GstRun() {
  if (pipeline_) {
    gst_element_set_state(pipeline_, GST_STATE_NULL);
    gst_object_unref(pipeline_);
  }
}

GstElement *GstRun::element(const char *name) {
  GstElement *e = gst_bin_get_by_name(GST_BIN(pipeline_), name);
  if (!e) throw std::runtime_error(std::string("pipeline has no element named ") + name);
  gst_object_unref(e);  // the bin keeps it
  return e;
}

void GstRun::on_sink(const char *name, std::function<void(GstBuffer *)> fn) {
  auto ctx = std::make_unique<SinkCtx>();
  ctx->run = this;
  ctx->name = name;
  ctx->fn = std::move(fn);
  auto cb = +[](GstElement *, GstBuffer *buf, gpointer data) {
    auto *c = static_cast<SinkCtx *>(data);
    {
      const double t = seconds_since(c->run->t0_), cpu = cpu_seconds();
      std::lock_guard lk(c->run->mu_);
      ++c->count;
      c->run->last_t_ = std::max(c->run->last_t_, t);
      c->run->last_cpu_ = std::max(c->run->last_cpu_, cpu);
    }
    try {  // exceptions must not cross into GLib
      if (c->fn) c->fn(buf);
    } catch (const std::exception &e) {
      g_printerr("nns-paper: sink %s: %s\n", c->name.c_str(), e.what());
      std::lock_guard lk(c->run->mu_);
      c->run->callback_error_ = c->name + ": " + e.what();
    }
  };
  g_signal_connect(element(name), "new-data", G_CALLBACK(cb), ctx.get());
  sinks_.push_back(std::move(ctx));
}

void GstRun::dump_sink(const char *name, Dumper &d, const std::string &as) {
  GstElement *sink = element(name);
  std::string n = as.empty() ? name : as;
  on_sink(name, [sink, n, &d](GstBuffer *buf) {
    GstPad *pad = gst_element_get_static_pad(sink, "sink");
    GstCaps *caps = gst_pad_get_current_caps(pad);
    auto t = buffer_tensors(buf, caps);
    if (caps) gst_caps_unref(caps);
    gst_object_unref(pad);
    for (std::size_t i = 0; i < t.size(); ++i)
      d.write(n + "." + std::to_string(i), t[i].data(), t[i].size());
  });
}

void GstRun::stamp(const char *element_name, const char *pad_name, int slot) {
  GstPad *pad = gst_element_get_static_pad(element(element_name), pad_name);
  if (!pad) throw std::runtime_error(std::string("no pad ") + pad_name + " on " + element_name);
  auto ctx = std::make_unique<StampCtx>();
  ctx->run = this;
  ctx->slot = slot;
  auto cb = +[](GstPad *, GstPadProbeInfo *info, gpointer data) -> GstPadProbeReturn {
    auto *c = static_cast<StampCtx *>(data);
    GstBuffer *buf = GST_PAD_PROBE_INFO_BUFFER(info);
    if (buf && GST_BUFFER_PTS_IS_VALID(buf)) {
      const double t = seconds_since(c->run->t0_);
      std::lock_guard lk(c->run->mu_);
      if (!c->run->first_set_) {
        c->run->first_set_ = true;
        c->run->first_t_ = t;
        c->run->first_cpu_ = cpu_seconds();
        c->run->first_sched_ = SchedSnapshot::now();
      }
      c->run->times_[GST_BUFFER_PTS(buf)].emplace(c->slot, t);  // first arrival only
      c->run->last_t_ = std::max(c->run->last_t_, t);
      c->run->last_cpu_ = std::max(c->run->last_cpu_, cpu_seconds());
    }
    return GST_PAD_PROBE_OK;
  };
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, cb, ctx.get(), nullptr);
  gst_object_unref(pad);
  stamps_.push_back(std::move(ctx));
}

std::string GstRun::run(int timeout_s) {
  t0_ = Clock::now();
  std::string err = nns_example::run_to_eos(pipeline_, timeout_s, "no EOS before the timeout");
  end_sched_ = SchedSnapshot::now();  // at EOS: the streaming threads still exist
  std::lock_guard lk(mu_);
  return err.empty() && !callback_error_.empty() ? "output callback failed: " + callback_error_
                                                 : err;
}

std::size_t GstRun::count(const std::string &sink) const {
  std::lock_guard lk(mu_);
  for (const auto &s : sinks_)
    if (s->name == sink) return s->count;
  return 0;
}

double GstRun::wall() const {
  std::lock_guard lk(mu_);
  return last_t_ - first_t_;
}

void GstRun::add_usage(Result &r) const {
  std::lock_guard lk(mu_);
  r.add_usage(last_t_ - first_t_, last_cpu_ - first_cpu_, first_sched_, end_sched_);
}

Samples GstRun::between(int a, int b) const {
  std::lock_guard lk(mu_);
  Samples s;
  for (const auto &[pts, slots] : times_) {
    auto ia = slots.find(a), ib = slots.find(b);
    if (ia != slots.end() && ib != slots.end()) s.add(1000.0 * (ib->second - ia->second));
  }
  return s;
}

std::size_t GstRun::count_slot(int slot) const {
  std::lock_guard lk(mu_);
  std::size_t n = 0;
  for (const auto &[pts, slots] : times_) n += slots.count(slot);
  return n;
}

namespace {
int g_ort_threads = 1;
}

void set_ort_threads(int n) {
  g_ort_threads = n > 0 ? n : 1;
}
int ort_threads() {
  return g_ort_threads;
}

std::string ort_filter(const std::string &model, const std::string &extra) {
  return "filter framework=onnxruntime model=" + model +
         " custom=NumThreads:" + std::to_string(g_ort_threads) + ",InterOpNumThreads:1" +
         (extra.empty() ? "" : " " + extra);
}

void warm_file(const std::string &path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return;  // the run itself names a missing input
  std::vector<char> buf(1 << 20);
  while (::read(fd, buf.data(), buf.size()) > 0) {
  }
  ::close(fd);
}

}  // namespace paper
