// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_if
 *
 * Routes each frame by a condition on its tensors:
 *   if (compared-value OPERATOR supplied-value) then <then> on src_0 else <else> on src_1
 * where the actions are PASSTHROUGH (whole frame), SKIP (drop) or TENSORPICK (the tensors
 * listed in then-option / else-option). The condition logic is src/core/tensor_if_cond.h;
 * CUSTOM conditions come from nnstreamer_if_custom_register() (include/nnstreamer/tensor_if.h).
 *
 * Pads src_0 / src_1 appear when the input caps arrive (one per action other than SKIP). A
 * frame sent to one pad is announced as a GAP on the other, so sinks on both branches preroll.
 * Properties are read when caps are negotiated.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=10 ! video/x-raw,format=GRAY8,width=4,height=4 !
 *     tensor_converter ! tensor_if name=tif compared-value=A_VALUE
 *     compared-value-option=0:0:0:0,0 operator=GE supplied-value=128 then=PASSTHROUGH
 *     else=SKIP  tif.src_0 ! queue ! tensor_sink
 */
#include <memory>
#include <atomic>
#include <mutex>
#include <optional>
#include <string>

#include "core/c_tensor_info.h"
#include "core/tensor_if_cond.h"
#include "gst/element_glue.h"
#include "gst/flow_util.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "gst/tensor_if_custom.h"

GST_DEBUG_CATEGORY_STATIC(tensor_if_debug);
#define GST_CAT_DEFAULT tensor_if_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_IF (gst_tensor_if_get_type())
G_DECLARE_FINAL_TYPE(GstTensorIf, gst_tensor_if, GST, TENSOR_IF, GstElement)
G_END_DECLS

namespace {

using nns::tif::Action;
using nns::tif::Compared;
using nns::tif::Op;

struct Settings {
  bool silent = true;
  Compared cv = Compared::kAValue;
  std::string cv_option;
  Op op = Op::kEq;
  std::string sv;
  Action act[2] = {Action::kPassthrough, Action::kPassthrough};
  std::string act_option[2];
};

// One branch (0 = then, 1 = else) as negotiated.
struct Branch {
  Action action = Action::kPassthrough;
  std::vector<uint32_t> pick;
  nns::TensorsInfo out;
  GstPad *pad = nullptr;  // owned by the element once added
  GstFlowReturn last = GST_FLOW_OK;
};

struct State {
  nns::TensorsInfo in;
  std::optional<nns::tif::Condition> cond;
  std::optional<nns::gst::IfCustom> custom;
  std::string custom_name;
  std::unique_ptr<nns::CTensorsConfig> c_info;  // for custom callbacks
  Branch br[2];
  bool silent = true;
};

struct IfPriv {
  std::mutex lock;  // guards settings
  Settings settings;
  // compared-value(-option), operator or supplied-value changed while streaming: the condition is
  // rebuilt before the next buffer (as NNStreamer, which reads them per buffer).
  std::atomic<bool> condition_changed{false};
  std::unique_ptr<State> state;  // streaming thread
};

enum {
  PROP_0,
  PROP_SILENT,
  PROP_CV,
  PROP_CV_OPTION,
  PROP_OP,
  PROP_SV,
  PROP_THEN,
  PROP_THEN_OPTION,
  PROP_ELSE,
  PROP_ELSE_OPTION
};

GType compared_value_get_type() {
  static GType type = 0;
  static const GEnumValue values[] = {
      {0, "A_VALUE", "Decide based on a single scalar value"},
      {3, "TENSOR_AVERAGE_VALUE", "Decide based on a average value of a specific tensor"},
      {5, "CUSTOM", "Decide based on a user defined callback"},
      {0, nullptr, nullptr}};
  if (g_once_init_enter(&type)) {
    GType t = g_enum_register_static("tensor_if_compared_value", values);
    g_once_init_leave(&type, t);
  }
  return type;
}

GType operator_get_type() {
  static GType type = 0;
  // Nicks (including the "eqaual" spelling) are upstream's: gst-launch accepts name or nick.
  static const GEnumValue values[] = {{0, "EQ", "eqaual"},
                                      {1, "NE", "not_eqaual"},
                                      {2, "GT", "greater_than"},
                                      {3, "GE", "greater_or_equal"},
                                      {4, "LT", "less_than"},
                                      {5, "LE", "less_or_equal"},
                                      {6, "RANGE_INCLUSIVE", "range inclusive"},
                                      {7, "RANGE_EXCLUSIVE", "range exclusive"},
                                      {8, "NOT_IN_RANGE_INCLUSIVE", "not in range inclusive"},
                                      {9, "NOT_IN_RANGE_EXCLUSIVE", "not in range exclusive"},
                                      {0, nullptr, nullptr}};
  if (g_once_init_enter(&type)) {
    GType t = g_enum_register_static("tensor_if_operator", values);
    g_once_init_leave(&type, t);
  }
  return type;
}

GType behavior_get_type() {
  static GType type = 0;
  static const GEnumValue values[] = {{0, "PASSTHROUGH", "passthrough"},
                                      {1, "SKIP", "skip"},
                                      {7, "TENSORPICK", "tensorpick"},
                                      {0, nullptr, nullptr}};
  if (g_once_init_enter(&type)) {
    GType t = g_enum_register_static("tensor_if_behavior", values);
    g_once_init_leave(&type, t);
  }
  return type;
}

const char *kOptionName[2] = {"then-option", "else-option"};

}  // namespace

struct _GstTensorIf {
  GstElement parent;
  GstPad *sinkpad;
  IfPriv *priv;
};

G_DEFINE_TYPE(GstTensorIf, gst_tensor_if, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_if, "tensor_if", GST_RANK_NONE, GST_TYPE_TENSOR_IF)

#define TIF_CAPS                                                              \
  "other/tensor, framerate = (fraction) [ 0, max ]; "                         \
  "other/tensors, format = (string) static, num_tensors = (int) [ 1, 256 ], " \
  "framerate = (fraction) [ 0, max ]"

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(TIF_CAPS));
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_SOMETIMES, GST_STATIC_CAPS(TIF_CAPS));

// Builds the state for newly negotiated input caps; throws with the option at fault.
static std::unique_ptr<State> make_state(GstTensorIf *self, const nns::TensorsConfig &cfg) {
  Settings s;
  {
    std::lock_guard<std::mutex> l(self->priv->lock);
    s = self->priv->settings;
  }
  auto stp = std::make_unique<State>();
  State &st = *stp;
  st.in = cfg.info;
  st.silent = s.silent;
  if (s.cv == Compared::kCustom) {
    st.custom_name = nns::trim(s.cv_option);
    if (st.custom_name.empty())
      nns::fail(nns::ErrorKind::kSettings,
                "compared-value=CUSTOM needs compared-value-option=<registered condition name>");
    st.custom = nns::gst::find_if_custom(st.custom_name);
    if (!st.custom)
      nns::fail(nns::ErrorKind::kNotFound,
                "compared-value-option: no custom condition is registered as '" + st.custom_name +
                    "' (nnstreamer_if_custom_register)");
    st.c_info = std::make_unique<nns::CTensorsConfig>(cfg);
  } else {
    st.cond.emplace(s.cv, s.cv_option, s.op, nns::tif::parse_supplied_value(s.sv), cfg.info);
  }
  for (int b = 0; b < 2; ++b) {
    st.br[b].action = s.act[b];
    if (s.act[b] == Action::kTensorPick)
      st.br[b].pick = nns::tif::parse_pick(s.act_option[b], kOptionName[b]);
    st.br[b].out = nns::tif::action_output(s.act[b], st.br[b].pick, cfg.info, kOptionName[b]);
  }
  return stp;
}

static GstPad *find_src_pad(GstTensorIf *self, int b) {
  std::string name = "src_" + std::to_string(b);
  return gst_element_get_static_pad(GST_ELEMENT(self), name.c_str());  // new ref or null
}

static void configure(GstTensorIf *self, const nns::TensorsConfig &cfg) {
  auto stp = make_state(self, cfg);
  State &st = *stp;
  bool added = false;
  for (int b = 0; b < 2; ++b) {
    Branch &br = st.br[b];
    if (br.action == Action::kSkip) continue;
    GstPad *pad = find_src_pad(self, b);
    if (!pad) {
      std::string name = "src_" + std::to_string(b);
      pad = gst_pad_new_from_static_template(&src_template, name.c_str());
      gst_pad_use_fixed_caps(pad);
      gst_pad_set_active(pad, TRUE);
      gst_element_add_pad(GST_ELEMENT(self), pad);  // takes the floating ref
      added = true;
    } else {
      gst_object_unref(pad);  // the element keeps it
    }
    br.pad = pad;
    nns::gst::start_src_pad(GST_ELEMENT(self), pad, "src_" + std::to_string(b),
                            nns::TensorsConfig{br.out, cfg.rate_n, cfg.rate_d});
  }
  if (added) gst_element_no_more_pads(GST_ELEMENT(self));
  self->priv->state = std::move(stp);
}

static gboolean tensor_if_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_IF(parent);
  if (GST_EVENT_TYPE(event) == GST_EVENT_CAPS) {
    nns::gst::EventPtr owned(event);
    return nns::gst::guard(self, FALSE, [&]() -> gboolean {
      GstCaps *caps;
      gst_event_parse_caps(event, &caps);
      auto cfg = nns::gst::config_from_caps(caps);
      if (!cfg.info.valid())
        nns::fail(nns::ErrorKind::kNegotiation,
                  "sink caps need the dimensions and types of every tensor, got " +
                      nns::gst::caps_to_string(caps));
      configure(self, cfg);
      return TRUE;
    });
  }
  // Stream-start and segment go out on the src pads when they are created.
  if (GST_EVENT_TYPE(event) == GST_EVENT_STREAM_START) {
    gst_event_unref(event);
    return TRUE;
  }
  return gst_pad_event_default(pad, parent, event);
}

static bool check_condition(GstTensorIf *self, State &st, const nns::gst::TensorMaps &maps) {
  if (!st.custom) return st.cond->evaluate(maps.pointers());
  std::vector<GstTensorMemory> mems(maps.size());
  for (std::size_t i = 0; i < maps.size(); ++i)
    mems[i] = {const_cast<uint8_t *>(maps.data(i)), maps.bytes(i)};
  gboolean result = FALSE;
  if (!st.custom->func(&st.c_info->get()->info, mems.data(), st.custom->data, &result))
    nns::fail(nns::ErrorKind::kLibrary,
              "custom condition '" + st.custom_name + "' returned an error");
  (void)self;
  return result;
}

static GstFlowReturn tensor_if_chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_IF(parent);
  nns::gst::BufferPtr in(buf);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto &st = self->priv->state;
    if (!st) nns::fail(nns::ErrorKind::kNegotiation, "buffer before caps");
    if (self->priv->condition_changed.exchange(false) && st->cond) {
      Settings s;
      {
        std::lock_guard<std::mutex> l(self->priv->lock);
        s = self->priv->settings;
      }
      if (s.cv != Compared::kCustom)
        st->cond.emplace(s.cv, s.cv_option, s.op, nns::tif::parse_supplied_value(s.sv), st->in);
    }
    nns::gst::check_static_buffer(buf, st->in);
    bool result;
    {
      nns::gst::TensorMaps maps(buf, st->in.size());
      result = check_condition(self, *st, maps);
    }
    int b = result ? 0 : 1;
    Branch &br = st->br[b];
    if (!st->silent)
      GST_INFO_OBJECT(self, "pts %" GST_TIME_FORMAT ": condition %s -> %s",
                      GST_TIME_ARGS(GST_BUFFER_PTS(buf)), result ? "TRUE" : "FALSE",
                      b ? "else" : "then");
    // Frames that a pad does not get are announced as gaps, so its sink prerolls.
    for (int o = 0; o < 2; ++o) {
      Branch &other = st->br[o];
      if ((o == b && br.action != Action::kSkip) || !other.pad || !GST_BUFFER_PTS_IS_VALID(buf))
        continue;
      gst_pad_push_event(other.pad,
                         gst_event_new_gap(GST_BUFFER_PTS(buf), GST_BUFFER_DURATION(buf)));
    }
    if (br.action == Action::kSkip) return GST_FLOW_OK;
    GstBuffer *out;
    if (br.action == Action::kPassthrough) {
      out = in.release();
    } else {
      out = gst_buffer_new();
      for (uint32_t i : br.pick)
        nns::gst::buffer_append_tensor(out, nns::gst::buffer_get_tensor(buf, i), st->in[i]);
      gst_buffer_copy_into(out, buf, GST_BUFFER_COPY_METADATA, 0, -1);
    }
    GstFlowReturn ret = gst_pad_push(br.pad, out);
    br.last = ret;
    if (ret == GST_FLOW_NOT_LINKED) {
      // Not linked is only fatal when no branch is linked.
      for (auto &o : st->br)
        if (o.pad && o.last != GST_FLOW_NOT_LINKED) return GST_FLOW_OK;
    }
    return ret;
  });
}

static void gst_tensor_if_set_property(GObject *object, guint id, const GValue *value,
                                       GParamSpec *pspec) {
  auto *self = GST_TENSOR_IF(object);
  std::lock_guard<std::mutex> l(self->priv->lock);
  Settings &s = self->priv->settings;
  auto str = [&] {
    const char *v = g_value_get_string(value);
    return std::string(v ? v : "");
  };
  switch (id) {
    case PROP_SILENT:
      s.silent = g_value_get_boolean(value);
      break;
    case PROP_CV:
      s.cv = static_cast<Compared>(g_value_get_enum(value));
      break;
    case PROP_CV_OPTION:
      s.cv_option = str();
      self->priv->condition_changed = true;
      break;
    case PROP_OP:
      s.op = static_cast<Op>(g_value_get_enum(value));
      self->priv->condition_changed = true;
      break;
    case PROP_SV:
      s.sv = str();
      self->priv->condition_changed = true;
      break;
    case PROP_THEN:
      s.act[0] = static_cast<Action>(g_value_get_enum(value));
      break;
    case PROP_THEN_OPTION:
      s.act_option[0] = str();
      break;
    case PROP_ELSE:
      s.act[1] = static_cast<Action>(g_value_get_enum(value));
      break;
    case PROP_ELSE_OPTION:
      s.act_option[1] = str();
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_if_get_property(GObject *object, guint id, GValue *value,
                                       GParamSpec *pspec) {
  auto *self = GST_TENSOR_IF(object);
  std::lock_guard<std::mutex> l(self->priv->lock);
  const Settings &s = self->priv->settings;
  switch (id) {
    case PROP_SILENT:
      g_value_set_boolean(value, s.silent);
      break;
    case PROP_CV:
      g_value_set_enum(value, static_cast<int>(s.cv));
      break;
    case PROP_CV_OPTION:
      g_value_set_string(value, s.cv_option.c_str());
      break;
    case PROP_OP:
      g_value_set_enum(value, static_cast<int>(s.op));
      break;
    case PROP_SV:
      g_value_set_string(value, s.sv.c_str());
      break;
    case PROP_THEN:
      g_value_set_enum(value, static_cast<int>(s.act[0]));
      break;
    case PROP_THEN_OPTION:
      g_value_set_string(value, s.act_option[0].c_str());
      break;
    case PROP_ELSE:
      g_value_set_enum(value, static_cast<int>(s.act[1]));
      break;
    case PROP_ELSE_OPTION:
      g_value_set_string(value, s.act_option[1].c_str());
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static GstStateChangeReturn tensor_if_change_state(GstElement *element, GstStateChange t) {
  auto *self = GST_TENSOR_IF(element);
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_if_parent_class)->change_state(element, t);
  if (t == GST_STATE_CHANGE_PAUSED_TO_READY) self->priv->state.reset();
  return ret;
}

static void gst_tensor_if_finalize(GObject *object) {
  delete GST_TENSOR_IF(object)->priv;
  G_OBJECT_CLASS(gst_tensor_if_parent_class)->finalize(object);
}

static void gst_tensor_if_class_init(GstTensorIfClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_if_debug, "tensor_if", 0, "tensor_if element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_if_set_property;
  gobject_class->get_property = gst_tensor_if_get_property;
  gobject_class->finalize = gst_tensor_if_finalize;
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log each decision", TRUE, rw));
  g_object_class_install_property(gobject_class, PROP_CV,
                                  g_param_spec_enum("compared-value", "CV",
                                                    "What is compared: one element, a tensor's "
                                                    "average or a custom callback",
                                                    compared_value_get_type(), 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_CV_OPTION,
      g_param_spec_string("compared-value-option", "CV_OPTION",
                          "Element 'd0:d1:..,tensor', tensor index, or custom condition name", "",
                          rw));
  g_object_class_install_property(
      gobject_class, PROP_SV,
      g_param_spec_string("supplied-value", "SV", "Value (or 'low,high' range) to compare with", "",
                          rw));
  g_object_class_install_property(
      gobject_class, PROP_OP,
      g_param_spec_enum("operator", "OP", "Comparison operator", operator_get_type(), 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_THEN,
      g_param_spec_enum("then", "THEN", "Action when the condition holds", behavior_get_type(), 0,
                        rw));
  g_object_class_install_property(
      gobject_class, PROP_THEN_OPTION,
      g_param_spec_string("then-option", "THEN_OPTION", "Tensors to pick (TENSORPICK), e.g. 0,2",
                          "", rw));
  g_object_class_install_property(
      gobject_class, PROP_ELSE,
      g_param_spec_enum("else", "ELSE", "Action when the condition does not hold",
                        behavior_get_type(), 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_ELSE_OPTION,
      g_param_spec_string("else-option", "ELSE_OPTION", "Tensors to pick (TENSORPICK), e.g. 1", "",
                          rw));
  gst_element_class_set_static_metadata(element_class, "TensorIf", "Filter/Tensor",
                                        "Routes tensor frames by a condition on their values",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
  element_class->change_state = tensor_if_change_state;
}

static void gst_tensor_if_init(GstTensorIf *self) {
  self->priv = new IfPriv();
  self->sinkpad = gst_pad_new_from_static_template(&sink_template, "sink");
  gst_pad_set_event_function(self->sinkpad, tensor_if_sink_event);
  gst_pad_set_chain_function(self->sinkpad, tensor_if_chain);
  gst_element_add_pad(GST_ELEMENT(self), self->sinkpad);
}
