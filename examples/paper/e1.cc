// SPDX-License-Identifier: LGPL-2.1-only
// E1: several models of different speeds on one video stream.
//   nns:     filesrc ! rawvideoparse ! [identity sync] ! tensor_converter ! tee, one branch per
//            model: queue ! tensor_filter ! tensor_sink. With --live the input is paced at
//            30 fps and the queues are leaky (each model takes the newest frame when it is
//            free, as a camera pipeline would); otherwise every model sees every frame.
//   control: one loop: take a frame (live: the newest one due), run the models one after the
//            other, repeat.
// config: comma-separated models among fast, mid, slow (e1_<name>.onnx).
#include <thread>

#include "common.h"
#include "core/tensor_info.h"

namespace paper {
namespace {

constexpr int kW = 224, kH = 224;
constexpr std::size_t kFrame = kW * kH * 3;

std::string model_path(const Options &o, const std::string &key) {
  return o.models + "/e1_" + key + ".onnx";
}

void run_nns(const Options &o, const std::vector<std::string> &keys, Result &r) {
  std::string d = "filesrc location=" + o.inputs + "/e1.rgb blocksize=" + std::to_string(kFrame);
  if (o.frames > 0) d += " num-buffers=" + std::to_string(o.frames);
  d += " ! rawvideoparse format=rgb width=224 height=224 framerate=30/1 ! ";
  if (o.live) d += "identity sync=true ! ";
  d += "tensor_converter ! tee name=t ";
  const std::string q = o.live ? "queue leaky=downstream max-size-buffers=1" : "queue";
  for (const auto &k : keys)
    d += " t. ! " + q + " ! tensor_" + ort_filter(model_path(o, k)) + " name=f_" + k +
         " ! tensor_sink name=out_" + k;
  GstRun run(d);
  Dumper dump(o.dump);
  run.stamp("t", "sink", 0);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::string sink = "out_" + keys[i];
    if (dump.on())
      run.dump_sink(sink.c_str(), dump, keys[i]);
    else
      run.on_sink(sink.c_str());
    run.stamp(("f_" + keys[i]).c_str(), "src", static_cast<int>(i) + 1);
  }
  std::string err = run.run(o.timeout_s);
  if (!err.empty()) throw std::runtime_error(err);
  run.add_usage(r);
  r.info["pipeline"] = d;
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const double n = static_cast<double>(run.count("out_" + keys[i]));
    r.figures["frames_" + keys[i]] = n;
    r.figures["fps_" + keys[i]] = n / run.wall();
    r.latency[keys[i]] = run.between(0, static_cast<int>(i) + 1);
  }
  r.figures["input_frames"] = static_cast<double>(run.between(0, 0).ms.size());
}

void run_control(const Options &o, const std::vector<std::string> &keys, Result &r) {
  RecordFile clip(o.inputs + "/e1.rgb", kFrame);
  const std::size_t n = o.frames > 0 ? std::min<std::size_t>(o.frames, clip.count()) : clip.count();
  std::vector<std::unique_ptr<OrtModel>> models;
  for (const auto &k : keys) models.push_back(std::make_unique<OrtModel>(model_path(o, k)));
  Dumper dump(o.dump);
  std::vector<uint8_t> frame(kFrame);
  const std::vector<int64_t> shape{1, kH, kW, 3};
  std::vector<Samples> lat(keys.size());
  std::size_t done = 0, last = SIZE_MAX;
  Meter m;
  m.start();
  for (std::size_t i = 0; i < n;) {
    double due = 0;
    if (o.live) {  // the newest frame that is due; wait for the next one if it was taken
      const double now = seconds_since(m.t0());
      std::size_t idx = static_cast<std::size_t>(now * o.rate);
      if (idx == last) {
        std::this_thread::sleep_for(std::chrono::duration<double>((idx + 1) / o.rate - now));
        continue;
      }
      if (idx >= n) break;
      i = idx;
      due = static_cast<double>(idx) / o.rate;
    } else {
      due = seconds_since(m.t0());
    }
    clip.read(i, frame.data());
    std::vector<Ort::Value> in;
    in.push_back(OrtModel::tensor(frame.data(), frame.size(), shape));
    for (std::size_t k = 0; k < models.size(); ++k) {
      auto out = models[k]->run(in);
      lat[k].add(1000.0 * (seconds_since(m.t0()) - due));
      dump.write(keys[k] + ".0", out[0]);
    }
    ++done;
    last = i;
    if (!o.live) ++i;
  }
  m.stop();
  r.add_usage(m);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    r.figures["frames_" + keys[k]] = static_cast<double>(done);
    r.figures["fps_" + keys[k]] = static_cast<double>(done) / m.wall();
    r.latency[keys[k]] = lat[k];
  }
  r.figures["input_frames"] = static_cast<double>(n);
}

}  // namespace

void run_e1(const Options &o, Result &r) {
  const auto keys = nns::split(o.config.empty() ? "fast,mid,slow" : o.config, ",");
  for (const auto &k : keys)
    if (k != "fast" && k != "mid" && k != "slow")
      throw std::runtime_error("e1: unknown model '" + k + "' (fast, mid, slow)");
  if (o.mode == "nns")
    run_nns(o, keys, r);
  else
    run_control(o, keys, r);
}

}  // namespace paper
