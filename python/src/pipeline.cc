// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer.Pipeline: ml_pipeline_* (libcapi-nnstreamer) for Python. Sink callbacks run on
// the pipeline's streaming threads with the GIL taken; they get numpy arrays that own a copy
// of the buffer (ml_tensors_data_clone: the C data is valid only during the C callback). Every
// C call that may wait for a callback (stop, destroy, unregister, push) runs without the GIL.
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>

#include "nns_py.h"
#include "nnstreamer.h"

namespace nns::py {

namespace {

PyObject *g_state_enum = nullptr;  // nnstreamer.State (IntEnum)

pyb::object state_of(ml_pipeline_state_e s) {
  return pyb::reinterpret_borrow<pyb::object>(g_state_enum)(static_cast<int>(s));
}

// What a C callback needs: the Python callable. Owned by the Pipeline; C keeps a raw pointer
// until the registration is undone (after which no call happens).
struct Callback {
  pyb::object fn;
};

void call_python(const char *where, const std::function<void()> &body) {
  pyb::gil_scoped_acquire gil;
  try {
    body();
  } catch (pyb::error_already_set &e) {
    e.discard_as_unraisable(where);  // printed like an exception in a __del__
  } catch (const std::exception &e) {
    PyErr_SetString(PyExc_RuntimeError, e.what());
    PyErr_WriteUnraisable(pyb::str(where).ptr());
  }
}

void on_sink_data(const ml_tensors_data_h data, const ml_tensors_info_h info, void *user) {
  auto *cb = static_cast<Callback *>(user);
  call_python("nnstreamer.Pipeline sink callback", [&] {
    auto specs = specs_of(info);
    ml_tensors_data_h copy = nullptr;
    check(ml_tensors_data_clone(data, &copy), "ml_tensors_data_clone");
    pyb::list arrays = arrays_over(copy, specs);  // owns `copy` from here
    cb->fn(arrays, specs_to_py(specs));
  });
}

void on_state(ml_pipeline_state_e state, void *user) {
  auto *cb = static_cast<Callback *>(user);
  if (!Py_IsInitialized()) return;
  call_python("nnstreamer.Pipeline state callback", [&] { cb->fn(state_of(state)); });
}

class Pipeline;
std::mutex g_live_mu;
std::set<Pipeline *> g_live;  // closed by nnstreamer's atexit hook before Python goes away

// element(name).props: typed get/set through the C API's per-type calls (it refuses a call of
// the wrong type, so the first type that works is the property's).
class Element {
 public:
  Element(std::shared_ptr<void> pipe_alive, ml_pipeline_element_h h, std::string name)
      : alive_(std::move(pipe_alive)), h_(h), name_(std::move(name)) {}
  ~Element() {
    if (h_ && *static_cast<bool *>(alive_.get())) ml_pipeline_element_release_handle(h_);
  }

  pyb::object get(const std::string &prop) {
    ml_pipeline_element_h h = handle();
    const char *p = prop.c_str();
    {
      int32_t b = 0;
      if (ml_pipeline_element_get_property_bool(h, p, &b) == ML_ERROR_NONE) return pyb::bool_(b);
    }
    {
      char *s = nullptr;
      if (ml_pipeline_element_get_property_string(h, p, &s) == ML_ERROR_NONE) {
        pyb::object o = s ? pyb::object(pyb::str(s)) : pyb::object(pyb::none());
        std::free(s);  // g_malloc memory: GLib's allocator is malloc
        return o;
      }
    }
    {
      int32_t v = 0;
      if (ml_pipeline_element_get_property_int32(h, p, &v) == ML_ERROR_NONE) return pyb::int_(v);
    }
    {
      uint32_t v = 0;
      if (ml_pipeline_element_get_property_uint32(h, p, &v) == ML_ERROR_NONE) return pyb::int_(v);
    }
    {
      int64_t v = 0;
      if (ml_pipeline_element_get_property_int64(h, p, &v) == ML_ERROR_NONE) return pyb::int_(v);
    }
    {
      uint64_t v = 0;
      if (ml_pipeline_element_get_property_uint64(h, p, &v) == ML_ERROR_NONE) return pyb::int_(v);
    }
    {
      double v = 0;
      if (ml_pipeline_element_get_property_double(h, p, &v) == ML_ERROR_NONE) return pyb::float_(v);
    }
    uint32_t e = 0;
    int rc = ml_pipeline_element_get_property_enum(h, p, &e);
    if (rc == ML_ERROR_NONE) return pyb::int_(e);
    check(rc, "ml_pipeline_element_get_property");
    return pyb::none();
  }

  void set(const std::string &prop, const pyb::handle &value) {
    ml_pipeline_element_h h = handle();
    const char *p = prop.c_str();
    int rc;
    if (pyb::isinstance<pyb::bool_>(value)) {
      rc = ml_pipeline_element_set_property_bool(h, p, value.cast<bool>() ? 1 : 0);
    } else if (pyb::isinstance<pyb::int_>(value)) {
      long long v = value.cast<long long>();
      rc = ML_ERROR_INVALID_PARAMETER;
      if (v >= INT32_MIN && v <= INT32_MAX)
        rc = ml_pipeline_element_set_property_int32(h, p, static_cast<int32_t>(v));
      if (rc != ML_ERROR_NONE && v >= 0 && v <= UINT32_MAX)
        rc = ml_pipeline_element_set_property_uint32(h, p, static_cast<uint32_t>(v));
      if (rc != ML_ERROR_NONE) rc = ml_pipeline_element_set_property_int64(h, p, v);
      if (rc != ML_ERROR_NONE && v >= 0)
        rc = ml_pipeline_element_set_property_uint64(h, p, static_cast<uint64_t>(v));
      if (rc != ML_ERROR_NONE && v >= 0 && v <= UINT32_MAX)
        rc = ml_pipeline_element_set_property_enum(h, p, static_cast<uint32_t>(v));
      if (rc != ML_ERROR_NONE) rc = ml_pipeline_element_set_property_double(h, p, double(v));
      if (rc != ML_ERROR_NONE)  // report the first kind's message: the most common type
        if (v >= INT32_MIN && v <= INT32_MAX)
          rc = ml_pipeline_element_set_property_int32(h, p, static_cast<int32_t>(v));
    } else if (pyb::isinstance<pyb::float_>(value)) {
      rc = ml_pipeline_element_set_property_double(h, p, value.cast<double>());
    } else {
      std::string s = pyb::isinstance<pyb::str>(value) ? value.cast<std::string>() : text(value);
      rc = ml_pipeline_element_set_property_string(h, p, s.c_str());
    }
    check(rc, "ml_pipeline_element_set_property");
  }

  const std::string &name() const { return name_; }

 private:
  ml_pipeline_element_h handle() const {
    if (!*static_cast<bool *>(alive_.get()))
      throw MlError{ML_ERROR_INVALID_PARAMETER,
                    "element '" + name_ + "': its pipeline has been closed"};
    return h_;
  }
  std::shared_ptr<void> alive_;
  ml_pipeline_element_h h_;
  std::string name_;
};

class Props {
 public:
  explicit Props(std::shared_ptr<Element> e) : e_(std::move(e)) {}
  pyb::object get(const std::string &k) { return e_->get(k); }
  void set(const std::string &k, const pyb::handle &v) { e_->set(k, v); }

 private:
  std::shared_ptr<Element> e_;
};

class Switch {
 public:
  Switch(std::shared_ptr<void> alive, ml_pipeline_switch_h h, ml_pipeline_switch_e type,
         std::string name)
      : alive_(std::move(alive)), h_(h), type_(type), name_(std::move(name)) {}
  ~Switch() {
    if (h_ && *static_cast<bool *>(alive_.get())) ml_pipeline_switch_release_handle(h_);
  }
  void select(const std::string &pad) {
    int rc;
    {
      pyb::gil_scoped_release nogil;
      rc = ml_pipeline_switch_select(handle(), pad.c_str());
    }
    check(rc, "ml_pipeline_switch_select");
  }
  std::vector<std::string> pads() {
    char **list = nullptr;
    check(ml_pipeline_switch_get_pad_list(handle(), &list), "ml_pipeline_switch_get_pad_list");
    std::vector<std::string> out;
    for (char **p = list; p && *p; ++p) {
      out.emplace_back(*p);
      std::free(*p);
    }
    std::free(list);
    return out;
  }
  std::string type() const {
    return type_ == ML_PIPELINE_SWITCH_INPUT_SELECTOR ? "input-selector" : "output-selector";
  }

 private:
  ml_pipeline_switch_h handle() const {
    if (!*static_cast<bool *>(alive_.get()))
      throw MlError{ML_ERROR_INVALID_PARAMETER,
                    "switch '" + name_ + "': its pipeline has been closed"};
    return h_;
  }
  std::shared_ptr<void> alive_;
  ml_pipeline_switch_h h_;
  ml_pipeline_switch_e type_;
  std::string name_;
};

class Valve {
 public:
  Valve(std::shared_ptr<void> alive, ml_pipeline_valve_h h, std::string name)
      : alive_(std::move(alive)), h_(h), name_(std::move(name)) {}
  ~Valve() {
    if (h_ && *static_cast<bool *>(alive_.get())) ml_pipeline_valve_release_handle(h_);
  }
  void set_open(bool open) {
    if (!*static_cast<bool *>(alive_.get()))
      throw MlError{ML_ERROR_INVALID_PARAMETER,
                    "valve '" + name_ + "': its pipeline has been closed"};
    int rc;
    {
      pyb::gil_scoped_release nogil;
      rc = ml_pipeline_valve_set_open(h_, open);
    }
    check(rc, "ml_pipeline_valve_set_open");
  }

 private:
  std::shared_ptr<void> alive_;
  ml_pipeline_valve_h h_;
  std::string name_;
};

class Pipeline {
 public:
  Pipeline(const std::string &description, const pyb::object &on_state) {
    if (!on_state.is_none()) state_cb_ = std::make_unique<Callback>(Callback{on_state});
    int rc;
    {
      pyb::gil_scoped_release nogil;
      rc = ml_pipeline_construct(description.c_str(), state_cb_ ? on_state_trampoline : nullptr,
                                 state_cb_.get(), &h_);
    }
    check(rc, "ml_pipeline_construct");
    std::lock_guard g(g_live_mu);
    g_live.insert(this);
  }
  ~Pipeline() { close(); }

  void close() {
    {
      std::lock_guard g(g_live_mu);
      g_live.erase(this);
    }
    if (!h_) return;
    *static_cast<bool *>(alive_.get()) = false;  // handles of this pipeline die with it
    ml_pipeline_h h = h_;
    h_ = nullptr;
    if (Py_IsInitialized() && PyGILState_Check()) {
      pyb::gil_scoped_release nogil;  // a running callback needs the GIL to finish
      ml_pipeline_destroy(h);
    } else {
      ml_pipeline_destroy(h);
    }
    sinks_.clear();
  }

  void start() { run(ml_pipeline_start, "ml_pipeline_start"); }
  void stop() { run(ml_pipeline_stop, "ml_pipeline_stop"); }
  void flush(bool start) {
    ml_pipeline_h h = handle();
    int rc;
    {
      pyb::gil_scoped_release nogil;
      rc = ml_pipeline_flush(h, start);
    }
    check(rc, "ml_pipeline_flush");
  }

  pyb::object state() {
    ml_pipeline_state_e s = ML_PIPELINE_STATE_UNKNOWN;
    check(ml_pipeline_get_state(handle(), &s), "ml_pipeline_get_state");
    return state_of(s);
  }

  // Registers callback(arrays, info) for tensor_sink/appsink `name`; None unregisters.
  void on_sink(const std::string &name, const pyb::object &fn) {
    ml_pipeline_h h = handle();
    auto it = sinks_.find(name);
    if (it != sinks_.end()) {
      ml_pipeline_sink_h s = it->second.first;
      int rc;
      {
        pyb::gil_scoped_release nogil;  // waits for a running callback
        rc = ml_pipeline_sink_unregister(s);
      }
      sinks_.erase(it);
      check(rc, "ml_pipeline_sink_unregister");
    }
    if (fn.is_none()) return;
    auto cb = std::make_unique<Callback>(Callback{fn});
    ml_pipeline_sink_h s = nullptr;
    check(ml_pipeline_sink_register(h, name.c_str(), on_sink_data, cb.get(), &s),
          "ml_pipeline_sink_register");
    sinks_.emplace(name, std::make_pair(s, std::move(cb)));
  }

  // Pushes one frame (an array, or a list of arrays: one per tensor) into appsrc `name`. The
  // arrays are copied into a new buffer the pipeline owns.
  void push(const std::string &name, const pyb::object &arrays) {
    ml_pipeline_h h = handle();
    std::vector<pyb::array> list;
    if (pyb::isinstance<pyb::array>(arrays)) {
      list.push_back(pyb::reinterpret_borrow<pyb::array>(arrays));
    } else {
      for (auto a : pyb::reinterpret_borrow<pyb::iterable>(arrays))
        list.push_back(pyb::array::ensure(a, pyb::array::c_style));
    }
    std::vector<TensorSpec> specs;
    for (auto &a : list) {
      if (!a) throw pyb::type_error("push: every tensor must be a numpy array (or array-like)");
      a = pyb::array::ensure(a, pyb::array::c_style);
      TensorSpec s;
      s.type = type_of(a.dtype());
      for (pyb::ssize_t k = 0; k < a.ndim(); ++k) s.shape.push_back(a.shape(k));
      if (s.shape.empty()) s.shape.push_back(1);
      specs.push_back(std::move(s));
    }
    ml_tensors_info_h info = info_from_specs(specs);
    ml_tensors_data_h data = nullptr;
    int rc = ml_tensors_data_create(info, &data);
    ml_tensors_info_destroy(info);
    check(rc, "ml_tensors_data_create");
    for (std::size_t i = 0; i < list.size(); ++i) {
      rc = ml_tensors_data_set_tensor_data(data, static_cast<unsigned>(i), list[i].data(),
                                           static_cast<std::size_t>(list[i].nbytes()));
      if (rc != ML_ERROR_NONE) {
        ml_tensors_data_destroy(data);
        check(rc, "ml_tensors_data_set_tensor_data");
      }
    }
    ml_pipeline_src_h src = src_handle(h, name);
    {
      pyb::gil_scoped_release nogil;
      rc = ml_pipeline_src_input_data(src, data, ML_PIPELINE_BUF_POLICY_AUTO_FREE);
    }
    if (rc != ML_ERROR_NONE) {
      // The data is the library's only when the call succeeded.
      ml_tensors_data_destroy(data);
      check(rc, "ml_pipeline_src_input_data");
    }
  }

  void end_of_stream(const std::string &name) {
    ml_pipeline_src_h src = src_handle(handle(), name);
    int rc;
    {
      pyb::gil_scoped_release nogil;
      rc = ml_pipeline_src_input_data(src, nullptr, ML_PIPELINE_BUF_SRC_EVENT_EOS);
    }
    check(rc, "ml_pipeline_src_input_data");
  }

  std::shared_ptr<Element> element(const std::string &name) {
    ml_pipeline_element_h e = nullptr;
    check(ml_pipeline_element_get_handle(handle(), name.c_str(), &e),
          "ml_pipeline_element_get_handle");
    return std::make_shared<Element>(alive_, e, name);
  }

  std::shared_ptr<Switch> switch_(const std::string &name) {
    ml_pipeline_switch_h s = nullptr;
    ml_pipeline_switch_e type = ML_PIPELINE_SWITCH_OUTPUT_SELECTOR;
    check(ml_pipeline_switch_get_handle(handle(), name.c_str(), &type, &s),
          "ml_pipeline_switch_get_handle");
    return std::make_shared<Switch>(alive_, s, type, name);
  }

  std::shared_ptr<Valve> valve(const std::string &name) {
    ml_pipeline_valve_h v = nullptr;
    check(ml_pipeline_valve_get_handle(handle(), name.c_str(), &v), "ml_pipeline_valve_get_handle");
    return std::make_shared<Valve>(alive_, v, name);
  }

 private:
  static void on_state_trampoline(ml_pipeline_state_e s, void *user) { on_state(s, user); }

  ml_pipeline_h handle() const {
    if (!h_) throw MlError{ML_ERROR_INVALID_PARAMETER, "the Pipeline is closed"};
    return h_;
  }

  void run(int (*fn)(ml_pipeline_h), const char *what) {
    ml_pipeline_h h = handle();
    int rc;
    {
      pyb::gil_scoped_release nogil;
      rc = fn(h);
    }
    check(rc, what);
  }

  ml_pipeline_src_h src_handle(ml_pipeline_h h, const std::string &name) {
    auto it = srcs_.find(name);
    if (it != srcs_.end()) return it->second;
    ml_pipeline_src_h s = nullptr;
    check(ml_pipeline_src_get_handle(h, name.c_str(), &s), "ml_pipeline_src_get_handle");
    srcs_[name] = s;  // released with the pipeline (destroy frees its handles)
    return s;
  }

  ml_pipeline_h h_ = nullptr;
  std::unique_ptr<Callback> state_cb_;
  std::map<std::string, std::pair<ml_pipeline_sink_h, std::unique_ptr<Callback>>> sinks_;
  std::map<std::string, ml_pipeline_src_h> srcs_;
  // Shared with element/switch/valve objects: false once the pipeline is destroyed (its
  // handles are gone with it).
  std::shared_ptr<void> alive_{new bool(true), [](void *p) { delete static_cast<bool *>(p); }};
};

void close_all() {
  std::set<Pipeline *> live;
  {
    std::lock_guard g(g_live_mu);
    live = g_live;
  }
  for (Pipeline *p : live) p->close();
}

}  // namespace

void bind_pipeline(pyb::module_ &m) {
  pyb::object int_enum = pyb::module_::import("enum").attr("IntEnum");
  pyb::list members;
  for (auto [n, v] :
       std::initializer_list<std::pair<const char *, int>>{{"UNKNOWN", ML_PIPELINE_STATE_UNKNOWN},
                                                           {"NULL", ML_PIPELINE_STATE_NULL},
                                                           {"READY", ML_PIPELINE_STATE_READY},
                                                           {"PAUSED", ML_PIPELINE_STATE_PAUSED},
                                                           {"PLAYING", ML_PIPELINE_STATE_PLAYING}})
    members.append(pyb::make_tuple(n, v));
  pyb::dict kw;
  kw["module"] = "nnstreamer";
  pyb::object state = int_enum("State", members, **kw);
  g_state_enum = state.inc_ref().ptr();
  m.add_object("State", state);

  pyb::class_<Props>(m, "ElementProperties",
                     "element.props[name]: get/set a property (bool, int, float or str)")
      .def("__getitem__", &Props::get)
      .def("__setitem__", &Props::set);
  pyb::class_<Element, std::shared_ptr<Element>>(m, "Element")
      .def_property_readonly("name", &Element::name)
      .def_property_readonly("props", [](std::shared_ptr<Element> e) { return Props(e); });
  pyb::class_<Switch, std::shared_ptr<Switch>>(m, "Switch")
      .def("select", &Switch::select, pyb::arg("pad"))
      .def_property_readonly("pads", &Switch::pads)
      .def_property_readonly("type", &Switch::type);
  pyb::class_<Valve, std::shared_ptr<Valve>>(m, "Valve")
      .def("set_open", &Valve::set_open, pyb::arg("open"))
      .def_property("open", nullptr, &Valve::set_open);
  pyb::class_<Pipeline>(m, "Pipeline",
                        R"doc(A pipeline of the ML Pipeline API (ml_pipeline_construct).

Pipeline(description, on_state=None): a gst-launch description; it is constructed PAUSED.
on_state(State) is called on every state change (from GStreamer's threads).)doc")
      .def(pyb::init<const std::string &, const pyb::object &>(), pyb::arg("description"),
           pyb::arg("on_state") = pyb::none())
      .def("start", &Pipeline::start)
      .def("stop", &Pipeline::stop)
      .def("flush", &Pipeline::flush, pyb::arg("start") = true)
      .def_property_readonly("state", &Pipeline::state)
      .def("on_sink", &Pipeline::on_sink, pyb::arg("name"), pyb::arg("callback"),
           "callback(arrays, info) per buffer of tensor_sink/appsink `name`, on a streaming "
           "thread; arrays own a copy of the buffer. None unregisters (waits for a running "
           "callback).")
      .def("push", &Pipeline::push, pyb::arg("src"), pyb::arg("arrays"),
           "One frame into appsrc `src`: an array or a list of arrays (one per tensor), copied.")
      .def("end_of_stream", &Pipeline::end_of_stream, pyb::arg("src"))
      .def("element", &Pipeline::element, pyb::arg("name"))
      .def("switch", &Pipeline::switch_, pyb::arg("name"))
      .def("valve", &Pipeline::valve, pyb::arg("name"))
      .def("close", &Pipeline::close, "ml_pipeline_destroy (waits for running callbacks)")
      .def("__enter__", [](pyb::object self) { return self; })
      .def("__exit__", [](Pipeline &p, const pyb::args &) {
        p.close();
        return false;
      });
  m.def("_close_all_pipelines", &close_all);
}

}  // namespace nns::py
