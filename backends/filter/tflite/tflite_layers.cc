// SPDX-License-Identifier: LGPL-2.1-only
// Translation of the TFLite ops that need more than one ONNX node or layout handling.
#include "tflite_translator.h"

namespace nns::tfl::detail {

void Translator::conv(const Op &op, bool depthwise) {
  need(op, 2, 1);
  int x = op.inputs[0], w = op.inputs[1], out = op.outputs[0];
  int b = op.inputs.size() > 2 ? op.inputs[2] : -1;
  need_rank(op, x, 4);
  need_rank(op, w, 4);
  int padding, sw, sh, dw, dh, fused;
  int64_t group = 1;
  if (depthwise) {
    auto *o = op.raw->builtin_options_as_DepthwiseConv2DOptions();
    if (!o) fail(op, "DepthwiseConv2DOptions missing");
    padding = o->padding(), sw = o->stride_w(), sh = o->stride_h();
    dw = o->dilation_w_factor(), dh = o->dilation_h_factor(),
    fused = o->fused_activation_function();
    group = T(x).shape[3];
    if (group <= 0 || T(w).shape[3] % group) fail(op, "weights do not match the input channels");
  } else {
    auto *o = op.raw->builtin_options_as_Conv2DOptions();
    if (!o) fail(op, "Conv2DOptions missing");
    padding = o->padding(), sw = o->stride_w(), sh = o->stride_h();
    dw = o->dilation_w_factor(), dh = o->dilation_h_factor(),
    fused = o->fused_activation_function();
    if (T(w).shape[3] > 0 && T(x).shape[3] % T(w).shape[3] == 0)
      group = T(x).shape[3] / T(w).shape[3];
  }
  if (sw <= 0 || sh <= 0 || dw <= 0 || dh <= 0) fail(op, "strides and dilations must be positive");
  std::string xi = nchw(flt(x));
  // TFLite weights: conv OHWI, depthwise 1HW(C*M); ONNX wants OIHW ((C*M)1HW).
  std::string wi = flt(w, depthwise ? std::vector<int>{3, 0, 1, 2} : std::vector<int>{0, 3, 1, 2});
  Strs in{xi, wi};
  if (b >= 0) in.push_back(flt(b));
  std::string y = fresh();
  std::vector<onnx::Msg> at{attr_ints("strides", {sh, sw}), attr_ints("dilations", {dh, dw}),
                            attr_int("group", group),
                            attr_ints("kernel_shape", {T(w).shape[1], T(w).shape[2]})};
  if (padding == 0 && (dh > 1 || dw > 1)) {
    // ORT has no SAME auto_pad with dilation: explicit pads from the declared input size.
    auto pads = [](int64_t in, int64_t k, int64_t s, int64_t d) {
      int64_t out = (in + s - 1) / s, ke = (k - 1) * d + 1;
      int64_t total = std::max<int64_t>((out - 1) * s + ke - in, 0);
      return std::pair<int64_t, int64_t>{total / 2, total - total / 2};
    };
    auto [t0, t1] = pads(T(x).shape[1], T(w).shape[1], sh, dh);
    auto [l0, l1] = pads(T(x).shape[2], T(w).shape[2], sw, dw);
    at.push_back(attr_ints("pads", {t0, l0, t1, l1}));
  } else {
    at.push_back(pad_attr(padding));
  }
  g_.node("Conv", in, {y}, at);
  store(out, nhwc(act(y, fused, op)));
}

void Translator::transpose_conv(const Op &op) {
  need(op, 3, 1);
  int shape_t = op.inputs[0], w = op.inputs[1], x = op.inputs[2], out = op.outputs[0];
  int b = op.inputs.size() > 3 ? op.inputs[3] : -1;
  need_rank(op, x, 4);
  need_rank(op, w, 4);
  auto *o = op.raw->builtin_options_as_TransposeConvOptions();
  if (!o) fail(op, "TransposeConvOptions missing");
  auto oshape = ints(op, shape_t);
  if (oshape.size() != 4) fail(op, "output_shape must have 4 values");
  std::string xi = nchw(flt(x));
  std::string wi = flt(w, {3, 0, 1, 2});  // OHWI -> IOHW
  Strs in{xi, wi};
  if (b >= 0) in.push_back(flt(b));
  std::string y = fresh();
  std::vector<onnx::Msg> at{attr_ints("strides", {o->stride_h(), o->stride_w()}),
                            attr_ints("kernel_shape", {T(w).shape[1], T(w).shape[2]}),
                            attr_ints("output_shape", {oshape[1], oshape[2]})};
  if (o->padding() == 0) at.push_back(attr_str("auto_pad", "SAME_UPPER"));
  g_.node("ConvTranspose", in, {y}, at);
  store(out, nhwc(act(y, o->fused_activation_function(), op)));
}

void Translator::pool(const Op &op, const char *onnx_op) {
  need(op, 1, 1);
  need_rank(op, op.inputs[0], 4);
  auto *o = op.raw->builtin_options_as_Pool2DOptions();
  if (!o) fail(op, "Pool2DOptions missing");
  if (o->stride_w() <= 0 || o->stride_h() <= 0 || o->filter_width() <= 0 || o->filter_height() <= 0)
    fail(op, "strides and filter sizes must be positive");
  std::string y = fresh();
  g_.node(onnx_op, {nchw(flt(op.inputs[0]))}, {y},
          {pad_attr(o->padding()), attr_ints("strides", {o->stride_h(), o->stride_w()}),
           attr_ints("kernel_shape", {o->filter_height(), o->filter_width()})});
  store(op.outputs[0], nhwc(act(y, o->fused_activation_function(), op)));
}

void Translator::fully_connected(const Op &op) {
  need(op, 2, 1);
  int x = op.inputs[0], w = op.inputs[1], out = op.outputs[0];
  int b = op.inputs.size() > 2 ? op.inputs[2] : -1;
  need_rank(op, w, 2);
  auto *o = op.raw->builtin_options_as_FullyConnectedOptions();
  int fused = o ? o->fused_activation_function() : 0;
  if (o && o->weights_format() != 0) unsupported(op, "shuffled weights");
  int64_t k = T(w).shape[1];
  std::string x2 = fresh();
  g_.node("Reshape", {flt(x), const_i64({-1, k})}, {x2});
  Strs in{x2, flt(w)};
  if (b >= 0) in.push_back(flt(b));
  std::string y = fresh();
  g_.node("Gemm", in, {y}, {attr_int("transB", 1)});
  y = act(y, fused, op);
  if (o && o->keep_num_dims()) {
    std::vector<int64_t> s(T(out).shape.begin(), T(out).shape.end());
    for (std::size_t i = 0; i + 1 < s.size(); ++i) s[i] = i == 0 ? -1 : s[i];
    std::string r = fresh();
    g_.node("Reshape", {y, const_i64(s)}, {r});
    y = r;
  }
  store(out, y);
}

void Translator::resize(const Op &op, bool bilinear) {
  need(op, 2, 1);
  need_rank(op, op.inputs[0], 4);
  auto size = ints(op, op.inputs[1]);
  if (size.size() != 2) fail(op, "size must have 2 values");
  bool align = false, half = false;
  if (bilinear) {
    if (auto *o = op.raw->builtin_options_as_ResizeBilinearOptions())
      align = o->align_corners(), half = o->half_pixel_centers();
  } else if (auto *o = op.raw->builtin_options_as_ResizeNearestNeighborOptions()) {
    align = o->align_corners(), half = o->half_pixel_centers();
  }
  int x = op.inputs[0], out = op.outputs[0];
  bool direct = !bilinear && same_q(x, out);
  std::string xi = nchw(direct ? raw(x) : flt(x));
  std::string shp = unary("Shape", xi);
  std::string nc = fresh();
  g_.node("Slice", {shp, const_i64({0}), const_i64({2})}, {nc});
  std::string sizes = fresh();
  g_.node("Concat", {nc, const_i64(size)}, {sizes}, {attr_int("axis", 0)});
  std::string mode = align  ? "align_corners"
                     : half ? (bilinear ? "half_pixel" : "tf_half_pixel_for_nn")
                            : "asymmetric";
  std::vector<onnx::Msg> at{attr_str("mode", bilinear ? "linear" : "nearest"),
                            attr_str("coordinate_transformation_mode", mode)};
  if (!bilinear) at.push_back(attr_str("nearest_mode", align ? "round_prefer_ceil" : "floor"));
  std::string y = fresh();
  g_.node("Resize", {xi, "", "", sizes}, {y}, at);
  if (direct)
    store_raw(out, nhwc(y));
  else
    store(out, nhwc(y));
}

void Translator::strided_slice(const Op &op) {
  need(op, 4, 1);
  auto *o = op.raw->builtin_options_as_StridedSliceOptions();
  int bm = o ? o->begin_mask() : 0, em = o ? o->end_mask() : 0;
  int sm = o ? o->shrink_axis_mask() : 0;
  if (o && (o->ellipsis_mask() || o->new_axis_mask() || o->offset()))
    unsupported(op, "ellipsis/new_axis masks or offset");
  auto begin = ints(op, op.inputs[1]), end = ints(op, op.inputs[2]),
       stride = ints(op, op.inputs[3]);
  if (begin.size() != end.size() || begin.size() != stride.size())
    fail(op, "begin, end and strides differ in length");
  const int64_t kMax = std::numeric_limits<int64_t>::max(),
                kMin = std::numeric_limits<int64_t>::min();
  std::vector<int64_t> axes, squeeze;
  for (std::size_t i = 0; i < begin.size(); ++i) {
    if (stride[i] == 0) fail(op, "stride 0");
    axes.push_back(static_cast<int64_t>(i));
    if (bm & (1 << i)) begin[i] = stride[i] > 0 ? 0 : kMax;
    if (sm & (1 << i)) {
      end[i] = begin[i] == -1 ? kMax : begin[i] + 1;
      stride[i] = 1;
      squeeze.push_back(static_cast<int64_t>(i));
    } else if (em & (1 << i)) {
      end[i] = stride[i] > 0 ? kMax : kMin;
    }
  }
  int x = op.inputs[0], out = op.outputs[0];
  bool direct = same_q(x, out);
  std::string y = fresh();
  g_.node("Slice",
          {direct ? raw(x) : flt(x), const_i64(begin), const_i64(end), const_i64(axes),
           const_i64(stride)},
          {y});
  if (!squeeze.empty()) y = binary("Squeeze", y, const_i64(squeeze));
  if (direct)
    store_raw(out, y);
  else
    store(out, y);
}

void Translator::detection_post(const Op &op, Translation &tr) {
  need(op, 3, 4);
  for (int o : op.outputs)
    for (const Op &other : m_.ops)
      if (std::count(other.inputs.begin(), other.inputs.end(), o))
        unsupported(op, "its outputs feed other operators");
  DetectionPost p;
  DetectionPostProcessOptions &o = p.opts;
  if (op.custom_options && op.custom_options_size) {
    std::vector<uint8_t> buf(op.custom_options, op.custom_options + op.custom_options_size);
    if (!flexbuffers::VerifyBuffer(buf.data(), buf.size()))
      fail(op, "custom_options is not a valid flexbuffer");
    auto map = flexbuffers::GetRoot(buf).AsMap();
    auto geti = [&](const char *k, int &v) {
      auto e = map[k];
      if (!e.IsNull()) v = static_cast<int>(e.AsInt64());
    };
    auto getf = [&](const char *k, float &v) {
      auto e = map[k];
      if (!e.IsNull()) v = e.AsFloat();
    };
    geti("max_detections", o.max_detections);
    geti("max_classes_per_detection", o.max_classes_per_detection);
    geti("detections_per_class", o.detections_per_class);
    getf("nms_score_threshold", o.nms_score_threshold);
    getf("nms_iou_threshold", o.nms_iou_threshold);
    geti("num_classes", o.num_classes);
    getf("y_scale", o.y_scale);
    getf("x_scale", o.x_scale);
    getf("h_scale", o.h_scale);
    getf("w_scale", o.w_scale);
    auto r = map["use_regular_nms"];
    if (!r.IsNull()) o.use_regular_nms = r.AsBool();
  }
  if (o.max_detections <= 0 || o.max_detections > 10000 || o.num_classes <= 0 ||
      o.num_classes > 100000 || o.max_classes_per_detection <= 0 ||
      o.max_classes_per_detection > o.num_classes || p.slots() <= 0 || p.slots() > 100000)
    fail(op, "implausible options (max_detections " + std::to_string(o.max_detections) +
                 ", num_classes " + std::to_string(o.num_classes) + ")");
  int anchors = op.inputs[2];
  if (!is_const(anchors)) unsupported(op, "anchors must be a constant");
  const Tensor &a = T(anchors);
  if (a.shape.size() != 2 || a.shape[1] != 4) fail(op, "anchors must be [num_anchors, 4]");
  p.num_anchors = a.shape[0];
  Const c = cst(anchors);
  std::size_t n = static_cast<std::size_t>(p.num_anchors) * 4;
  p.anchors.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (c.type == kFloat32) {
      std::memcpy(&p.anchors[i], c.data + 4 * i, 4);
    } else if (c.type == kUInt8 && c.q) {
      p.anchors[i] = c.q->scale[0] * (static_cast<float>(c.data[i]) - c.q->zero_point[0]);
    } else {
      unsupported(op, std::string("anchors of type ") + type_name(c.type));
    }
  }
  int boxes = op.inputs[0], scores = op.inputs[1];
  int64_t nb = T(boxes).elements(), ns = T(scores).elements();
  if (nb != int64_t{p.num_anchors} * 4 || ns % p.num_anchors ||
      ns / p.num_anchors != o.num_classes + 1)
    fail(op, "box encodings/scores do not match " + std::to_string(p.num_anchors) +
                 " anchors and " + std::to_string(o.num_classes) + " classes (+1 background)");
  p.boxes = "post_boxes";
  p.scores = "post_scores";
  g_.node("Identity", {flt(boxes)}, {p.boxes});
  g_.node("Identity", {flt(scores)}, {p.scores});
  p.outputs = op.outputs;
  p.op_index = op_index_;
  for (int o : op.outputs) emitted_[o] = true;
  tr.post = std::move(p);
}

}  // namespace nns::tfl::detail
