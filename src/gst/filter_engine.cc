// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/filter_engine.h"

#include "profile/invoke_probe.h"

#include <chrono>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "core/filter_desc.h"
#include "core/filter_registry.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

namespace nns::gst {
namespace {

constexpr double kLatencyHeadroom = 0.05;   // added to the LATENCY query answer
constexpr double kLatencyThreshold = 0.25;  // change that triggers a latency message

int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

GstCaps *with_flexible(GstCaps *caps, int rate_n, int rate_d) {
  gst_caps_append(caps, caps_for_format(TensorFormat::kFlexible, rate_n, rate_d));
  return caps;
}

TensorsInfo as_static(TensorsInfo i) {
  i.format = TensorFormat::kStatic;
  return i;
}

// "; the stream comes from NAME" naming the element before `e` (with the framework and model
// when it is another tensor_filter), for negotiation errors; "" when it has no peer.
std::string upstream_note(GstBaseTransform *e) {
  GstPad *peer = gst_pad_get_peer(GST_BASE_TRANSFORM_SINK_PAD(e));
  if (!peer) return "";
  GstElement *up = gst_pad_get_parent_element(peer);
  gst_object_unref(peer);
  if (!up) return "";
  std::string note = std::string("; the stream comes from ") + GST_OBJECT_NAME(up);
  GstElementFactory *f = gst_element_get_factory(up);
  if (f && std::string(GST_OBJECT_NAME(f)) == "tensor_filter") {
    gchar *fw = nullptr, *model = nullptr;
    g_object_get(up, "framework", &fw, "model", &model, nullptr);
    note += std::string(" (tensor_filter framework '") + (fw ? fw : "") + "', model '" +
            (model ? model : "") + "')";
    g_free(fw);
    g_free(model);
  }
  gst_object_unref(up);
  return note;
}

struct WrappedOut {
  std::shared_ptr<FilterSession> session;
  void *data;
};

void free_wrapped(gpointer p) {
  auto *w = static_cast<WrappedOut *>(p);
  w->session->free_output(w->data);
  delete w;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// FilterStats

void FilterStats::reset() {
  recent_.fill(0);
  n_ = pos_ = 0;
  sum_recent_ = total_num_ = total_ns_ = 0;
  latency_us_ = 0;
  throughput_ = 0;
}

void FilterStats::record(int64_t ns, bool latency, bool throughput) {
  if (n_ == kRecent)
    sum_recent_ -= recent_[pos_];
  else
    ++n_;
  recent_[pos_] = ns;
  sum_recent_ += ns;
  pos_ = (pos_ + 1) % kRecent;
  total_num_ += 1;
  total_ns_ += ns;
  if (latency) {
    int64_t avg_ns = sum_recent_ / static_cast<int64_t>(n_);
    int64_t us = (avg_ns + 500) / 1000;
    if (us == 0 && avg_ns > 0) us = 1;
    latency_us_.store(us > INT32_MAX ? -1 : static_cast<int>(us), std::memory_order_relaxed);
  }
  if (throughput && total_ns_ > 0) {
    double t = static_cast<double>(total_num_) * 1e9 * 1000.0 / static_cast<double>(total_ns_);
    throughput_.store(t > INT32_MAX ? -1 : static_cast<int>(t), std::memory_order_relaxed);
  }
  // Keep the totals from growing without bound (NNStreamer drops old history the same way).
  if (total_num_ > 2000) {
    total_ns_ /= 2;
    total_num_ /= 2;
  }
}

// ---------------------------------------------------------------------------------------------
// Open and shape checks

std::string FilterEngine::where() const {
  return inst_ ? inst_->describe() : std::string("framework '") + settings_.framework + "'";
}

void FilterEngine::open(const FilterSettings &s) {
  try {
    open_model(s);
  } catch (const Error &e) {
    // input= asks a batch (tensor_query_serversrc max-batch) the model cannot take: the back
    // end's message (ONNX Runtime's reshape error...) becomes the detail of a clear refusal.
    if (!s.input.empty()) refuse_batch(s, make_open_spec(s).input, "input=", e.what());
    throw;
  }
}

void FilterEngine::open_model(const FilterSettings &s) {
  close();
  settings_ = s;
  combi_ = parse_combination(s.input_combination, s.output_combination);
  invoke_dynamic_ = s.invoke_dynamic;
  FilterOpenSpec spec = make_open_spec(s);
  auto conf = current_filter_conf();
  BackendRef be = FilterRegistry::get().resolve(spec.framework, spec.models, *conf);
  spec.invoke_async = s.invoke_async && be.iface->invoke_async != nullptr;
  if (invoke_dynamic_ && !(be.iface->flags & NNS_FILTER_FLAG_DYNAMIC))
    fail(ErrorKind::kSettings, "invoke-dynamic=true, but framework '" +
                                   std::string(be.iface->name) +
                                   "' does not support dynamic invoke");
  inst_ = FilterInstance::acquire(be, spec);
  open_warnings_.clear();
  if (!(inst_->flags() & NNS_FILTER_FLAG_TENSOR_NAMES))
    for (const char *prop : {"inputname", "outputname"}) {
      const TensorsInfo &given = prop[0] == 'i' ? spec.input : spec.output;
      if (names_only(given))
        open_warnings_.push_back(
            std::string(prop) + "='" + (prop[0] == 'i' ? s.inputname : s.outputname) +
            "' is ignored: framework '" + inst_->name() + "' does not pick tensors by name");
    }
  allocate_in_invoke_ = (inst_->flags() & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE) != 0;
  check_model_shapes();
  stats_.reset();
  last_posted_ns_ = 0;
  reported_ns_ = 0;
  prev_ts_ = GST_CLOCK_TIME_NONE;
  throttling_accum_ = 0;
}

void FilterEngine::check_model_shapes() {
  const FilterOpenSpec &spec = inst_->spec();
  TensorsInfo mi, mo;
  bool known = inst_->model_info(mi, mo);
  mi = as_static(mi);
  mo = as_static(mo);
  model_in_known_ = known && mi.size() > 0 && mi.valid();
  model_out_known_ = known && mo.size() > 0 && mo.valid();
  TensorsInfo pin = settings_.shared_key.empty() ? spec.input : make_open_spec(settings_).input;
  TensorsInfo pout = settings_.shared_key.empty() ? spec.output : make_open_spec(settings_).output;
  // inputname=/outputname= alone pick tensors (the model's shapes already reflect the choice);
  // they describe no shapes to check.
  if (names_only(pin)) pin = TensorsInfo{};
  if (names_only(pout)) pout = TensorsInfo{};
  if (pin.size() && model_in_known_ && !pin.same_as(mi))
    fail(ErrorKind::kNegotiation, where() + ": input='" + settings_.input + "' inputtype='" +
                                      settings_.inputtype + "' gives " + pin.to_string() +
                                      ", but the model's input is " + mi.to_string());
  if (pout.size() && model_out_known_ && !pout.same_as(mo))
    fail(ErrorKind::kNegotiation, where() + ": output='" + settings_.output + "' outputtype='" +
                                      settings_.outputtype + "' gives " + pout.to_string() +
                                      ", but the model's output is " + mo.to_string());
  eff_in_known_ = pin.size() > 0 || model_in_known_;
  eff_in_ = pin.size() ? pin : mi;
  in_source_ = pin.size() ? "input=/inputtype= give" : "the model's input is";
  eff_out_known_ = pout.size() > 0 || model_out_known_;
  eff_out_ = pout.size() ? pout : mo;
  out_source_ = pout.size() ? "output=/outputtype= give" : "the model's output is";
  // Keep the property names with the model's shapes (names are not part of the check).
  if (pin.size() && model_in_known_)
    for (std::size_t i = 0; i < eff_in_.size(); ++i)
      if (eff_in_[i].name.empty()) eff_in_[i].name = mi[i].name;
}

void FilterEngine::post_open_warnings() const {
  for (const std::string &w : open_warnings_) NNS_POST_WARNING(element_, w);
}

void FilterEngine::close() {
  inst_.reset();
  open_warnings_.clear();
  configured_ = false;
  eff_in_known_ = eff_out_known_ = model_in_known_ = model_out_known_ = false;
  eff_in_ = eff_out_ = TensorsInfo{};
}

void FilterEngine::reload(const std::vector<std::string> &models) {
  if (!inst_) return;
  FilterInstance::ReloadCheck check;
  if (configured_ && !invoke_dynamic_) {
    // The stream's caps stay as negotiated: the new model must take and give the same tensors.
    check = [&](const FilterInstance::ReloadProbe &probe) {
      std::string what = "framework '" + inst_->name() + "': model '" + join(models, ",") +
                         "' cannot replace model '" + join(inst_->spec().models, ",") + "': ";
      TensorsInfo mi, mo;
      bool known = probe.model_info(mi, mo);
      mi = as_static(mi);
      mo = as_static(mo);
      bool in_known = known && mi.size() && mi.valid();
      bool out_known = known && mo.size() && mo.valid();
      if (in_known && !mi.same_as(model_in_))
        fail(ErrorKind::kNegotiation, what + "the reloaded model's input " + mi.to_string() +
                                          " differs from the negotiated input " +
                                          model_in_.to_string());
      if (!(in_known && out_known)) {
        // As configure(): a model that does not tell its shapes learns the negotiated input.
        TensorsInfo computed;
        if (probe.set_input_info(model_in_, computed)) {
          computed = as_static(computed);
          if (computed.size() && computed.valid() && !out_known) mo = computed;
          out_known = out_known || (computed.size() && computed.valid());
        }
      }
      if (out_known && !mo.same_as(model_out_))
        fail(ErrorKind::kNegotiation, what + "the reloaded model's output " + mo.to_string() +
                                          " differs from the negotiated output " +
                                          model_out_.to_string());
    };
  }
  inst_->reload(models, check);
}

TensorsInfo FilterEngine::current_input() const {
  if (configured_) return model_in_;
  return eff_in_known_ ? eff_in_ : TensorsInfo{};
}

TensorsInfo FilterEngine::current_output() const {
  if (configured_) return model_out_;
  return eff_out_known_ ? eff_out_ : TensorsInfo{};
}

// ---------------------------------------------------------------------------------------------
// Caps

GstCaps *FilterEngine::transform_caps(GstPadDirection direction, GstCaps *caps) {
  if (!inst_) return nullptr;
  if (direction == GST_PAD_SRC && eff_in_known_ && !combi_.in_defined) {
    // src -> sink: the model's input, whatever downstream is (ANY too), so the elements before
    // the filter negotiate to it (tensor_converter then asks its source for 280x40 video for a
    // 3:280:40:1 model). The rate comes from downstream's caps when they give one.
    int rate_n = -1, rate_d = -1;
    if (caps && !gst_caps_is_empty(caps) && !gst_caps_is_any(caps)) {
      try {
        TensorsConfig c = config_from_structure(gst_caps_get_structure(caps, 0));
        rate_n = c.rate_n, rate_d = c.rate_d;
      } catch (const Error &) {
      }
    }
    TensorsConfig ic{eff_in_, rate_n, rate_d};
    return with_flexible(caps_from_config(ic, true), rate_n, rate_d);
  }
  if (!caps || gst_caps_is_empty(caps) || gst_caps_is_any(caps)) return nullptr;
  TensorsConfig in;
  try {
    in = config_from_structure(gst_caps_get_structure(caps, 0));
  } catch (const Error &) {
    return nullptr;
  }
  if (direction == GST_PAD_SINK) {
    if (invoke_dynamic_) return caps_for_format(TensorFormat::kFlexible, in.rate_n, in.rate_d);
    bool in_static = in.info.format == TensorFormat::kStatic && in.info.valid();
    TensorsInfo out;
    bool ok = false;
    try {
      if (eff_out_known_) {
        out = eff_out_;
        ok = true;
      } else if (in_static) {
        ok = inst_->set_input_info(combi_.model_input(in.info), out);
        out = as_static(out);
        ok = ok && out.valid();
      }
      if (ok && combi_.out_defined) {
        if (!combi_.out_in.empty() && !in_static) return nullptr;
        out = combi_.frame_output(in.info, out);
      }
    } catch (const Error &) {
      return nullptr;
    }
    if (!ok) return nullptr;
    TensorsConfig oc{out, in.rate_n, in.rate_d};
    return with_flexible(caps_from_config(oc, true), in.rate_n, in.rate_d);
  }
  return nullptr;  // src -> sink without a known model input
}

void FilterEngine::configure(GstCaps *incaps, GstCaps *outcaps) {
  if (!inst_) fail(ErrorKind::kInternal, "tensor_filter: caps set before the filter was opened");
  configured_ = false;
  TensorsConfig in_cfg = config_from_caps(incaps);
  TensorsConfig out_caps_cfg = config_from_caps(outcaps);
  in_flexible_ = in_cfg.info.format == TensorFormat::kFlexible;
  out_flexible_ = out_caps_cfg.info.format == TensorFormat::kFlexible;
  if (!in_flexible_ && !in_cfg.info.valid())
    fail(ErrorKind::kNegotiation, where() +
                                      ": the input caps do not describe complete static "
                                      "tensors: " +
                                      caps_to_string(incaps));
  frame_in_ = in_flexible_ ? TensorsInfo{} : in_cfg.info;

  if (invoke_dynamic_) {
    if (!out_flexible_)
      fail(ErrorKind::kNegotiation, where() +
                                        ": invoke-dynamic=true produces flexible tensors, "
                                        "but downstream accepts only " +
                                        caps_to_string(outcaps));
    model_in_ =
        in_flexible_ ? (eff_in_known_ ? eff_in_ : TensorsInfo{}) : combi_.model_input(frame_in_);
    model_out_ = TensorsInfo{};
    frame_out_ = TensorsInfo{};
    frame_out_.format = TensorFormat::kFlexible;
  } else {
    if (!in_flexible_) {
      model_in_ = combi_.model_input(frame_in_);
      if (eff_in_known_ && !model_in_.same_as(eff_in_)) {
        const std::string cause = where() + ": the input stream " +
                                  (combi_.in_defined ? "(after input-combination) " : "") + "has " +
                                  model_in_.to_string() + ", but " + in_source_ + " " +
                                  eff_in_.to_string() + "; caps: " + caps_to_string(incaps);
        refuse_batch(settings_, model_in_, "the stream ", cause);
        fail(ErrorKind::kNegotiation, cause + upstream_note(element_));
      }
    } else {
      if (!eff_in_known_)
        fail(ErrorKind::kNegotiation,
             where() + ": the input is flexible (" + caps_to_string(incaps) +
                 ") and the model does not give its input shapes; set input= and inputtype=, "
                 "use static caps, or set invoke-dynamic=true");
      model_in_ = eff_in_;
    }
    bool told = false;
    TensorsInfo computed;
    if (!(model_in_known_ && model_out_known_)) {
      told = inst_->set_input_info(model_in_, computed);
      computed = as_static(computed);
    }
    if (eff_out_known_) {
      model_out_ = eff_out_;
      if (told && computed.size() && !computed.same_as(eff_out_))
        fail(ErrorKind::kNegotiation, where() + ": for input " + model_in_.to_string() +
                                          " the model produces " + computed.to_string() + ", but " +
                                          out_source_ + " " + eff_out_.to_string());
    } else if (told && computed.valid()) {
      model_out_ = computed;
    } else {
      fail(ErrorKind::kNegotiation,
           where() + ": cannot tell the output tensors for input " + model_in_.to_string() +
               ": the back end neither reports them nor computes them; set output= and "
               "outputtype=");
    }
    if (combi_.out_defined && !combi_.out_in.empty() && in_flexible_ && !out_flexible_)
      fail(ErrorKind::kNegotiation, where() +
                                        ": output-combination passes input tensors "
                                        "through, which needs static input caps or "
                                        "flexible output caps");
    frame_out_ = in_flexible_ && !combi_.out_in.empty()
                     ? combi_.frame_output(TensorsInfo{}, model_out_)  // checked at runtime
                     : combi_.frame_output(frame_in_, model_out_);
    if (!out_flexible_ && !out_caps_cfg.info.same_as(frame_out_))
      fail(ErrorKind::kNegotiation, where() + ": downstream caps " + caps_to_string(outcaps) +
                                        " do not match the filter output " +
                                        frame_out_.to_string());
    // Flexible output caps a capsfilter decorated with static fields must not contradict them.
    if (out_flexible_ && frame_out_.valid())
      check_flexible_caps_fields(outcaps, frame_out_, where() + " produces");
  }

  // Scratch and headers for the per-buffer path.
  in_.assign(frame_in_.size(), InTensor{});
  in_tm_.assign(frame_in_.size(), GstTensorMemory{nullptr, 0});
  invoke_in_.assign(model_in_.size(), GstTensorMemory{nullptr, 0});
  out_.assign(model_out_.size(), OutTensor{});
  out_tm_.assign(model_out_.size(), GstTensorMemory{nullptr, 0});
  out_headers_.assign(model_out_.size(), {});
  if (out_flexible_)
    for (std::size_t i = 0; i < model_out_.size(); ++i) {
      write_meta_header(flexible_header(model_out_[i].type, model_out_[i].dims),
                        out_headers_[i].data());
    }
  if (invoke_dynamic_) {
    dyn_in_ = new_desc();
    dyn_out_ = new_desc();
    out_tm_.assign(kTensorLimit, GstTensorMemory{nullptr, 0});
  }
  if (async_) {
    if (!dyn_in_) dyn_in_ = new_desc();
    async_->configure(model_out_, out_flexible_);
  }
  configured_ = true;
}

// ---------------------------------------------------------------------------------------------
// Per buffer

void FilterEngine::set_throttling_delay(GstClockTimeDiff diff) {
  GstClockTimeDiff cur = throttling_delay_.load();
  throttling_delay_.store(cur != 0 ? std::min(cur, diff) : diff);
}

bool FilterEngine::throttled(GstBuffer *inbuf) {
  GstClockTimeDiff delay_set = throttling_delay_.load(std::memory_order_relaxed);
  if (delay_set == 0) return false;
  GstClockTime cur = GST_BUFFER_PTS(inbuf);
  GstClockTime prev = prev_ts_;
  prev_ts_ = cur;
  if (!GST_CLOCK_TIME_IS_VALID(prev) || !GST_CLOCK_TIME_IS_VALID(cur)) return false;
  throttling_accum_ += GST_CLOCK_DIFF(prev, cur);
  GstClockTimeDiff delay = std::max<GstClockTimeDiff>(
      static_cast<GstClockTimeDiff>(stats_.latency_us()) * 1000, delay_set);
  if (throttling_accum_ < delay) {
    double rate = GST_BUFFER_DURATION_IS_VALID(inbuf)
                      ? static_cast<double>(GST_BUFFER_DURATION(inbuf)) / static_cast<double>(delay)
                      : 1.0;
    // A QoS event's negative jitter may not reach before time 0.
    GstClockTimeDiff jitter =
        std::max<GstClockTimeDiff>(throttling_accum_ - delay, -static_cast<GstClockTimeDiff>(cur));
    gst_pad_push_event(GST_BASE_TRANSFORM_SINK_PAD(element_),
                       gst_event_new_qos(GST_QOS_TYPE_OVERFLOW, rate, jitter, cur));
    return true;
  }
  throttling_accum_ = 0;
  return false;
}

void FilterEngine::release_inputs(std::size_t n) {
  for (std::size_t i = 0; i < n && i < in_.size(); ++i) {
    InTensor &t = in_[i];
    if (t.mapped) gst_memory_unmap(t.mem, &t.map);
    t.mapped = false;
    if (t.owned) gst_memory_unref(t.mem);
    t.owned = false;
    t.mem = nullptr;
  }
}

void FilterEngine::release_outputs(bool free_mems) {
  for (auto &o : out_) {
    if (o.mapped) gst_memory_unmap(o.mem, &o.map);
    o.mapped = false;
    if (free_mems && o.mem) gst_memory_unref(o.mem);
    if (free_mems) o.mem = nullptr;
  }
}

GstMemory *FilterEngine::pass_input(std::size_t i) {
  InTensor &t = in_[i];
  if (!in_flexible_ && out_flexible_) {
    return memory_with_header(flexible_header(frame_in_[i].type, frame_in_[i].dims), t.mem);
  }
  if (in_flexible_ && !out_flexible_) return gst_memory_share(t.mem, kMetaHeaderSize, -1);
  return gst_memory_ref(t.mem);
}

// This frame's model inputs (types and dims from the flexible headers or the caps).
void FilterEngine::describe_input(nns_tensors_desc &d, std::size_t nin) const {
  d.num_tensors = static_cast<uint32_t>(nin);
  d.format = static_cast<uint32_t>(TensorFormat::kStatic);
  for (std::size_t k = 0; k < nin; ++k) {
    std::size_t i = combi_.in_defined ? combi_.in[k] : k;
    const TensorInfo ti = in_flexible_ ? in_[i].header.info() : frame_in_[i];
    d.tensors[k].name[0] = '\0';
    d.tensors[k].type = static_cast<uint32_t>(ti.type);
    std::memcpy(d.tensors[k].dims, ti.dims.data(), sizeof d.tensors[k].dims);
  }
}

void FilterEngine::record_invoke(int64_t dur_ns) {
  const bool lat = prof_latency_.load(std::memory_order_relaxed);
  const bool thr = prof_throughput_.load(std::memory_order_relaxed);
  const bool rep = prof_report_.load(std::memory_order_relaxed);
  if (lat || thr || rep) stats_.record(dur_ns, lat || rep, thr);
  if (rep) track_latency();
  if (nns::profile::invoke_probe_on())
    nns::profile::note_invoke(GST_ELEMENT_CAST(element_), dur_ns);
}

void FilterEngine::track_latency() {
  int64_t est = static_cast<int64_t>(stats_.latency_us()) * 1000;
  if (est <= 0) return;
  int64_t reported = reported_ns_.load(std::memory_order_relaxed);
  double dev = reported > 0 ? std::fabs(double(est - reported)) / double(reported) : 0.0;
  if (est <= reported && dev <= kLatencyThreshold) return;
  // Post once per notable change, not on every buffer until the application re-queries.
  if (last_posted_ns_ > 0 &&
      std::fabs(double(est - last_posted_ns_)) / double(last_posted_ns_) <= kLatencyThreshold)
    return;
  last_posted_ns_ = est;
  gst_element_post_message(GST_ELEMENT_CAST(element_),
                           gst_message_new_latency(GST_OBJECT_CAST(element_)));
}

GstFlowReturn FilterEngine::process(GstBuffer *inbuf, GstBuffer *outbuf) {
  if (!configured_ || !inst_)
    fail(ErrorKind::kNegotiation, where() + ": a buffer arrived before the caps were set");

  // 1. Map the input tensors; their pointers go to the back end unchanged.
  guint nmem = gst_buffer_n_memory(inbuf);
  std::size_t count = nmem < kMemoryMax ? nmem : buffer_tensor_count(inbuf);
  if (!in_flexible_ && count != frame_in_.size())
    fail(ErrorKind::kStream, where() + ": the input buffer has " + std::to_string(count) +
                                 " tensor(s), the caps say " + frame_in_.to_string());
  if (in_.size() < count) {
    in_.resize(count);
    in_tm_.resize(count);
  }
  std::size_t mapped = 0;
  struct InputGuard {
    FilterEngine *e;
    std::size_t *n;
    ~InputGuard() { e->release_inputs(*n); }
  } in_guard{this, &mapped};
  for (std::size_t i = 0; i < count; ++i) {
    InTensor &t = in_[i];
    if (nmem < kMemoryMax || i + 1 < kMemoryMax) {
      t.mem = gst_buffer_peek_memory(inbuf, static_cast<guint>(i));
      t.owned = false;
    } else {
      t.mem = buffer_get_tensor(inbuf, i);
      t.owned = true;
    }
    ++mapped;
    if (!t.mem || !gst_memory_map(t.mem, &t.map, GST_MAP_READ))
      fail(ErrorKind::kStream, where() + ": cannot map input tensor " + std::to_string(i));
    t.mapped = true;
    uint8_t *data = t.map.data;
    std::size_t size = t.map.size;
    if (in_flexible_) {
      t.header = parse_meta_header(data, size);
      data += kMetaHeaderSize;
      size -= kMetaHeaderSize;
    } else if (size != frame_in_[i].byte_size()) {
      fail(ErrorKind::kStream, where() + ": input tensor " + std::to_string(i) + " has " +
                                   std::to_string(size) + " bytes, expected " +
                                   std::to_string(frame_in_[i].byte_size()) + " for " +
                                   frame_in_[i].to_string());
    }
    in_tm_[i] = GstTensorMemory{data, size};
  }

  // 2. Select the model inputs (input-combination).
  std::size_t nin = combi_.in_defined ? combi_.in.size() : count;
  if (invoke_in_.size() < nin) invoke_in_.resize(nin);
  for (std::size_t k = 0; k < nin; ++k) {
    std::size_t i = combi_.in_defined ? combi_.in[k] : k;
    if (i >= count)
      fail(ErrorKind::kStream, where() + ": input-combination index " + std::to_string(i) +
                                   " is out of range: the buffer has " + std::to_string(count) +
                                   " tensor(s)");
    invoke_in_[k] = in_tm_[i];
    if (in_flexible_ && !invoke_dynamic_ &&
        (k >= model_in_.size() || in_tm_[i].size != model_in_[k].byte_size()))
      fail(ErrorKind::kStream,
           where() + ": flexible input tensor " + std::to_string(i) + " has " +
               std::to_string(in_tm_[i].size) + " bytes, but the model input " + std::to_string(k) +
               " needs " +
               (k < model_in_.size() ? std::to_string(model_in_[k].byte_size()) + " (" +
                                           model_in_[k].to_string() + ")"
                                     : std::string("nothing (the model has fewer inputs)")));
  }
  if (!in_flexible_ && !invoke_dynamic_ && nin != model_in_.size())
    fail(ErrorKind::kStream, where() + ": internal: model input count mismatch");

  // One clock read before and after the invoke feeds both the latency / throughput /
  // latency-report properties and the nnsprofile tracer (record_invoke).
  const bool profiling = prof_latency_.load(std::memory_order_relaxed) ||
                         prof_throughput_.load(std::memory_order_relaxed) ||
                         prof_report_.load(std::memory_order_relaxed) ||
                         nns::profile::invoke_probe_on();
  int64_t t0 = profiling ? now_ns() : 0;
  int rc = 0;
  std::shared_ptr<FilterSession> session;
  std::vector<GstMemory *> &outs = outs_;  // model outputs kept, in order
  outs.clear();
  TensorsInfo dyn_info;

  if (async_) {
    // 3. invoke-async: the back end dispatches the outputs itself, now or later (through
    // AsyncDispatcher); this input gives no buffer of its own.
    describe_input(*dyn_in_, nin);
    nns_filter_async_ctx ctx = async_->begin_input(inbuf);
    int arc = -1;
    struct End {
      AsyncDispatcher *d;
      const nns_filter_async_ctx &c;
      int &rc;
      ~End() { d->end_input(c, rc); }
    } end{async_.get(), ctx, arc};
    arc = inst_->invoke_async(*dyn_in_, invoke_in_.data(), static_cast<uint32_t>(nin), ctx);
    if (profiling) record_invoke(now_ns() - t0);
    return GST_BASE_TRANSFORM_FLOW_DROPPED;
  } else if (invoke_dynamic_) {
    // 3a. invoke-dynamic: describe this frame's input, the back end allocates the output.
    nns_tensors_desc &d = *dyn_in_;
    describe_input(d, nin);
    dyn_out_->num_tensors = 0;
    for (auto &o : out_tm_) o = GstTensorMemory{nullptr, 0};
    inst_->invoke_dynamic(d, invoke_in_.data(), *dyn_out_, out_tm_.data(), &session);
    dyn_info = info_from_desc(*dyn_out_);
    for (std::size_t o = 0; o < dyn_info.size(); ++o) {
      void *data = out_tm_[o].data;
      if (combi_.keeps_output(static_cast<uint32_t>(o)) && data) {
        const MetaHeader h = flexible_header(dyn_info[o].type, dyn_info[o].dims, MediaType::kTensor,
                                             FlexHeaderKind::kMarkedFlexible);
        GstMemory *m = gst_allocator_alloc(nullptr, kMetaHeaderSize + out_tm_[o].size, nullptr);
        MemoryMap mm(m, GST_MAP_WRITE);
        write_meta_header(h, mm.data());
        std::memcpy(mm.data() + kMetaHeaderSize, data, out_tm_[o].size);
        outs.push_back(m);
      }
      if (data) session->free_output(data);
    }
  } else if (allocate_in_invoke_) {
    // 3b. The back end allocates; wrap its memory (copy only to prepend a flexible header).
    for (std::size_t o = 0; o < model_out_.size(); ++o)
      out_tm_[o] = GstTensorMemory{nullptr, model_out_[o].byte_size()};
    rc = inst_->invoke(invoke_in_.data(), static_cast<uint32_t>(nin), out_tm_.data(),
                       static_cast<uint32_t>(model_out_.size()), &session);
    for (std::size_t o = 0; o < model_out_.size(); ++o) {
      void *data = out_tm_[o].data;
      if (!data) {
        if (rc == 0) {
          for (auto *m : outs) gst_memory_unref(m);
          fail(ErrorKind::kLibrary,
               where() + ": the back end returned no data for output " + std::to_string(o));
        }
        continue;
      }
      if (rc != 0 || !combi_.keeps_output(static_cast<uint32_t>(o))) {
        session->free_output(data);
        continue;
      }
      std::size_t size = model_out_[o].byte_size();
      if (out_flexible_) {
        GstMemory *m = gst_allocator_alloc(nullptr, kMetaHeaderSize + size, nullptr);
        MemoryMap mm(m, GST_MAP_WRITE);
        std::memcpy(mm.data(), out_headers_[o].data(), kMetaHeaderSize);
        std::memcpy(mm.data() + kMetaHeaderSize, data, size);
        session->free_output(data);
        outs.push_back(m);
      } else {
        auto *w = new WrappedOut{session, data};
        outs.push_back(
            gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, data, size, 0, size, w, free_wrapped));
      }
    }
  } else {
    // 3c. Allocate the outputs here; the back end writes into them.
    const std::size_t hsize = out_flexible_ ? kMetaHeaderSize : 0;
    struct OutGuard {
      FilterEngine *e;
      bool done = false;
      ~OutGuard() {
        if (!done) e->release_outputs(true);
      }
    } out_guard{this};
    for (std::size_t o = 0; o < model_out_.size(); ++o) {
      OutTensor &t = out_[o];
      std::size_t size = model_out_[o].byte_size();
      t.mem = gst_allocator_alloc(nullptr, hsize + size, nullptr);
      if (!t.mem || !gst_memory_map(t.mem, &t.map, GST_MAP_WRITE))
        fail(ErrorKind::kStream, where() + ": cannot allocate " + std::to_string(hsize + size) +
                                     " bytes for output tensor " + std::to_string(o));
      t.mapped = true;
      if (hsize) std::memcpy(t.map.data, out_headers_[o].data(), hsize);
      out_tm_[o] = GstTensorMemory{t.map.data + hsize, size};
    }
    rc = inst_->invoke(invoke_in_.data(), static_cast<uint32_t>(nin), out_tm_.data(),
                       static_cast<uint32_t>(model_out_.size()));
    release_outputs(false);
    if (rc == 0) {
      for (std::size_t o = 0; o < model_out_.size(); ++o) {
        if (combi_.keeps_output(static_cast<uint32_t>(o)))
          outs.push_back(out_[o].mem);
        else
          gst_memory_unref(out_[o].mem);
        out_[o].mem = nullptr;
      }
      out_guard.done = true;
    }
  }

  if (profiling) record_invoke(now_ns() - t0);
  if (rc > 0) return GST_BASE_TRANSFORM_FLOW_DROPPED;  // the back end asked to drop it

  // 4. Assemble: passed-through input tensors first (output-combination), then the outputs.
  std::size_t total = combi_.out_in.size() + outs.size();
  const TensorsInfo &out_desc = invoke_dynamic_ ? dyn_info : model_out_;
  std::size_t oi = 0;
  auto append = [&](GstMemory *m, const TensorInfo &info) {
    if (total <= kMemoryMax)
      gst_buffer_append_memory(outbuf, m);
    else
      buffer_append_tensor(outbuf, m, info);
  };
  for (uint32_t i : combi_.out_in) {
    if (i >= count) {
      for (auto *m : outs) gst_memory_unref(m);
      fail(ErrorKind::kStream, where() + ": output-combination i" + std::to_string(i) +
                                   " is out of range: the buffer has " + std::to_string(count) +
                                   " tensor(s)");
    }
    TensorInfo ti = in_flexible_ ? in_[i].header.info() : frame_in_[i];
    append(pass_input(i), ti);
  }
  for (std::size_t o = 0; o < out_desc.size(); ++o) {
    if (!combi_.keeps_output(static_cast<uint32_t>(o))) continue;
    if (oi < outs.size()) append(outs[oi++], out_desc[o]);
  }
  return GST_FLOW_OK;
}

}  // namespace nns::gst
