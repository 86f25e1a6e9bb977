// SPDX-License-Identifier: LGPL-2.1-only
// tensor_converter sub-plugin "python3": tensor_converter mode=custom-script:<file.py> runs a
// Python script defining NNStreamer's CustomConverter class.
//
//   gst-launch-1.0 filesrc location=data.json ! application/octet-stream !
//     tensor_converter mode=custom-script:json_to_tensors.py ! tensor_sink
//
// The script (compatible with NNStreamer's):
//   import nnstreamer_python as nns
//   class CustomConverter:
//     def convert(self, input_array):    # list of 1-D uint8 numpy arrays, one per GstMemory
//       return tensors_info, raw_data, rate_n, rate_d
// tensors_info: list of nns.TensorShape (dims innermost first, numpy dtype); raw_data: list of
// numpy arrays, one per tensor, each holding exactly the tensor's bytes (its dtype may differ:
// only the byte count must match); rate_n/rate_d: the output framerate (a negative or zero
// denominator keeps the input's).
//
// No copies on the way in: each input array is a read-only view of the mapped GstMemory, and the
// mapping lives as long as the array (a script may keep it). On the way out:
//   - an array that is a view of an input memory becomes a share of that GstMemory;
//   - any other C-contiguous array is wrapped as a read-only GstMemory holding a reference to
//     it (the script must not modify an array after returning it);
//   - a non-contiguous array (e.g. arr[::-1]) is copied once into a C-ordered array.
// Failures put the Python exception (type, message, traceback) in the error slot that
// tensor_converter appends to its bus error.
#include <gst/gst.h>

#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "decoder/common/decoder_common.h"
#include "nns_numpy.h"
#include "nns_python.h"
#include "nns_python_tensors.h"
#include "nnstreamer_plugin_api_converter.h"

namespace nns::py {
namespace {

constexpr const char *kName = "python3";

// One mapped input memory, owned by the capsule that is the base object of its numpy view.
struct InputMap {
  GstMemory *mem;
  GstMapInfo map;
};

void release_input_map(PyObject *capsule) {
  auto *m = static_cast<InputMap *>(PyCapsule_GetPointer(capsule, "nns.converter.input"));
  if (!m) {
    PyErr_Clear();
    return;
  }
  gst_memory_unmap(m->mem, &m->map);
  gst_memory_unref(m->mem);
  delete m;
}

// Destroy notify of a GstMemory wrapping a numpy array: drops the array reference.
void release_array(gpointer obj) {
  if (!runtime_alive()) return;  // process exit: the interpreter is gone or going
  pin_thread_state();
  Gil gil;
  Py_DECREF(static_cast<PyObject *>(obj));
}

struct Converter {
  dec::DecoderErrorSlot err;  // first: tensor_converter reads it (see decoder_common.h)
  std::string path;
  Script script;
  Ref obj, convert;                  // CustomConverter() and its bound convert method
  std::vector<InputMap *> inputs;    // this buffer's input maps, owned by the input list (scratch)
  std::vector<GstMemory *> outputs;  // this buffer's output memories (scratch, reused)

  std::string where() const { return "Python script '" + path + "': "; }

  ~Converter() {
    if (!runtime_alive()) {  // process exit: leave the Python objects
      script.module.release();
      obj.release();
      convert.release();
      return;
    }
    Gil gil;
    convert = Ref();
    obj = Ref();
    unload_script(script);
  }

  void open() {
    ensure_runtime();
    Gil gil;
    script = load_script(path);
    Ref cls(PyObject_GetAttrString(script.module.get(), "CustomConverter"));
    if (!cls) {
      PyErr_Clear();
      throw PyError(where() + "defines no class CustomConverter");
    }
    obj = Ref(PyObject_CallNoArgs(cls.get()));
    if (!obj) throw_pending(where() + "CustomConverter() raised");
    convert = Ref(PyObject_GetAttrString(obj.get(), "convert"));
    if (!convert || !PyCallable_Check(convert.get())) {
      PyErr_Clear();
      convert = Ref();
      throw PyError(where() + "CustomConverter has no convert(self, input_array) method");
    }
  }

  // The list of read-only uint8 views of every memory of `in` (the views keep the maps).
  Ref input_list(GstBuffer *in) {
    guint n = gst_buffer_n_memory(in);
    Ref list(PyList_New(n));
    if (!list) throw_pending(where() + "cannot build the input list");
    inputs.clear();
    for (guint i = 0; i < n; i++) {
      auto *m = new InputMap{gst_buffer_get_memory(in, i), {}};
      if (!gst_memory_map(m->mem, &m->map, GST_MAP_READ)) {
        gst_memory_unref(m->mem);
        delete m;
        throw PyError(where() + "cannot map input memory " + std::to_string(i));
      }
      PyObject *cap = PyCapsule_New(m, "nns.converter.input", release_input_map);
      if (!cap) {
        gst_memory_unmap(m->mem, &m->map);
        gst_memory_unref(m->mem);
        delete m;
        throw_pending(where() + "cannot wrap input memory " + std::to_string(i));
      }
      npy_intp dims[1] = {static_cast<npy_intp>(m->map.size)};
      PyObject *arr = PyArray_New(&PyArray_Type, 1, dims, NPY_UINT8, nullptr, m->map.data, 0,
                                  NPY_ARRAY_CARRAY_RO, nullptr);
      if (!arr) {
        Py_DECREF(cap);
        throw_pending(where() + "cannot wrap input memory " + std::to_string(i));
      }
      if (PyArray_SetBaseObject(reinterpret_cast<PyArrayObject *>(arr), cap) < 0) {  // steals
        Py_DECREF(arr);
        throw_pending(where() + "cannot wrap input memory " + std::to_string(i));
      }
      inputs.push_back(m);  // borrowed: the array (in the list) owns it
      PyList_SET_ITEM(list.get(), i, arr);
    }
    return list;
  }

  // A GstMemory for output `i`, sharing an input memory or lending the array (copied first when
  // it is not C-contiguous).
  GstMemory *output_memory(PyObject *o, size_t i) {
    auto *arr = reinterpret_cast<PyArrayObject *>(o);
    const size_t bytes = static_cast<size_t>(PyArray_NBYTES(arr));
    Ref hold;
    if (!PyArray_IS_C_CONTIGUOUS(arr)) {
      hold = Ref(PyArray_NewCopy(arr, NPY_CORDER));
      if (!hold) throw_pending(where() + "convert() raw_data[" + std::to_string(i) + "]: copy");
      arr = reinterpret_cast<PyArrayObject *>(hold.get());
    } else {
      hold = Ref::borrow(o);
    }
    const auto *data = static_cast<const guint8 *>(PyArray_DATA(arr));
    for (InputMap *m : inputs) {
      if (data >= m->map.data && data + bytes <= m->map.data + m->map.size &&
          !GST_MEMORY_FLAG_IS_SET(m->mem, GST_MEMORY_FLAG_NO_SHARE))
        return gst_memory_share(m->mem, static_cast<gssize>(data - m->map.data),
                                static_cast<gssize>(bytes));
    }
    PyObject *owner = hold.release();  // the memory's reference, dropped by release_array
    return gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, const_cast<guint8 *>(data), bytes, 0,
                                  bytes, owner, release_array);
  }

  GstBuffer *run(GstBuffer *in, GstTensorsConfig *config) {
    if (!runtime_alive()) throw PyError(where() + "the Python interpreter is shutting down");
    pin_thread_state();
    Gil gil;
    // The list keeps the input maps (`inputs`) alive until the outputs are made from them.
    Ref list = input_list(in);
    Ref res(PyObject_CallOneArg(convert.get(), list.get()));
    if (!res) throw_pending(where() + "convert() raised");
    if (!PyTuple_Check(res.get()) || PyTuple_GET_SIZE(res.get()) != 4)
      throw PyError(where() + "convert() returned " + type_name(res.get()) +
                    (PyTuple_Check(res.get())
                         ? " of " + std::to_string(PyTuple_GET_SIZE(res.get())) + " items"
                         : std::string()) +
                    "; expected a tuple (tensors_info, raw_data, rate_n, rate_d)");
    PyObject *info = PyTuple_GET_ITEM(res.get(), 0);
    PyObject *raw = PyTuple_GET_ITEM(res.get(), 1);
    auto desc = std::make_unique<nns_tensors_desc>();  // 83 KB: not on the streaming stack
    desc_from_shapes(info, where() + "convert() tensors_info", *desc);
    if (desc->num_tensors > NNS_TENSOR_MEMORY_MAX)
      throw PyError(where() + "convert() tensors_info lists " + std::to_string(desc->num_tensors) +
                    " tensors; this converter supports up to " +
                    std::to_string(NNS_TENSOR_MEMORY_MAX));
    int rate[2];
    for (int k = 0; k < 2; k++) {
      PyObject *r = PyTuple_GET_ITEM(res.get(), 2 + k);
      Ref idx(PyNumber_Index(r));  // int, numpy integers, anything with __index__
      long v = idx ? PyLong_AsLong(idx.get()) : -1;
      if (!idx || (v == -1 && PyErr_Occurred()) || v < INT32_MIN || v > INT32_MAX) {
        PyErr_Clear();
        throw PyError(where() + "convert() " + (k ? "rate_d" : "rate_n") + " is " + type_name(r) +
                      " " + str(r) + "; expected an int");
      }
      rate[k] = static_cast<int>(v);
    }
    if (!PyList_Check(raw) && !PyTuple_Check(raw))
      throw PyError(where() + "convert() raw_data is a " + type_name(raw) +
                    "; expected a list of numpy arrays");
    Py_ssize_t n = PySequence_Fast_GET_SIZE(raw);
    if (n != static_cast<Py_ssize_t>(desc->num_tensors))
      throw PyError(where() + "convert() raw_data has " + std::to_string(n) +
                    " arrays but tensors_info describes " + std::to_string(desc->num_tensors) +
                    " tensors (" + desc_text(*desc) + ")");
    // Check everything before making any memory.
    for (Py_ssize_t i = 0; i < n; i++) {
      PyObject *o = PySequence_Fast_GET_ITEM(raw, i);
      const nns_tensor_desc &t = desc->tensors[i];
      std::string what = where() + "convert() raw_data[" + std::to_string(i) + "]";
      if (!PyArray_Check(o)) throw PyError(what + " is a " + type_name(o) + ", not a numpy array");
      size_t bytes = static_cast<size_t>(PyArray_NBYTES(reinterpret_cast<PyArrayObject *>(o)));
      if (bytes != tensor_bytes(t))
        throw PyError(what + " has " + std::to_string(bytes) + " bytes; tensors_info[" +
                      std::to_string(i) + "] (" + dims_text(t) + " " + type_name_of(t.type) +
                      ") needs " + std::to_string(tensor_bytes(t)));
    }
    outputs.clear();
    try {
      for (Py_ssize_t i = 0; i < n; i++)
        outputs.push_back(output_memory(PySequence_Fast_GET_ITEM(raw, i), i));
    } catch (...) {
      for (GstMemory *m : outputs) gst_memory_unref(m);
      outputs.clear();
      throw;
    }
    GstBuffer *out = gst_buffer_new();
    for (GstMemory *m : outputs) gst_buffer_append_memory(out, m);
    outputs.clear();
    gst_buffer_copy_into(out, in, GST_BUFFER_COPY_METADATA, 0, -1);

    config->info.num_tensors = desc->num_tensors;
    config->info.format = _NNS_TENSOR_FORMAT_STATIC;
    for (uint32_t i = 0; i < desc->num_tensors; i++) {
      GstTensorInfo &t = config->info.info[i];
      t.type = static_cast<tensor_type>(desc->tensors[i].type);
      std::memcpy(t.dimension, desc->tensors[i].dims, sizeof t.dimension);
    }
    config->rate_n = rate[0];
    config->rate_d = rate[1];
    return out;
  }
};

static_assert(sizeof(tensor_dim) == sizeof(nns_tensor_desc::dims));

// As NNStreamer's: opening the script already open in *priv_data keeps it and returns 1; another
// script replaces it (the old one is closed) and returns 0.
int py_open(const gchar *script_path, void **priv_data) {
  if (!priv_data) return -EINVAL;
  if (auto *old = static_cast<Converter *>(*priv_data)) {
    if (script_path && old->convert && old->path == script_path) return 1;
    delete old;
    *priv_data = nullptr;
  }
  auto *c = new Converter();
  *priv_data = c;  // also on failure: the host reads the error slot, then calls close
  if (!script_path || !*script_path) {
    c->err.set("python3: no script path given");
    return -EINVAL;
  }
  c->path = script_path;
  try {
    c->open();
  } catch (const std::exception &e) {
    c->err.set("%s", e.what());
    return -EINVAL;
  }
  return 0;
}

void py_close(void **priv_data) {
  if (!priv_data) return;
  delete static_cast<Converter *>(*priv_data);
  *priv_data = nullptr;
}

GstBuffer *py_convert(GstBuffer *in_buf, GstTensorsConfig *config, void *priv_data) {
  auto *c = static_cast<Converter *>(priv_data);
  if (!c || !in_buf || !config) return nullptr;
  if (!c->convert) {
    c->err.set("python3: no script is open (tensor_converter mode=custom-script:<file.py>)");
    return nullptr;
  }
  c->err.message[0] = '\0';
  try {
    return c->run(in_buf, config);
  } catch (const std::exception &e) {
    c->err.set("%s", e.what());
    return nullptr;
  }
}

// The tensors are known only once the script has converted a buffer: no tensors here, which
// makes tensor_converter set its src caps from the first converted buffer.
gboolean py_get_out_config(const GstCaps *in_caps, GstTensorsConfig *config) {
  if (!in_caps || !config) return FALSE;  // as NNStreamer's (its invalidParam2_n)
  config->info.num_tensors = 0;
  config->info.format = _NNS_TENSOR_FORMAT_STATIC;
  config->rate_n = 0;
  config->rate_d = 1;
  if (gst_caps_get_size(in_caps) > 0) {
    const GstStructure *s = gst_caps_get_structure(in_caps, 0);
    if (!gst_structure_get_fraction(s, "framerate", &config->rate_n, &config->rate_d))
      config->rate_n = 0, config->rate_d = 1;
  }
  return TRUE;
}

GstCaps *py_query_caps(const GstTensorsConfig *) {
  return gst_caps_from_string("application/octet-stream");
}

const NNStreamerExternalConverter kConverter = {kName,         py_convert, py_get_out_config,
                                                py_query_caps, py_open,    py_close};

}  // namespace
}  // namespace nns::py

extern "C" __attribute__((visibility("default"))) const NNStreamerExternalConverter *
nns_converter_subplugin_entry(void) {
  return &nns::py::kConverter;
}
