// SPDX-License-Identifier: LGPL-2.1-only
// E3: an MTCNN-shaped cascade on a 160x120 recorded clip.
//   P-Net stage: three P-Net filters (scales 0.6, 0.4, 0.25, resized in the models) in
//     parallel branches; tensor_demux + tensor_merge concatenate their boxes and logits;
//     tensor_decoder mode=tensor_region (our bounding-box code: SSD decoding against the P-Net
//     window priors, threshold, NMS) gives the K=4 best regions.
//   R-Net stage: tensor_crop cuts the regions out of the frame; tensor_mux adds the regions;
//     R-Net (any crop size, resized to 24x24 in the model, invoke-dynamic) scores them and
//     refines the boxes (box regression).
//   O-Net stage: tensor_crop on the refined boxes, O-Net (48x48) scores, boxes, landmarks;
//     tensor_if passes the frames whose best face score reaches the threshold to `faces`.
// The Control program runs the same models by hand in one loop and uses the same box decoding
// and NMS (nns_bbox's mobilenet-ssd scheme, as tensor_region) and crop code (core/crop.h).
// Figures: throughput, per-stage latency (P: frame in -> regions out, R: -> R-Net out,
// O: -> O-Net out) and overall latency. Use --rate 5 --live for the latency run.
#include <thread>

#include "box_scheme.h"
#include "common.h"
#include "core/crop.h"

namespace paper {
namespace {

constexpr uint32_t kW = 160, kH = 120;
constexpr std::size_t kFrame = kW * kH * 3, kK = 4;
constexpr float kFaceThreshold = 0.5f;

std::string nms_option3(const Options &o) {
  return o.models + "/e3_priors.txt:0.6:10:10:5:5:0.3";
}

void run_nns(const Options &o, Result &r) {
  const std::string &m = o.models;
  std::string d = "filesrc location=" + o.inputs + "/e3.rgb blocksize=" + std::to_string(kFrame);
  if (o.frames > 0) d += " num-buffers=" + std::to_string(o.frames);
  d += " ! rawvideoparse format=rgb width=160 height=120 framerate=" +
       std::to_string(static_cast<int>(o.rate)) + "/1 ! ";
  if (o.live) d += "identity sync=true ! ";
  d += "tensor_converter ! tee name=t ";
  for (int s = 0; s < 3; ++s) {
    const std::string i = std::to_string(s);
    d += " t. ! queue ! tensor_" + ort_filter(m + "/e3_pnet_" + i + ".onnx") + " name=p" + i +
         " ! tensor_demux name=d" + i + "  d" + i + ".src_0 ! queue ! mb.sink_" + i + "  d" + i +
         ".src_1 ! queue ! ml.sink_" + i;
  }
  d += " tensor_merge name=mb mode=linear option=2 sync-mode=slowest ! pm.sink_0"
       " tensor_merge name=ml mode=linear option=1 sync-mode=slowest ! pm.sink_1"
       " tensor_mux name=pm sync-mode=slowest ! tensor_decoder name=nms mode=tensor_region"
       " option1=" +
       std::to_string(kK) + " option2=" + m + "/labels2.txt option3=" + nms_option3(o) +
       " option4=160:120 ! tee name=reg"
       " t. ! queue ! c1.raw  reg. ! queue ! c1.info  tensor_crop name=c1 ! rm.sink_0"
       " reg. ! queue ! rm.sink_1  tensor_mux name=rm sync-mode=slowest ! tensor_" +
       ort_filter(m + "/e3_rnet.onnx", "invoke-dynamic=true") +
       " name=rnet ! tee name=rr"
       " t. ! queue ! c2.raw  rr. ! queue ! c2.info  tensor_crop name=c2 ! om.sink_0"
       " rr. ! queue ! om.sink_1  tensor_mux name=om sync-mode=slowest ! tensor_" +
       ort_filter(m + "/e3_onet.onnx", "invoke-dynamic=true") +
       " name=onet ! tee name=ot"
       " ot. ! queue ! tensor_sink name=out"
       " ot. ! queue ! tensor_converter ! tensor_if name=tif compared-value=A_VALUE"
       " compared-value-option=0,3 operator=GE supplied-value=" +
       std::to_string(kFaceThreshold) + " then=PASSTHROUGH else=SKIP ! tensor_sink name=faces";
  GstRun run(d);
  Dumper dump(o.dump);
  run.stamp("t", "sink", 0);
  run.stamp("nms", "src", 1);
  run.stamp("rnet", "src", 2);
  run.stamp("onet", "src", 3);
  if (dump.on())
    run.dump_sink("out", dump);
  else
    run.on_sink("out");
  run.on_sink("faces");
  std::string err = run.run(o.timeout_s);
  if (!err.empty()) throw std::runtime_error(err);
  run.add_usage(r);
  r.info["pipeline"] = d;
  const double n = static_cast<double>(run.count("out"));
  r.figures["frames"] = n;
  r.figures["face_frames"] = static_cast<double>(run.count("faces"));
  r.figures["fps"] = n / run.wall();
  r.latency["overall"] = run.between(0, 3);
  r.latency["pnet"] = run.between(0, 1);
  r.latency["rnet"] = run.between(1, 2);
  r.latency["onet"] = run.between(2, 3);
}

// K crops of `regions` (x, y, w, h quadruples of any numeric type) as model inputs.
template <typename T>
void crops_of(const uint8_t *frame, const T *regions, std::vector<std::vector<uint8_t>> &store,
              std::vector<Ort::Value> &inputs) {
  for (std::size_t k = 0; k < kK; ++k) {
    nns::CropRegion cr{
        static_cast<uint32_t>(regions[k * 4]), static_cast<uint32_t>(regions[k * 4 + 1]),
        static_cast<uint32_t>(regions[k * 4 + 2]), static_cast<uint32_t>(regions[k * 4 + 3])};
    bool clipped = false;
    cr = nns::fit_crop_region(cr, kW, kH, k, &clipped);
    store[k].resize(std::size_t{cr.w} * cr.h * 3);
    nns::crop_nhwc(frame, 3, kW, 1, cr, store[k].data());
    inputs.push_back(
        OrtModel::tensor(store[k].data(), store[k].size(),
                         {1, static_cast<int64_t>(cr.h), static_cast<int64_t>(cr.w), 3}));
  }
}

void run_control(const Options &o, Result &r) {
  RecordFile clip(o.inputs + "/e3.rgb", kFrame);
  const std::size_t n = o.frames > 0 ? std::min<std::size_t>(o.frames, clip.count()) : clip.count();
  std::vector<std::unique_ptr<OrtModel>> pnet;
  for (int s = 0; s < 3; ++s)
    pnet.push_back(
        std::make_unique<OrtModel>(o.models + "/e3_pnet_" + std::to_string(s) + ".onnx"));
  OrtModel rnet(o.models + "/e3_rnet.onnx"), onet(o.models + "/e3_onet.onnx");
  // The box decoding and NMS of tensor_decoder mode=tensor_region, called directly.
  auto scheme = nns::bbox::schemes().make("mobilenet-ssd");
  scheme->set_option3(nms_option3(o));
  nns::bbox::Context ctx;
  ctx.in_w = kW;
  ctx.in_h = kH;
  ctx.num_labels = 2;
  bool checked = false;
  nns::TensorsInfo info;
  std::vector<nns::bbox::Box> boxes;
  Dumper dump(o.dump);
  std::vector<uint8_t> frame(kFrame);
  std::vector<float> all_boxes, all_logits;
  std::vector<std::vector<uint8_t>> crops(kK);
  Samples lp, lr, lo, lall;
  std::size_t faces = 0;
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
    // P-Net stage
    all_boxes.clear();
    all_logits.clear();
    {
      std::vector<Ort::Value> in;
      in.push_back(OrtModel::tensor(frame.data(), kFrame, {1, kH, kW, 3}));
      for (auto &p : pnet) {
        auto out = p->run(in);
        const auto b = to_floats(out[0]), l = to_floats(out[1]);
        all_boxes.insert(all_boxes.end(), b.begin(), b.end());
        all_logits.insert(all_logits.end(), l.begin(), l.end());
      }
    }
    const uint32_t total = static_cast<uint32_t>(all_logits.size() / 2);
    if (!checked) {
      info.tensors = {{"", nns::TensorType::kFloat32, nns::make_dims({4, 1, total})},
                      {"", nns::TensorType::kFloat32, nns::make_dims({2, total})}};
      scheme->check_input(info, ctx);
      checked = true;
    }
    nns::bbox::TensorView views[2] = {{all_boxes.data(), all_boxes.size() * 4, &info[0]},
                                      {all_logits.data(), all_logits.size() * 4, &info[1]}};
    scheme->decode(views, ctx, boxes);
    uint32_t regions[kK * 4] = {};
    for (std::size_t k = 0; k < boxes.size() && k < kK; ++k) {
      regions[k * 4] = static_cast<uint32_t>(boxes[k].x);
      regions[k * 4 + 1] = static_cast<uint32_t>(boxes[k].y);
      regions[k * 4 + 2] = static_cast<uint32_t>(boxes[k].w);
      regions[k * 4 + 3] = static_cast<uint32_t>(boxes[k].h);
    }
    const double t1 = seconds_since(m.t0());
    // R-Net stage
    std::vector<Ort::Value> rin;
    crops_of(frame.data(), regions, crops, rin);
    rin.push_back(OrtModel::tensor(regions, kK * 4, {kK, 4}));
    auto rout = rnet.run(rin);
    const double t2 = seconds_since(m.t0());
    // O-Net stage on the refined boxes
    std::vector<Ort::Value> oin;
    crops_of(frame.data(), rout[0].GetTensorData<int32_t>(), crops, oin);
    for (auto &v : rout) oin.push_back(std::move(v));
    auto oout = onet.run(oin);
    const double t3 = seconds_since(m.t0());
    if (oout[3].GetTensorData<float>()[0] >= kFaceThreshold) ++faces;
    for (std::size_t k = 0; k < oout.size(); ++k) dump.write("out." + std::to_string(k), oout[k]);
    lp.add(1000 * (t1 - t0));
    lr.add(1000 * (t2 - t1));
    lo.add(1000 * (t3 - t2));
    lall.add(1000 * (t3 - t0));
  }
  m.stop();
  r.add_usage(m);
  r.figures["frames"] = static_cast<double>(n);
  r.figures["face_frames"] = static_cast<double>(faces);
  r.figures["fps"] = n / m.wall();
  r.latency["overall"] = lall;
  r.latency["pnet"] = lp;
  r.latency["rnet"] = lr;
  r.latency["onet"] = lo;
}

}  // namespace

void run_e3(const Options &o, Result &r) {
  if (o.mode == "nns")
    run_nns(o, r);
  else
    run_control(o, r);
}

}  // namespace paper
