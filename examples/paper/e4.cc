// SPDX-License-Identifier: LGPL-2.1-only
// E4: SSD-style detection on a 640x360 recorded clip at two model sizes (config 160 or 320).
//   nns:     filesrc ! rawvideoparse ! [identity sync] ! videoscale ! SxS RGB !
//            tensor_converter ! tensor_filter (SSD) ! tee ! tensor_decoder
//            mode=bounding_boxes (decoding, NMS, drawing a 640x360 RGBA overlay) ! fakesink,
//            and the detector outputs to a tensor_sink.
//   control: one loop: read, bilinear resize by hand, ONNX Runtime, the same decoding, NMS and
//            drawing code as the decoder (nns_bbox), called directly.
// The paper compares NNStreamer with MediaPipe here; MediaPipe is not on this machine, so the
// comparison is with a Control loop as in the other experiments.
#include <cmath>
#include <cstring>
#include <thread>

#include "box_scheme.h"
#include "common.h"
#include "draw.h"

namespace paper {
namespace {

constexpr int kW = 640, kH = 360;
constexpr std::size_t kFrame = std::size_t{kW} * kH * 3;

int side_of(const Options &o) {
  const int s = o.config.empty() ? 160 : std::stoi(o.config);
  if (s != 160 && s != 320) throw std::runtime_error("e4: config must be 160 or 320");
  return s;
}

std::string option3(const Options &o, int s) {
  return o.models + "/e4_priors_" + std::to_string(s) + ".txt:0.6:10:10:5:5:0.5";
}

void run_nns(const Options &o, Result &r) {
  const int s = side_of(o);
  const std::string side = std::to_string(s);
  std::string d = "filesrc location=" + o.inputs + "/e4.rgb blocksize=" + std::to_string(kFrame);
  if (o.frames > 0) d += " num-buffers=" + std::to_string(o.frames);
  d += " ! rawvideoparse format=rgb width=640 height=360 framerate=30/1 ! ";
  if (o.live) d += "identity sync=true ! ";
  d += "queue ! videoscale name=scale ! video/x-raw,format=RGB,width=" + side + ",height=" + side +
       " ! tensor_converter ! tensor_" + ort_filter(o.models + "/e4_ssd_" + side + ".onnx") +
       " name=det ! tee name=dt  dt. ! queue ! tensor_decoder name=dec mode=bounding_boxes"
       " option1=mobilenet-ssd option2=" +
       o.models + "/labels3.txt option3=" + option3(o, s) + " option4=640:360 option5=" + side +
       ":" + side +
       " ! fakesink name=show"
       "  dt. ! queue ! tensor_sink name=out";
  GstRun run(d);
  Dumper dump(o.dump);
  run.stamp("scale", "sink", 0);
  run.stamp("det", "src", 1);
  run.stamp("show", "sink", 2);
  if (dump.on())
    run.dump_sink("out", dump);
  else
    run.on_sink("out");
  std::string err = run.run(o.timeout_s);
  if (!err.empty()) throw std::runtime_error(err);
  run.add_usage(r);
  r.info["pipeline"] = d;
  const double n = static_cast<double>(run.count_slot(2));
  r.figures["frames"] = n;
  r.figures["fps"] = n / run.wall();
  r.latency["overall"] = run.between(0, 2);
  r.latency["to_detector_out"] = run.between(0, 1);
}

// Bilinear RGB resize (pixel centres aligned, edges clamped), as a plain C++ loop.
class Resizer {
 public:
  Resizer(int sw, int sh, int dw, int dh) : sw_(sw), dw_(dw), dh_(dh) {
    auto taps = [](int src, int dst, std::vector<int> &i0, std::vector<float> &f) {
      for (int x = 0; x < dst; ++x) {
        float p = (x + 0.5f) * static_cast<float>(src) / static_cast<float>(dst) - 0.5f;
        p = std::clamp(p, 0.f, static_cast<float>(src - 1));
        const int i = std::min(static_cast<int>(p), src - 2);
        i0.push_back(i);
        f.push_back(p - static_cast<float>(i));
      }
    };
    taps(sw, dw, x0_, fx_);
    taps(sh, dh, y0_, fy_);
  }
  void run(const uint8_t *src, uint8_t *dst) const {
    const std::size_t stride = std::size_t{3} * sw_;
    for (int y = 0; y < dh_; ++y) {
      const uint8_t *r0 = src + y0_[y] * stride, *r1 = r0 + stride;
      const float wy = fy_[y];
      for (int x = 0; x < dw_; ++x) {
        const int i = 3 * x0_[x];
        const float wx = fx_[x];
        for (int c = 0; c < 3; ++c) {
          const float top = r0[i + c] + wx * (r0[i + 3 + c] - r0[i + c]);
          const float bot = r1[i + c] + wx * (r1[i + 3 + c] - r1[i + c]);
          *dst++ = static_cast<uint8_t>(std::lround(top + wy * (bot - top)));
        }
      }
    }
  }

 private:
  int sw_, dw_, dh_;
  std::vector<int> x0_, y0_;
  std::vector<float> fx_, fy_;
};

void run_control(const Options &o, Result &r) {
  const int s = side_of(o);
  RecordFile clip(o.inputs + "/e4.rgb", kFrame);
  const std::size_t n = o.frames > 0 ? std::min<std::size_t>(o.frames, clip.count()) : clip.count();
  OrtModel det(o.models + "/e4_ssd_" + std::to_string(s) + ".onnx");
  auto scheme = nns::bbox::schemes().make("mobilenet-ssd");
  scheme->set_option3(option3(o, s));
  nns::bbox::Context ctx;
  ctx.in_w = ctx.in_h = static_cast<unsigned>(s);
  ctx.num_labels = 3;
  const char *labels[3] = {"background", "blob", "other"};
  Resizer resize(kW, kH, s, s);
  std::vector<uint8_t> frame(kFrame), small(std::size_t{3} * s * s);
  std::vector<uint32_t> overlay(std::size_t{kW} * kH);
  std::vector<nns::bbox::Box> boxes;
  nns::TensorsInfo info;
  bool checked = false;
  Dumper dump(o.dump);
  Samples lat;
  std::size_t drawn = 0;
  Meter m;
  m.start();
  for (std::size_t i = 0; i < n; ++i) {
    double t0 = seconds_since(m.t0());
    if (o.live) {
      const double wait = i / o.rate - t0;
      if (wait > 0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
      t0 = seconds_since(m.t0());
    }
    clip.read(i, frame.data());
    resize.run(frame.data(), small.data());
    std::vector<Ort::Value> in;
    in.push_back(OrtModel::tensor(small.data(), small.size(), {1, s, s, 3}));
    auto out = det.run(in);
    const auto b = to_floats(out[0]), l = to_floats(out[1]);
    dump.write("out.0", b.data(), b.size());
    dump.write("out.1", l.data(), l.size());
    if (!checked) {
      const uint32_t np = static_cast<uint32_t>(l.size() / 3);
      info.tensors = {{"", nns::TensorType::kFloat32, nns::make_dims({4, 1, np})},
                      {"", nns::TensorType::kFloat32, nns::make_dims({3, np})}};
      scheme->check_input(info, ctx);
      checked = true;
    }
    nns::bbox::TensorView views[2] = {{b.data(), b.size() * 4, &info[0]},
                                      {l.data(), l.size() * 4, &info[1]}};
    scheme->decode(views, ctx, boxes);
    std::memset(overlay.data(), 0, overlay.size() * 4);
    nns::bbox::Canvas c{overlay.data(), kW, kH};
    for (const auto &bx : boxes) {
      auto p = nns::bbox::draw_box(c, bx, ctx.in_w, ctx.in_h, nns::bbox::box_colour());
      if (bx.class_id >= 0 && bx.class_id < 3)
        nns::bbox::draw_text(c, p.x, p.y - 14, labels[bx.class_id], nns::bbox::box_colour());
      ++drawn;
    }
    lat.add(1000 * (seconds_since(m.t0()) - t0));
  }
  m.stop();
  r.add_usage(m);
  r.figures["frames"] = static_cast<double>(n);
  r.figures["boxes"] = static_cast<double>(drawn);
  r.figures["fps"] = n / m.wall();
  r.latency["overall"] = lat;
}

}  // namespace

void run_e4(const Options &o, Result &r) {
  if (o.mode == "nns")
    run_nns(o, r);
  else
    run_control(o, r);
}

}  // namespace paper
