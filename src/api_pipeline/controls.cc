// SPDX-License-Identifier: LGPL-2.1-only
// ml_pipeline_switch_* (input-selector / output-selector), ml_pipeline_valve_* and
// ml_pipeline_element_* (typed property access on any named element).
#include <cstring>

#include "api_pipeline/pipeline_internal.h"

namespace nns::capi {
namespace {

Node *find_node(Pipeline *p, const char *name) {
  auto it = p->nodes.find(name);
  return it == p->nodes.end() ? nullptr : it->second.get();
}

std::string factory_of(GstElement *e) {
  GstElementFactory *f = gst_element_get_factory(e);
  return f ? GST_OBJECT_NAME(f) : G_OBJECT_TYPE_NAME(e);
}

// A handle on node `name` of kind `want` (any node for kElement). g_mu held.
int get_handle(ml_pipeline_h pipe, const char *name, HandleKind want, void **out, const char *func,
               Node **node_out) {
  if (!out)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(func) + ": the output handle pointer is NULL");
  *out = nullptr;
  if (!name)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(func) + ": the element name is NULL");
  Pipeline *p = live_pipeline(pipe, func);
  if (!p) return ML_ERROR_INVALID_PARAMETER;
  Node *n = find_node(p, name);
  if (!n) {
    GstElement *e = gst_bin_get_by_name(GST_BIN(p->bin), name);
    if (!e)
      return fail(ML_ERROR_INVALID_PARAMETER, std::string(func) + ": there is no element named '" +
                                                  name + "' in " + p->describe());
    if (want != HandleKind::kElement) {
      std::string f = factory_of(e);
      gst_object_unref(e);
      return fail(ML_ERROR_INVALID_PARAMETER,
                  std::string(func) + ": '" + name + "' is a " + f + ", not a " +
                      (want == HandleKind::kValve ? "valve" : "input-selector or output-selector"));
    }
    auto nn = std::make_unique<Node>();
    nn->pipe = p;
    nn->element = e;  // takes the reference
    nn->name = name;
    nn->factory = factory_of(e);
    nn->kind = NodeKind::kCommon;
    n = nn.get();
    p->nodes.emplace(name, std::move(nn));
  }
  bool ok = want == HandleKind::kElement ||
            (want == HandleKind::kValve && n->kind == NodeKind::kValve) ||
            (want == HandleKind::kSwitch &&
             (n->kind == NodeKind::kInputSelector || n->kind == NodeKind::kOutputSelector));
  if (!ok)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(func) + ": '" + name + "' is a " + n->factory + ", not a " +
                    (want == HandleKind::kValve ? "valve" : "input-selector or output-selector"));
  auto *h = new Handle();
  h->kind = want;
  h->pipe = p;
  h->node = n;
  add_handle(h);
  *out = h;
  if (node_out) *node_out = n;
  return ML_ERROR_NONE;
}

int release(void *handle, HandleKind kind, const char *func, const char *arg) {
  std::lock_guard lk(registry_lock());
  Handle *h = live_handle(handle, kind, func, arg);
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  remove_handle(h);
  delete h;
  return ML_ERROR_NONE;
}

const char *type_word(GType t) {
  if (t == G_TYPE_BOOLEAN) return "boolean";
  if (t == G_TYPE_STRING) return "string";
  if (t == G_TYPE_INT) return "int32";
  if (t == G_TYPE_INT64 || t == G_TYPE_LONG) return "int64";
  if (t == G_TYPE_UINT) return "uint32";
  if (t == G_TYPE_UINT64 || t == G_TYPE_ULONG) return "uint64";
  if (t == G_TYPE_DOUBLE || t == G_TYPE_FLOAT) return "double";
  if (G_TYPE_IS_ENUM(t)) return "enum";
  return g_type_name(t);
}

// Whether a property of GType `actual` can be used through the API of kind `want` (the
// accepted pairs are NNStreamer's: enums also through int32/uint32, float through double,
// long through int64).
bool compatible(GType want, GType actual) {
  if (want == actual) return true;
  if (G_TYPE_IS_ENUM(actual) && (want == G_TYPE_ENUM || want == G_TYPE_INT || want == G_TYPE_UINT))
    return true;
  return (want == G_TYPE_INT64 && actual == G_TYPE_LONG) ||
         (want == G_TYPE_UINT64 && actual == G_TYPE_ULONG) ||
         (want == G_TYPE_DOUBLE && actual == G_TYPE_FLOAT);
}

// Finds and checks the property; g_mu held. pspec_out borrowed from the class.
int check_property(Handle *h, const char *prop, GType want, bool write, const char *func,
                   GParamSpec **pspec_out) {
  if (!prop) return fail(ML_ERROR_INVALID_PARAMETER, std::string(func) + ": property_name is NULL");
  GParamSpec *ps = g_object_class_find_property(G_OBJECT_GET_CLASS(h->node->element), prop);
  std::string who = "element '" + h->node->name + "' (" + h->node->factory + ")";
  if (!ps)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(func) + ": " + who + " has no property '" + prop + "'");
  if (!compatible(want, ps->value_type))
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(func) + ": property '" + prop + "' of " + who + " is of type " +
                    type_word(ps->value_type) + " (" + g_type_name(ps->value_type) + "), not " +
                    type_word(want) + "; use ml_pipeline_element_" + (write ? "set" : "get") +
                    "_property_" + type_word(ps->value_type));
  if (write && !(ps->flags & G_PARAM_WRITABLE))
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(func) + ": property '" + prop + "' of " + who + " is read-only");
  if (!write && !(ps->flags & G_PARAM_READABLE))
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(func) + ": property '" + prop + "' of " + who + " is write-only");
  *pspec_out = ps;
  return ML_ERROR_NONE;
}

struct Arg {
  int64_t i = 0;
  uint64_t u = 0;
  double d = 0;
  const char *s = nullptr;
};

int set_prop(ml_pipeline_element_h eh, const char *prop, GType want, Arg a, const char *func) {
  std::lock_guard lk(registry_lock());
  Handle *h = live_handle(eh, HandleKind::kElement, func, "elem_h");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  GParamSpec *ps = nullptr;
  if (int rc = check_property(h, prop, want, true, func, &ps); rc != ML_ERROR_NONE) return rc;
  GValue v = G_VALUE_INIT;
  g_value_init(&v, ps->value_type);
  GType t = ps->value_type;
  if (G_TYPE_IS_ENUM(t)) {
    auto *ec = static_cast<GEnumClass *>(g_type_class_ref(t));
    gint ev = want == G_TYPE_INT ? static_cast<gint>(a.i) : static_cast<gint>(a.u);
    bool known = g_enum_get_value(ec, ev) != nullptr;
    std::string values;
    for (guint k = 0; k < ec->n_values; ++k)
      values +=
          (k ? ", " : "") + std::to_string(ec->values[k].value) + "=" + ec->values[k].value_nick;
    g_type_class_unref(ec);
    if (!known)
      return fail(ML_ERROR_INVALID_PARAMETER,
                  std::string(func) + ": " + std::to_string(ev) + " is not a value of property '" +
                      prop + "' of element '" + h->node->name + "' (" + values + ")");
    g_value_set_enum(&v, ev);
  } else if (t == G_TYPE_BOOLEAN) {
    g_value_set_boolean(&v, a.i != 0);
  } else if (t == G_TYPE_STRING) {
    g_value_set_string(&v, a.s);
  } else if (t == G_TYPE_INT) {
    g_value_set_int(&v, static_cast<gint>(a.i));
  } else if (t == G_TYPE_INT64) {
    g_value_set_int64(&v, a.i);
  } else if (t == G_TYPE_LONG) {
    g_value_set_long(&v, static_cast<glong>(a.i));
  } else if (t == G_TYPE_UINT) {
    g_value_set_uint(&v, static_cast<guint>(a.u));
  } else if (t == G_TYPE_UINT64) {
    g_value_set_uint64(&v, a.u);
  } else if (t == G_TYPE_ULONG) {
    g_value_set_ulong(&v, static_cast<gulong>(a.u));
  } else if (t == G_TYPE_DOUBLE) {
    g_value_set_double(&v, a.d);
  } else if (t == G_TYPE_FLOAT) {
    g_value_set_float(&v, static_cast<float>(a.d));
  }
  // Out-of-range numbers: GLib would only warn and keep the old value.
  if (g_param_value_validate(ps, &v)) {
    g_value_unset(&v);
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(func) +
                                                ": the value is out of the range of property '" +
                                                prop + "' of element '" + h->node->name + "'");
  }
  g_object_set_property(G_OBJECT(h->node->element), prop, &v);
  g_value_unset(&v);
  return ML_ERROR_NONE;
}

int get_prop(ml_pipeline_element_h eh, const char *prop, GType want, void *out, const char *func) {
  std::lock_guard lk(registry_lock());
  Handle *h = live_handle(eh, HandleKind::kElement, func, "elem_h");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  if (!prop) return fail(ML_ERROR_INVALID_PARAMETER, std::string(func) + ": property_name is NULL");
  if (!out) return fail(ML_ERROR_INVALID_PARAMETER, std::string(func) + ": value is NULL");
  GParamSpec *ps = nullptr;
  if (int rc = check_property(h, prop, want, false, func, &ps); rc != ML_ERROR_NONE) return rc;
  GValue v = G_VALUE_INIT;
  g_value_init(&v, ps->value_type);
  g_object_get_property(G_OBJECT(h->node->element), prop, &v);
  GType t = ps->value_type;
  if (G_TYPE_IS_ENUM(t)) {
    if (want == G_TYPE_INT)
      *static_cast<int32_t *>(out) = g_value_get_enum(&v);
    else
      *static_cast<uint32_t *>(out) = static_cast<uint32_t>(g_value_get_enum(&v));
  } else if (t == G_TYPE_BOOLEAN) {
    *static_cast<int32_t *>(out) = g_value_get_boolean(&v) ? 1 : 0;
  } else if (t == G_TYPE_STRING) {
    *static_cast<char **>(out) = g_value_dup_string(&v);
  } else if (t == G_TYPE_INT) {
    *static_cast<int32_t *>(out) = g_value_get_int(&v);
  } else if (t == G_TYPE_INT64) {
    *static_cast<int64_t *>(out) = g_value_get_int64(&v);
  } else if (t == G_TYPE_LONG) {
    *static_cast<int64_t *>(out) = g_value_get_long(&v);
  } else if (t == G_TYPE_UINT) {
    *static_cast<uint32_t *>(out) = g_value_get_uint(&v);
  } else if (t == G_TYPE_UINT64) {
    *static_cast<uint64_t *>(out) = g_value_get_uint64(&v);
  } else if (t == G_TYPE_ULONG) {
    *static_cast<uint64_t *>(out) = g_value_get_ulong(&v);
  } else if (t == G_TYPE_DOUBLE) {
    *static_cast<double *>(out) = g_value_get_double(&v);
  } else if (t == G_TYPE_FLOAT) {
    *static_cast<double *>(out) = g_value_get_float(&v);
  }
  g_value_unset(&v);
  return ML_ERROR_NONE;
}

}  // namespace
}  // namespace nns::capi

using namespace nns;
using namespace nns::capi;

NNS_CAPI int ml_pipeline_switch_get_handle(ml_pipeline_h pipe, const char *switch_name,
                                           ml_pipeline_switch_e *switch_type,
                                           ml_pipeline_switch_h *switch_handle) {
  std::lock_guard lk(registry_lock());
  Node *n = nullptr;
  int rc = get_handle(pipe, switch_name, HandleKind::kSwitch, switch_handle,
                      "ml_pipeline_switch_get_handle", &n);
  if (rc == ML_ERROR_NONE && switch_type)
    *switch_type = n->kind == NodeKind::kInputSelector ? ML_PIPELINE_SWITCH_INPUT_SELECTOR
                                                       : ML_PIPELINE_SWITCH_OUTPUT_SELECTOR;
  return rc;
}

NNS_CAPI int ml_pipeline_switch_release_handle(ml_pipeline_switch_h switch_handle) {
  return release(switch_handle, HandleKind::kSwitch, "ml_pipeline_switch_release_handle",
                 "switch_handle");
}

namespace {

std::vector<std::string> switch_pads(Node *n) {
  std::vector<std::string> out;
  GstIterator *it = n->kind == NodeKind::kInputSelector ? gst_element_iterate_sink_pads(n->element)
                                                        : gst_element_iterate_src_pads(n->element);
  GValue item = G_VALUE_INIT;
  for (bool done = false; !done;) {
    switch (gst_iterator_next(it, &item)) {
      case GST_ITERATOR_OK:
        out.emplace_back(GST_PAD_NAME(g_value_get_object(&item)));
        g_value_reset(&item);
        break;
      case GST_ITERATOR_RESYNC:
        out.clear();
        gst_iterator_resync(it);
        break;
      default:
        done = true;
        break;
    }
  }
  g_value_unset(&item);
  gst_iterator_free(it);
  return out;
}

}  // namespace

NNS_CAPI int ml_pipeline_switch_select(ml_pipeline_switch_h switch_handle, const char *pad_name) {
  constexpr const char *F = "ml_pipeline_switch_select";
  std::lock_guard lk(registry_lock());
  Handle *h = live_handle(switch_handle, HandleKind::kSwitch, F, "switch_handle");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  if (!pad_name) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": pad_name is NULL");
  Node *n = h->node;
  GstPad *pad = gst_element_get_static_pad(n->element, pad_name);
  bool right_side =
      pad && ((n->kind == NodeKind::kInputSelector) == (GST_PAD_DIRECTION(pad) == GST_PAD_SINK));
  if (!right_side) {
    if (pad) gst_object_unref(pad);
    std::string list;
    for (const auto &s : switch_pads(n)) list += (list.empty() ? "" : ", ") + s;
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": " + n->factory + " '" + n->name + "' has no selectable pad '" +
                    pad_name + "' (its pads: " + (list.empty() ? "none" : list) + ")");
  }
  g_object_set(n->element, "active-pad", pad, nullptr);
  gst_object_unref(pad);
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_switch_get_pad_list(ml_pipeline_switch_h switch_handle, char ***list) {
  constexpr const char *F = "ml_pipeline_switch_get_pad_list";
  std::lock_guard lk(registry_lock());
  Handle *h = live_handle(switch_handle, HandleKind::kSwitch, F, "switch_handle");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  if (!list) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": list is NULL");
  auto pads = switch_pads(h->node);
  *list = static_cast<char **>(g_malloc0(sizeof(char *) * (pads.size() + 1)));
  for (std::size_t i = 0; i < pads.size(); ++i) (*list)[i] = g_strdup(pads[i].c_str());
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_valve_get_handle(ml_pipeline_h pipe, const char *valve_name,
                                          ml_pipeline_valve_h *valve_handle) {
  std::lock_guard lk(registry_lock());
  return get_handle(pipe, valve_name, HandleKind::kValve, valve_handle,
                    "ml_pipeline_valve_get_handle", nullptr);
}

NNS_CAPI int ml_pipeline_valve_release_handle(ml_pipeline_valve_h valve_handle) {
  return release(valve_handle, HandleKind::kValve, "ml_pipeline_valve_release_handle",
                 "valve_handle");
}

NNS_CAPI int ml_pipeline_valve_set_open(ml_pipeline_valve_h valve_handle, bool open) {
  std::lock_guard lk(registry_lock());
  Handle *h =
      live_handle(valve_handle, HandleKind::kValve, "ml_pipeline_valve_set_open", "valve_handle");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  g_object_set(h->node->element, "drop", open ? FALSE : TRUE, nullptr);
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_element_get_handle(ml_pipeline_h pipe, const char *element_name,
                                            ml_pipeline_element_h *elem_h) {
  std::lock_guard lk(registry_lock());
  return get_handle(pipe, element_name, HandleKind::kElement, elem_h,
                    "ml_pipeline_element_get_handle", nullptr);
}

NNS_CAPI int ml_pipeline_element_release_handle(ml_pipeline_element_h elem_h) {
  return release(elem_h, HandleKind::kElement, "ml_pipeline_element_release_handle", "elem_h");
}

#define NNS_SETTER(suffix, ctype, gtype, field)                                                    \
  NNS_CAPI int ml_pipeline_element_set_property_##suffix(                                          \
      ml_pipeline_element_h elem_h, const char *property_name, const ctype value) {                \
    Arg a;                                                                                         \
    a.field = value;                                                                               \
    return set_prop(elem_h, property_name, gtype, a, "ml_pipeline_element_set_property_" #suffix); \
  }
#define NNS_GETTER(suffix, ctype, gtype)                                       \
  NNS_CAPI int ml_pipeline_element_get_property_##suffix(                      \
      ml_pipeline_element_h elem_h, const char *property_name, ctype *value) { \
    return get_prop(elem_h, property_name, gtype, value,                       \
                    "ml_pipeline_element_get_property_" #suffix);              \
  }

NNS_SETTER(bool, int32_t, G_TYPE_BOOLEAN, i)
NNS_CAPI int ml_pipeline_element_set_property_string(ml_pipeline_element_h elem_h,
                                                     const char *property_name, const char *value) {
  Arg a;
  a.s = value;
  return set_prop(elem_h, property_name, G_TYPE_STRING, a,
                  "ml_pipeline_element_set_property_string");
}

NNS_SETTER(int32, int32_t, G_TYPE_INT, i)
NNS_SETTER(int64, int64_t, G_TYPE_INT64, i)
NNS_SETTER(uint32, uint32_t, G_TYPE_UINT, u)
NNS_SETTER(uint64, uint64_t, G_TYPE_UINT64, u)
NNS_SETTER(double, double, G_TYPE_DOUBLE, d)
NNS_SETTER(enum, uint32_t, G_TYPE_ENUM, u)
NNS_GETTER(bool, int32_t, G_TYPE_BOOLEAN)
NNS_GETTER(string, char *, G_TYPE_STRING)
NNS_GETTER(int32, int32_t, G_TYPE_INT)
NNS_GETTER(int64, int64_t, G_TYPE_INT64)
NNS_GETTER(uint32, uint32_t, G_TYPE_UINT)
NNS_GETTER(uint64, uint64_t, G_TYPE_UINT64)
NNS_GETTER(double, double, G_TYPE_DOUBLE)
NNS_GETTER(enum, uint32_t, G_TYPE_ENUM)
