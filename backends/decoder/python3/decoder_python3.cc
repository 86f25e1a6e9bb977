// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder sub-plugin "python3": mode=python3 option1=<file.py> runs a Python script
// defining NNStreamer's CustomDecoder class.
//
//   gst-launch-1.0 videotestsrc num-buffers=3 ! video/x-raw,format=RGB,width=64,height=48 !
//     tensor_converter ! tensor_decoder mode=python3 option1=to_gray.py ! videoconvert !
//     autovideosink
//
// The script (compatible with NNStreamer's):
//   class CustomDecoder:
//     def getOutCaps(self):        # optional: caps string (bytes or str) of the output;
//                                  # application/octet-stream without it
//     def decode(self, raw_data, in_info, rate_n, rate_d):
//       # raw_data: list of read-only 1-D numpy arrays (the tensors' element types), views of
//       #           the input memory valid during the call only;
//       # in_info: list of nnstreamer_python.TensorShape; rate_n/rate_d: the input framerate
//       return bytes  # the output frame
// The framerate of the output caps is the input's. A bytes result (or a C-contiguous numpy
// array) becomes the output memory without a copy (the memory holds a reference to it); other
// buffer objects (bytearray, memoryview) are copied once. option2..option9 are ignored.
// Failures put the Python exception (type, message, traceback) in the error slot that
// tensor_decoder appends to its bus error.
#include <gst/gst.h>

#include <cstring>
#include <memory>
#include <string>

#include "../common/decoder_common.h"
#include "nns_numpy.h"
#include "nns_python.h"
#include "nns_python_tensors.h"
#include "nnstreamer_plugin_api_decoder.h"

GST_DEBUG_CATEGORY_STATIC(nns_decoder_python3_debug);
#define GST_CAT_DEFAULT nns_decoder_python3_debug

namespace nns::py {
namespace {

// Destroy notify of a GstMemory wrapping a Python object's bytes: drops the reference.
void release_object(gpointer obj) {
  if (!runtime_alive()) return;  // process exit: the interpreter is gone or going
  pin_thread_state();
  Gil gil;
  Py_DECREF(static_cast<PyObject *>(obj));
}

struct Decoder {
  dec::DecoderErrorSlot err;  // first: tensor_decoder reads it (see decoder_common.h)
  std::string path;
  Script script;
  Ref obj, decode, get_out_caps;  // CustomDecoder() and its bound methods
  std::unique_ptr<nns_tensors_desc> desc = std::make_unique<nns_tensors_desc>();
  bool warned_kept = false;

  std::string where() const { return "Python script '" + path + "': "; }
  bool loaded() const { return static_cast<bool>(decode); }

  ~Decoder() { unload(); }

  void unload() {
    if (!obj && !script.module) return;
    if (!runtime_alive()) {  // process exit: leave the Python objects
      script.module.release();
      obj.release();
      decode.release();
      get_out_caps.release();
      return;
    }
    Gil gil;
    decode = Ref();
    get_out_caps = Ref();
    obj = Ref();
    unload_script(script);
  }

  // Loads `file` and creates CustomDecoder(); on failure nothing stays loaded.
  void load(const std::string &file) {
    unload();
    path = file;
    ensure_runtime();
    Gil gil;
    try {
      script = load_script(path);
      Ref cls(PyObject_GetAttrString(script.module.get(), "CustomDecoder"));
      if (!cls) {
        PyErr_Clear();
        throw PyError(where() + "defines no class CustomDecoder");
      }
      obj = Ref(PyObject_CallNoArgs(cls.get()));
      if (!obj) throw_pending(where() + "CustomDecoder() raised");
      decode = Ref(PyObject_GetAttrString(obj.get(), "decode"));
      if (!decode || !PyCallable_Check(decode.get())) {
        PyErr_Clear();
        decode = Ref();
        throw PyError(
            where() +
            "CustomDecoder has no decode(self, raw_data, in_info, rate_n, rate_d) method");
      }
      get_out_caps = Ref(PyObject_GetAttrString(obj.get(), "getOutCaps"));
      if (!get_out_caps || !PyCallable_Check(get_out_caps.get())) {
        PyErr_Clear();
        get_out_caps = Ref();
      }
    } catch (...) {
      decode = Ref();
      get_out_caps = Ref();
      obj = Ref();
      unload_script(script);
      throw;
    }
  }

  // The script's caps with the input framerate; application/octet-stream without getOutCaps.
  GstCaps *out_caps(const GstTensorsConfig *config) {
    GstCaps *caps = nullptr;
    if (!get_out_caps) {
      caps = gst_caps_new_empty_simple("application/octet-stream");
    } else {
      if (!runtime_alive()) throw PyError(where() + "the Python interpreter is shutting down");
      Gil gil;
      Ref r(PyObject_CallNoArgs(get_out_caps.get()));
      if (!r) throw_pending(where() + "getOutCaps() raised");
      std::string text;
      if (PyBytes_Check(r.get())) {
        text.assign(PyBytes_AS_STRING(r.get()), PyBytes_GET_SIZE(r.get()));
      } else if (PyUnicode_Check(r.get())) {
        Py_ssize_t len = 0;
        const char *s = PyUnicode_AsUTF8AndSize(r.get(), &len);
        if (!s) throw_pending(where() + "getOutCaps() returned a str that is not UTF-8");
        text.assign(s, len);
      } else {
        throw PyError(where() + "getOutCaps() returned " + type_name(r.get()) +
                      "; expected a caps string (bytes or str), e.g. b'video/x-raw,format=RGB'");
      }
      caps = gst_caps_from_string(text.c_str());
      if (!caps || gst_caps_is_empty(caps) || gst_caps_is_any(caps)) {
        if (caps) gst_caps_unref(caps);
        throw PyError(where() + "getOutCaps() returned '" + text +
                      "', which is not a usable caps string");
      }
    }
    if (config && config->rate_n >= 0 && config->rate_d > 0) {
      caps = gst_caps_make_writable(caps);
      gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                          nullptr);
    }
    return caps;
  }

  // The output memory for the script's result; nullptr for an empty result.
  GstMemory *result_memory(PyObject *r) {
    if (PyBytes_Check(r)) {
      size_t n = static_cast<size_t>(PyBytes_GET_SIZE(r));
      if (n == 0) return nullptr;
      Py_INCREF(r);  // bytes are immutable: lend them as they are
      return gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, PyBytes_AS_STRING(r), n, 0, n, r,
                                    release_object);
    }
    if (PyArray_Check(r) && PyArray_IS_C_CONTIGUOUS(reinterpret_cast<PyArrayObject *>(r))) {
      auto *a = reinterpret_cast<PyArrayObject *>(r);
      size_t n = static_cast<size_t>(PyArray_NBYTES(a));
      if (n == 0) return nullptr;
      Py_INCREF(r);
      return gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, PyArray_DATA(a), n, 0, n, r,
                                    release_object);
    }
    if (PyObject_CheckBuffer(r) && !PyUnicode_Check(r)) {
      Py_buffer view;
      if (PyObject_GetBuffer(r, &view, PyBUF_C_CONTIGUOUS) < 0 &&
          (PyErr_Clear(), PyObject_GetBuffer(r, &view, PyBUF_FULL_RO) < 0))
        throw_pending(where() + "decode() returned a " + type_name(r) + " that cannot be read");
      size_t n = static_cast<size_t>(view.len);
      GstMemory *mem = n ? gst_allocator_alloc(nullptr, n, nullptr) : nullptr;
      if (mem) {
        GstMapInfo map;
        if (!gst_memory_map(mem, &map, GST_MAP_WRITE)) {
          gst_memory_unref(mem);
          PyBuffer_Release(&view);
          throw PyError(where() + "cannot map a " + std::to_string(n) + "-byte output memory");
        }
        if (PyBuffer_ToContiguous(map.data, &view, view.len, 'C') < 0) {
          gst_memory_unmap(mem, &map);
          gst_memory_unref(mem);
          PyBuffer_Release(&view);
          throw_pending(where() + "decode() result cannot be copied");
        }
        gst_memory_unmap(mem, &map);
      }
      PyBuffer_Release(&view);
      return mem;
    }
    throw PyError(where() + "decode() returned " + type_name(r) +
                  "; expected bytes (the output frame)");
  }

  GstFlowReturn run(const GstTensorsConfig *config, const GstTensorMemory *input,
                    GstBuffer *outbuf) {
    const unsigned n = config->info.num_tensors;
    if (n == 0 || n > NNS_TENSOR_SIZE_LIMIT)
      throw PyError(where() + "the input has " + std::to_string(n) + " tensors");
    nns_tensors_desc &d = *desc;
    d.num_tensors = n;
    d.format = _NNS_TENSOR_FORMAT_STATIC;
    for (unsigned i = 0; i < n; i++) {
      const GstTensorInfo *t =
          i < NNS_TENSOR_MEMORY_MAX
              ? &config->info.info[i]
              : (config->info.extra ? &config->info.extra[i - NNS_TENSOR_MEMORY_MAX] : nullptr);
      if (!t || numpy_type(t->type) < 0)
        throw PyError(where() + "input tensor " + std::to_string(i) + " has no known type");
      d.tensors[i].name[0] = '\0';
      d.tensors[i].type = t->type;
      std::memcpy(d.tensors[i].dims, t->dimension, sizeof d.tensors[i].dims);
    }
    if (!runtime_alive()) throw PyError(where() + "the Python interpreter is shutting down");
    pin_thread_state();
    Gil gil;
    Ref res;
    {
      Ref raw(PyList_New(n));
      if (!raw) throw_pending(where() + "cannot build raw_data");
      for (unsigned i = 0; i < n; i++)
        PyList_SET_ITEM(raw.get(), i,
                        wrap_readonly(input[i].data, input[i].size, d.tensors[i].type).release());
      Ref info = shapes_from_desc(d);
      Ref rn(PyLong_FromLong(config->rate_n)), rd(PyLong_FromLong(config->rate_d));
      if (!rn || !rd) throw_pending(where() + "cannot build the framerate");
      PyObject *args[] = {raw.get(), info.get(), rn.get(), rd.get()};
      res = Ref(PyObject_Vectorcall(decode.get(), args, 4, nullptr));
      // The arrays view memory the host unmaps after this call: warn (once) about a script that
      // keeps them (the list holds one reference each).
      if (res && !warned_kept) {
        for (unsigned i = 0; i < n && !warned_kept; i++) {
          if (Py_REFCNT(raw.get()) > 1 || Py_REFCNT(PyList_GET_ITEM(raw.get(), i)) > 1) {
            GST_WARNING(
                "%s decode() keeps raw_data beyond the call; the arrays view input "
                "memory that is released after it: keep a copy (a.copy()) instead",
                where().c_str());
            warned_kept = true;
          }
        }
      }
    }
    if (!res) throw_pending(where() + "decode() raised");
    GstMemory *mem = result_memory(res.get());
    if (!mem) return GST_FLOW_OK;  // an empty frame
    if (gst_buffer_get_size(outbuf) == 0 && gst_buffer_n_memory(outbuf) == 0) {
      gst_buffer_append_memory(outbuf, mem);
      return GST_FLOW_OK;
    }
    // The host gave a buffer (getTransformSize): fill it as far as it is writable and large.
    gsize need = gst_memory_get_sizes(mem, nullptr, nullptr), offset = 0, max = 0;
    gst_buffer_get_sizes(outbuf, &offset, &max);
    GstMapInfo src;
    bool ok = max - offset >= need && gst_memory_map(mem, &src, GST_MAP_READ);
    if (ok) {
      gsize size = gst_buffer_get_size(outbuf);
      if (size < need) gst_buffer_set_size(outbuf, static_cast<gssize>(need));
      ok = gst_buffer_fill(outbuf, 0, src.data, need) == need;
      if (ok) gst_buffer_set_size(outbuf, static_cast<gssize>(need));
      gst_memory_unmap(mem, &src);
    }
    gst_memory_unref(mem);
    if (!ok)
      throw PyError(where() + "the " + std::to_string(need) +
                    "-byte result does not fit the output buffer the host gave (" +
                    std::to_string(max - offset) + " bytes, or not writable)");
    return GST_FLOW_OK;
  }
};

int py_init(void **pdata) {
  if (!pdata) return FALSE;
  static gsize debug_once = 0;
  if (g_once_init_enter(&debug_once)) {
    GST_DEBUG_CATEGORY_INIT(nns_decoder_python3_debug, "nns_decoder_python3", 0,
                            "tensor_decoder mode=python3");
    g_once_init_leave(&debug_once, 1);
  }
  *pdata = new Decoder();
  return TRUE;
}

void py_exit(void **pdata) {
  if (!pdata) return;
  delete static_cast<Decoder *>(*pdata);
  *pdata = nullptr;
}

int py_set_option(void **pdata, int op, const char *param) {
  auto *d = pdata ? static_cast<Decoder *>(*pdata) : nullptr;
  if (!d) return FALSE;
  if (op != 0) return TRUE;  // option2..option9: not used
  if (!param || !*param) {
    d->err.set("option1 must be the path of a Python script defining class CustomDecoder");
    return FALSE;
  }
  if (d->loaded() && d->path == param) return TRUE;
  try {
    d->load(param);
  } catch (const std::exception &e) {
    d->err.set("option1: %s", e.what());
    return FALSE;
  }
  d->err.message[0] = '\0';
  return TRUE;
}

GstCaps *py_get_out_caps(void **pdata, const GstTensorsConfig *config) {
  auto *d = pdata ? static_cast<Decoder *>(*pdata) : nullptr;
  if (!d) return nullptr;
  if (!d->loaded()) {
    d->err.set("option1 (the Python script) is not set");
    return nullptr;
  }
  try {
    return d->out_caps(config);
  } catch (const std::exception &e) {
    d->err.set("%s", e.what());
    return nullptr;
  }
}

GstFlowReturn py_decode(void **pdata, const GstTensorsConfig *config, const GstTensorMemory *input,
                        GstBuffer *outbuf) {
  auto *d = pdata ? static_cast<Decoder *>(*pdata) : nullptr;
  if (!d || !config || !input || !outbuf) return GST_FLOW_ERROR;
  if (!d->loaded()) {
    d->err.set("option1 (the Python script) is not set");
    return GST_FLOW_ERROR;
  }
  try {
    return d->run(config, input, outbuf);
  } catch (const std::exception &e) {
    d->err.set("%s", e.what());
    return GST_FLOW_ERROR;
  }
}

GstTensorDecoderDef kPython3 = {const_cast<char *>("python3"),
                                py_init,
                                py_exit,
                                py_set_option,
                                py_get_out_caps,
                                py_decode,
                                nullptr};

}  // namespace
}  // namespace nns::py

extern "C" __attribute__((visibility("default"))) const GstTensorDecoderDef *
nns_decoder_subplugin_entry(void) {
  return &nns::py::kPython3;
}
