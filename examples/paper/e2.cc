// SPDX-License-Identifier: LGPL-2.1-only
// E2: multi-sensor aggregation into a recurrent model (the paper's activity recognition
// sensor). Three recorded streams at different rates:
//   video 128x128 RGB 30 fps -> per-frame features (e2_video.onnx) -> windows of 12 frames,
//                             hop 6 (tensor_aggregator)
//   audio 16 kHz mono, 100 ms chunks -> features (e2_audio.onnx) -> windows of 4, hop 2
//   IMU-like 6 x float32 at 100 Hz, 100 ms chunks -> windows of 40 samples, hop 20
// tensor_mux joins the three 200 ms-hop windows, a GRU (e2_gru.onnx) classifies them.
// The Control program does the same by hand: one loop over the inputs in time order, its own
// ring of features, the GRU when a window is complete. --live paces every input at its rate.
#include <thread>

#include "common.h"

namespace paper {
namespace {

constexpr std::size_t kVideo = 128 * 128 * 3, kAudio = 1600, kImu = 10 * 6;
constexpr int kVWin = 12, kVHop = 6, kAWin = 4, kAHop = 2, kIWin = 4, kIHop = 2;  // in records

std::string pace(const Options &o) {
  return o.live ? "identity sync=true ! " : "";
}

// Records available in every stream for --frames N video frames (or the whole input).
struct Lengths {
  std::size_t video, audio, imu, windows;
};

Lengths lengths(const Options &o) {
  RecordFile v(o.inputs + "/e2.rgb", kVideo), a(o.inputs + "/e2.s16", kAudio * 2),
      i(o.inputs + "/e2.imu", kImu * 4);
  Lengths l{v.count(), a.count(), i.count(), 0};
  if (o.frames > 0) {
    l.video = std::min<std::size_t>(l.video, o.frames);
    l.audio = std::min(l.audio, l.video / 3);
    l.imu = std::min(l.imu, l.video / 3);
  }
  auto wins = [](std::size_t n, int win, int hop) {
    return n < static_cast<std::size_t>(win) ? 0 : (n - win) / hop + 1;
  };
  l.windows = std::min(
      {wins(l.video, kVWin, kVHop), wins(l.audio, kAWin, kAHop), wins(l.imu, kIWin, kIHop)});
  return l;
}

void run_nns(const Options &o, Result &r) {
  const Lengths n = lengths(o);
  const std::string &m = o.models, &in = o.inputs;
  std::string d =
      "filesrc location=" + in + "/e2.rgb blocksize=" + std::to_string(kVideo) +
      " num-buffers=" + std::to_string(n.video) +
      " ! rawvideoparse format=rgb width=128 height=128 framerate=30/1 ! " + pace(o) +
      "tensor_converter ! tensor_" + ort_filter(m + "/e2_video.onnx") +
      " name=fv ! tensor_aggregator frames-out=12 frames-flush=6 frames-dim=1 ! mux.sink_0 "
      "filesrc location=" +
      in + "/e2.s16 blocksize=" + std::to_string(kAudio * 2) +
      " num-buffers=" + std::to_string(n.audio) +
      " ! rawaudioparse format=pcm pcm-format=s16le sample-rate=16000 num-channels=1 ! " + pace(o) +
      "tensor_converter frames-per-tensor=1600 ! tensor_" + ort_filter(m + "/e2_audio.onnx") +
      " name=fa ! tensor_aggregator frames-out=4 frames-flush=2 frames-dim=1 ! mux.sink_1 "
      "filesrc location=" +
      in + "/e2.imu blocksize=" + std::to_string(kImu * 4) +
      " num-buffers=" + std::to_string(n.imu) +
      " ! rawaudioparse format=pcm pcm-format=f32le sample-rate=100 num-channels=6 ! " + pace(o) +
      "tensor_converter frames-per-tensor=10 name=ci ! tensor_aggregator frames-in=10 "
      "frames-out=40 frames-flush=20 frames-dim=1 ! mux.sink_2 "
      "tensor_mux name=mux sync-mode=slowest ! tensor_" +
      ort_filter(m + "/e2_gru.onnx") + " name=gru ! tensor_sink name=out";
  GstRun run(d);
  Dumper dump(o.dump);
  run.stamp("fv", "sink", 0);
  run.stamp("fv", "src", 1);
  run.stamp("fa", "src", 2);
  run.stamp("ci", "src", 3);
  run.stamp("mux", "src", 4);
  run.stamp("gru", "src", 5);
  if (dump.on())
    run.dump_sink("out", dump, "activity");
  else
    run.on_sink("out");
  std::string err = run.run(o.timeout_s);
  if (!err.empty()) throw std::runtime_error(err);
  run.add_usage(r);
  const double wall = run.wall();
  r.info["pipeline"] = d;
  r.figures["video_frames"] = static_cast<double>(run.count_slot(1));
  r.figures["audio_chunks"] = static_cast<double>(run.count_slot(2));
  r.figures["imu_chunks"] = static_cast<double>(run.count_slot(3));
  r.figures["windows"] = static_cast<double>(run.count("out"));
  r.figures["fps_video"] = r.figures["video_frames"] / wall;
  r.figures["fps_audio"] = r.figures["audio_chunks"] / wall;
  r.figures["fps_windows"] = r.figures["windows"] / wall;
  r.latency["gru"] = run.between(4, 5);
}

void run_control(const Options &o, Result &r) {
  const Lengths n = lengths(o);
  RecordFile vf(o.inputs + "/e2.rgb", kVideo), af(o.inputs + "/e2.s16", kAudio * 2),
      imf(o.inputs + "/e2.imu", kImu * 4);
  OrtModel video(o.models + "/e2_video.onnx"), audio(o.models + "/e2_audio.onnx"),
      gru(o.models + "/e2_gru.onnx");
  Dumper dump(o.dump);
  std::vector<uint8_t> frame(kVideo);
  std::vector<int16_t> pcm(kAudio);
  std::vector<float> vfeat(n.video * 16), afeat(n.audio * 32), imu(n.imu * kImu);
  std::size_t vi = 0, ai = 0, ii = 0, w = 0;
  Samples gru_ms;
  Meter m;
  m.start();
  // Every input record is due at its timestamp; take the earliest due one.
  while (w < n.windows) {
    const double tv = vi < n.video ? vi / 30.0 : 1e30, ta = ai < n.audio ? ai * 0.1 : 1e30,
                 ti = ii < n.imu ? ii * 0.1 : 1e30;
    const double due = std::min({tv, ta, ti});
    if (due >= 1e30) break;
    if (o.live) {
      const double wait = due - seconds_since(m.t0());
      if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    }
    if (due == tv) {
      vf.read(vi, frame.data());
      std::vector<Ort::Value> x;
      x.push_back(OrtModel::tensor(frame.data(), kVideo, {1, 128, 128, 3}));
      auto y = video.run(x);
      std::copy_n(y[0].GetTensorData<float>(), 16, &vfeat[vi * 16]);
      ++vi;
    } else if (due == ta) {
      af.read(ai, pcm.data());
      std::vector<Ort::Value> x;
      x.push_back(OrtModel::tensor(pcm.data(), kAudio, {1600, 1}));
      auto y = audio.run(x);
      std::copy_n(y[0].GetTensorData<float>(), 32, &afeat[ai * 32]);
      ++ai;
    } else {
      imf.read(ii, &imu[ii * kImu]);
      ++ii;
    }
    // Window w is complete when its last video frame, audio chunk and IMU chunk are in.
    if (vi >= w * kVHop + kVWin && ai >= w * kAHop + kAWin && ii >= w * kIHop + kIWin) {
      const double t = seconds_since(m.t0());
      std::vector<Ort::Value> x;
      x.push_back(OrtModel::tensor(&vfeat[w * kVHop * 16], kVWin * 16, {1, kVWin, 16}));
      x.push_back(OrtModel::tensor(&afeat[w * kAHop * 32], kAWin * 32, {1, kAWin, 32}));
      x.push_back(OrtModel::tensor(&imu[w * kIHop * kImu], kIWin * kImu, {1, kIWin * 10, 6}));
      auto y = gru.run(x);
      gru_ms.add(1000.0 * (seconds_since(m.t0()) - t));
      dump.write("activity.0", y[0]);
      ++w;
    }
  }
  m.stop();
  r.add_usage(m);
  r.figures["video_frames"] = static_cast<double>(vi);
  r.figures["audio_chunks"] = static_cast<double>(ai);
  r.figures["imu_chunks"] = static_cast<double>(ii);
  r.figures["windows"] = static_cast<double>(w);
  r.figures["fps_video"] = vi / m.wall();
  r.figures["fps_audio"] = ai / m.wall();
  r.figures["fps_windows"] = w / m.wall();
  r.latency["gru"] = gru_ms;
}

}  // namespace

void run_e2(const Options &o, Result &r) {
  if (o.mode == "nns")
    run_nns(o, r);
  else
    run_control(o, r);
}

}  // namespace paper
