// SPDX-License-Identifier: LGPL-2.1-only
// Shared by the paper experiments (examples/paper): options, recorded-input readers, the
// ONNX Runtime session the Control programs call by hand, the GStreamer runner of the pipeline
// versions (tensor_sink callbacks, per-frame time stamps at pads keyed by PTS) and the output
// dumps that let run.sh check that a pipeline and its Control compute the same outputs.
#pragma once

#include <gst/gst.h>
#include <onnxruntime_cxx_api.h>

#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "measure.h"

namespace paper {

struct Options {
  std::string exp;           // e1 .. e4
  std::string mode = "nns";  // nns | control
  std::string config;        // experiment-specific (models, size, ...)
  std::string models;        // folder of make_models.py output
  std::string inputs;        // folder of make_inputs.py output
  std::string out;           // result JSON lines (appended); "" = stdout only
  std::string dump;          // prefix of output dumps ("" = none)
  int frames = 0;            // 0 = the whole recorded input
  bool live = false;         // pace the input at its frame rate (30 fps)
  double rate = 30;          // frame rate of the paced input
  int timeout_s = 300;
};

// Reads fixed-size records (frames, audio chunks) of a raw file by index.
class RecordFile {
 public:
  RecordFile(const std::string &path, std::size_t record_bytes);
  ~RecordFile();
  RecordFile(const RecordFile &) = delete;
  RecordFile &operator=(const RecordFile &) = delete;
  std::size_t count() const { return count_; }
  std::size_t record_bytes() const { return bytes_; }
  // Copies record i into dst (record_bytes() bytes).
  void read(std::size_t i, void *dst) const;

 private:
  int fd_ = -1;
  std::size_t bytes_, count_ = 0;
};

// Writes float32 copies of output tensors, one file per stream name: <prefix>.<name>.f32.
class Dumper {
 public:
  explicit Dumper(std::string prefix) : prefix_(std::move(prefix)) {}
  ~Dumper();
  bool on() const { return !prefix_.empty(); }
  void write(const std::string &name, const float *v, std::size_t n);
  // Any numeric ONNX tensor, converted to float32.
  void write(const std::string &name, const Ort::Value &v);

 private:
  std::string prefix_;
  std::mutex mu_;
  std::map<std::string, FILE *> files_;
};

// One ONNX Runtime session with ort_threads() intra-op threads and one inter-op thread (as the
// pipelines' custom=NumThreads:N,InterOpNumThreads:1); with 1 the caller's thread runs it.
class OrtModel {
 public:
  explicit OrtModel(const std::string &path);
  // Inputs in model order; returns every output.
  std::vector<Ort::Value> run(const std::vector<Ort::Value> &inputs);
  template <typename T>
  static Ort::Value tensor(T *data, std::size_t n, const std::vector<int64_t> &shape) {
    return Ort::Value::CreateTensor<T>(cpu(), data, n, shape.data(), shape.size());
  }
  static const OrtMemoryInfo *cpu();

 private:
  std::unique_ptr<Ort::Session> session_;
  std::vector<std::string> in_names_, out_names_;
  std::vector<const char *> in_ptrs_, out_ptrs_;
};

// Converts any numeric ONNX tensor to float32 values.
std::vector<float> to_floats(const Ort::Value &v);

// A pipeline built from a gst-launch description.
class GstRun {
 public:
  explicit GstRun(const std::string &description);  // throws std::runtime_error
  ~GstRun();
  GstRun(const GstRun &) = delete;
  GstRun &operator=(const GstRun &) = delete;

  GstElement *element(const char *name);
  // Calls fn for each buffer reaching the tensor_sink `name`; counts them as sink `name`.
  void on_sink(const char *name, std::function<void(GstBuffer *)> fn = {});
  // Records, per PTS, the first time a buffer passes pad `pad` of `element` (slot `slot`).
  void stamp(const char *element, const char *pad, int slot);
  // Dumps every tensor of the buffers reaching tensor_sink `name` as float32.
  // (as stream `as`, default the sink's name).
  void dump_sink(const char *name, Dumper &d, const std::string &as = "");
  // Plays to EOS; returns "" or the error text.
  std::string run(int timeout_s);

  std::size_t count(const std::string &sink) const;
  // Wall, CPU and memory from the first stamped buffer (every element is started then, models
  // loaded) to the last buffer reaching a sink; the Control programs start after loading too.
  void add_usage(Result &r) const;
  double wall() const;
  // Milliseconds from slot a to slot b for every PTS that has both.
  Samples between(int a, int b) const;
  // How many PTS passed slot `slot`.
  std::size_t count_slot(int slot) const;

 private:
  struct SinkCtx;
  struct StampCtx;
  GstElement *pipeline_ = nullptr;
  std::vector<std::unique_ptr<SinkCtx>> sinks_;
  std::vector<std::unique_ptr<StampCtx>> stamps_;
  mutable std::mutex mu_;
  std::map<GstClockTime, std::map<int, double>> times_;  // PTS -> slot -> seconds
  Clock::time_point t0_ = Clock::now();
  std::string callback_error_;  // first exception caught in a sink callback
  bool first_set_ = false;
  double first_t_ = 0, first_cpu_ = 0, last_t_ = 0, last_cpu_ = 0;
  SchedSnapshot first_sched_, end_sched_;
  friend struct StampCtx;
};

// The tensors of a buffer as float32 (static caps types or flexible headers).
std::vector<std::vector<float>> buffer_tensors(GstBuffer *buf, GstCaps *caps);

// "filter framework=onnxruntime model=<path> custom=NumThreads:N,InterOpNumThreads:1" (prefix
// with "tensor_"); N = ort_threads(), the same intra-op thread count as every OrtModel.
std::string ort_filter(const std::string &model, const std::string &extra = "");
void set_ort_threads(int n);  // --ort-threads (default 1), both modes
int ort_threads();

// Reads a file once so that neither side's measured loop waits on the disk for its input.
void warm_file(const std::string &path);

// Experiments: fill `r` (figures, latency) for opts.mode.
void run_e1(const Options &o, Result &r);
void run_e2(const Options &o, Result &r);
void run_e3(const Options &o, Result &r);
void run_e4(const Options &o, Result &r);

}  // namespace paper
