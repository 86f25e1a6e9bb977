// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter back end "python3": runs a Python script defining NNStreamer's CustomFilter class.
//
//   gst-launch-1.0 videotestsrc num-buffers=10 ! video/x-raw,format=RGB,width=640,height=480 !
//     tensor_converter ! tensor_filter framework=python3 model=scaler.py custom=320x240 !
//     tensor_sink
//
// The script (compatible with NNStreamer's):
//   class CustomFilter:
//     def __init__(self, *args)         # args: custom= split on spaces
//     def getInputDim(self) / getOutputDim(self)  -> [nnstreamer_python.TensorShape, ...]
//     def setInputDim(self, in_shapes)  -> output shapes (used instead of the get pair if present)
//     def invoke(self, inputs)          -> list of numpy arrays, one per output
// Inputs are read-only 1-D numpy arrays over the caller's memory (no copy), valid during invoke
// only. Outputs (NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE): a returned array is lent to the host as is,
// holding a reference until free_output; it is copied first when it is not C-contiguous, overlaps
// an input, or overlaps an array still lent (the same array returned twice or kept by the script).
// invoke-dynamic: inputs are shaped (numpy order) and the returned arrays' shapes and dtypes
// describe each frame's output.
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "nns_filter_backend.hh"
#include "nns_numpy.h"
#include "nns_python_lend.h"
#include "nns_python_tensors.h"

namespace nns::py {
namespace {

const char *const kExtensions[] = {".py", nullptr};

// Runs `f`, turning PyError into FilterError (the script or its results are at fault).
template <typename F>
auto script_call(F &&f) -> decltype(f()) {
  try {
    return f();
  } catch (const PyError &e) {
    throw FilterError(e.what(), -EINVAL);
  }
}

// The loaded script and the CustomFilter instance with its methods looked up once.
struct Instance {
  Script script;
  Ref obj;
  Ref invoke, set_input_dim, get_input_dim, get_output_dim;  // bound methods
  ~Instance() { unload_script(script); }
};

// Optional bound method `name` of `obj` (empty Ref when absent or not callable).
Ref method(PyObject *obj, const char *name) {
  Ref m(PyObject_GetAttrString(obj, name));
  if (!m || !PyCallable_Check(m.get())) {
    PyErr_Clear();
    return Ref();
  }
  return m;
}

class Python3Filter final : public FilterBackend {
 public:
  explicit Python3Filter(const nns_filter_props &p) {
    script_call([&] {
      path_ = script_path(p);
      custom_ = p.custom ? p.custom : "";
      ensure_runtime();
      Gil gil;
      if (p.input && p.input->num_tensors) {
        in_ = *p.input;
        in_known_ = true;
      }
      if (p.output && p.output->num_tensors) {
        out_ = *p.output;
        out_known_ = true;
      }
      inst_ = prepare(path_, custom_, in_, in_known_, out_, out_known_);
    });
  }

  ~Python3Filter() override {
    if (!runtime_alive()) {
      // Process exit: Python objects cannot be released any more; leave them.
      if (inst_) {
        inst_->script.module.release();
        inst_->obj.release();
        inst_->invoke.release();
        inst_->set_input_dim.release();
        inst_->get_input_dim.release();
        inst_->get_output_dim.release();
        (void)inst_.release();
      }
      return;
    }
    Gil gil;
    inst_.reset();
  }

  bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) override {
    return script_call([&] {
      Gil gil;
      if (!inst_->get_input_dim) return false;  // setInputDim script: no fixed shapes
      query_get_dims(*inst_, path_, in_, out_);
      in_known_ = out_known_ = true;
      in = in_;
      out = out_;
      return true;
    });
  }

  bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) override {
    return script_call([&] {
      Gil gil;
      if (!inst_->set_input_dim) return false;             // getInputDim/getOutputDim script
      auto result = std::make_unique<nns_tensors_desc>();  // 83 KB: not on a streaming stack
      call_set_input_dim(*inst_, path_, in, *result);
      in_ = in;
      out_ = *result;
      in_known_ = out_known_ = true;
      out = *result;
      return true;
    });
  }

  void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
              uint32_t num_out) override {
    script_call([&] { run(in, num_in, out, num_out); });
  }

  void invoke_dynamic(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                      nns_tensors_desc &out_info, GstTensorMemory *out) override {
    script_call([&] { run_dynamic(in_info, in, out_info, out); });
  }

  void reload(const nns_filter_props &p) override {
    script_call([&] {
      std::string path = script_path(p);
      std::string custom = p.custom ? p.custom : "";
      Gil gil;
      auto in = std::make_unique<nns_tensors_desc>(in_);
      auto out = std::make_unique<nns_tensors_desc>(out_);
      bool in_known = in_known_, out_known = out_known_;
      std::unique_ptr<Instance> fresh = prepare(path, custom, *in, in_known, *out, out_known);
      inst_.swap(fresh);  // the old instance goes with `fresh`, under the GIL
      path_ = path;
      custom_ = custom;
      in_ = *in;
      out_ = *out;
      in_known_ = in_known;
      out_known_ = out_known;
    });
  }

 private:
  static std::string script_path(const nns_filter_props &p) {
    if (p.num_models != 1 || !p.model_files || !p.model_files[0])
      throw PyError("python3 takes exactly one Python script as model (got " +
                    std::to_string(p.num_models) + " files)");
    return p.model_files[0];
  }

  // Loads the script, creates CustomFilter(*custom.split(' ')) and finds its methods; then asks
  // the script for its shapes (get pair) or gives it the known input (setInputDim). GIL held.
  static std::unique_ptr<Instance> prepare(const std::string &path, const std::string &custom,
                                           nns_tensors_desc &in, bool &in_known,
                                           nns_tensors_desc &out, bool &out_known) {
    auto inst = std::make_unique<Instance>();
    inst->script = load_script(path);
    const std::string where = "Python script '" + path + "'";
    Ref cls(PyObject_GetAttrString(inst->script.module.get(), "CustomFilter"));
    if (!cls) {
      PyErr_Clear();
      throw PyError(where + " defines no class CustomFilter");
    }
    // NNStreamer passes custom= to the constructor as positional strings split on spaces.
    std::vector<std::string> args;
    for (size_t pos = 0; pos <= custom.size();) {
      size_t sp = custom.find(' ', pos);
      if (sp == std::string::npos) sp = custom.size();
      if (sp > pos) args.push_back(custom.substr(pos, sp - pos));
      pos = sp + 1;
    }
    Ref tuple(PyTuple_New(static_cast<Py_ssize_t>(args.size())));
    if (!tuple) throw_pending(where);
    for (size_t i = 0; i < args.size(); i++) {
      PyObject *s = PyUnicode_DecodeUTF8(args[i].data(), args[i].size(), "replace");
      if (!s) throw_pending(where);
      PyTuple_SET_ITEM(tuple.get(), i, s);
    }
    inst->obj = Ref(PyObject_Call(cls.get(), tuple.get(), nullptr));
    if (!inst->obj) throw_pending(where + ": CustomFilter(" + custom + ") raised");

    inst->invoke = method(inst->obj.get(), "invoke");
    if (!inst->invoke) throw PyError(where + ": CustomFilter has no invoke(self, inputs) method");
    inst->set_input_dim = method(inst->obj.get(), "setInputDim");
    if (!inst->set_input_dim) {
      inst->get_input_dim = method(inst->obj.get(), "getInputDim");
      inst->get_output_dim = method(inst->obj.get(), "getOutputDim");
      if (!inst->get_input_dim || !inst->get_output_dim)
        throw PyError(where +
                      ": CustomFilter needs setInputDim(self, shapes) or both getInputDim(self) "
                      "and getOutputDim(self)");
      query_get_dims(*inst, path, in, out);
      in_known = out_known = true;
    } else if (in_known) {
      call_set_input_dim(*inst, path, in, out);
      out_known = true;
    }
    return inst;
  }

  static void query_get_dims(Instance &inst, const std::string &path, nns_tensors_desc &in,
                             nns_tensors_desc &out) {
    const std::string where = "Python script '" + path + "': ";
    Ref i(PyObject_CallNoArgs(inst.get_input_dim.get()));
    if (!i) throw_pending(where + "getInputDim() raised");
    Ref o(PyObject_CallNoArgs(inst.get_output_dim.get()));
    if (!o) throw_pending(where + "getOutputDim() raised");
    auto di = std::make_unique<nns_tensors_desc>();  // 83 KB each: not on the stack
    auto dout = std::make_unique<nns_tensors_desc>();
    desc_from_shapes(i.get(), where + "getInputDim()", *di);
    desc_from_shapes(o.get(), where + "getOutputDim()", *dout);
    in = *di;
    out = *dout;
  }

  static void call_set_input_dim(Instance &inst, const std::string &path,
                                 const nns_tensors_desc &in, nns_tensors_desc &out) {
    const std::string where = "Python script '" + path + "': ";
    Ref shapes = shapes_from_desc(in);
    Ref r(PyObject_CallOneArg(inst.set_input_dim.get(), shapes.get()));
    if (!r) throw_pending(where + "setInputDim() raised");
    if (r.get() == Py_None)
      throw PyError(where + "setInputDim() returned None: the script does not accept input " +
                    desc_text(in));
    desc_from_shapes(r.get(), where + "setInputDim()", out);
  }

  std::string where() const { return "Python script '" + path_ + "': "; }

  // Checks the inputs against `desc`, calls invoke() with one read-only array per input (1-D, or
  // with the tensors' numpy shapes when `shaped`) and returns its result, checked to be a list.
  // Takes the GIL; the caller holds `gil` for as long as it uses the result.
  Ref call_script(const GstTensorMemory *in, uint32_t num_in, const nns_tensors_desc &desc,
                  bool shaped) {
    // Messages are built on error paths only: no allocation per invoke.
    for (uint32_t i = 0; i < num_in; i++) {
      size_t want = tensor_bytes(desc.tensors[i]);
      if (in[i].size != want || (!in[i].data && want))
        throw PyError(where() + "input tensor " + std::to_string(i) + " has " +
                      std::to_string(in[i].size) + " bytes; expected " + std::to_string(want) +
                      " (" + dims_text(desc.tensors[i]) + " " + type_name_of(desc.tensors[i].type) +
                      ")");
    }
    Ref list(PyList_New(num_in));
    if (!list) throw_pending(where() + "cannot build the input list");
    for (uint32_t i = 0; i < num_in; i++)
      PyList_SET_ITEM(list.get(), i,
                      wrap_readonly(in[i].data, in[i].size, desc.tensors[i].type,
                                    shaped ? &desc.tensors[i] : nullptr)
                          .release());
    Ref res(PyObject_CallOneArg(inst_->invoke.get(), list.get()));
    list = Ref();  // the input arrays go now unless the script kept them
    if (!res) throw_pending(where() + "invoke() raised");
    if (!PyList_Check(res.get()))
      throw PyError(where() + "invoke() returned " + type_name(res.get()) +
                    "; expected a list of numpy arrays");
    return res;
  }

  void run(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out, uint32_t num_out) {
    if (!in_known_ || !out_known_)
      throw PyError(where() + "the input and output tensors are not known yet (setInputDim() " +
                    "has not been called: set the input first)");
    if (num_in != in_.num_tensors || num_out != out_.num_tensors)
      throw PyError(where() + "invoked with " + std::to_string(num_in) + " inputs and " +
                    std::to_string(num_out) + " outputs; the script has " +
                    std::to_string(in_.num_tensors) + " and " + std::to_string(out_.num_tensors));
    // A Python host that is exiting: taking the GIL now would end this thread inside Python.
    if (!runtime_alive()) throw PyError(where() + "the Python interpreter is shutting down");
    Gil gil;
    Ref res = call_script(in, num_in, in_, false);
    if (PyList_GET_SIZE(res.get()) != static_cast<Py_ssize_t>(num_out))
      throw PyError(where() + "invoke() returned " + std::to_string(PyList_GET_SIZE(res.get())) +
                    " arrays; the script's output has " + std::to_string(num_out) + " tensors (" +
                    desc_text(out_) + ")");

    // Validate and (where needed) copy every output before lending any: a failure lends none.
    LendBatch batch(pending_, in, num_in);
    for (uint32_t i = 0; i < num_out; i++) {
      PyObject *o = PyList_GET_ITEM(res.get(), i);
      const nns_tensor_desc &t = out_.tensors[i];
      auto what = [&] { return where() + "invoke() output " + std::to_string(i); };
      if (!PyArray_Check(o))
        throw PyError(what() + " is a " + type_name(o) + ", not a numpy array");
      auto *arr = reinterpret_cast<PyArrayObject *>(o);
      if (!PyArray_EquivTypenums(PyArray_TYPE(arr), numpy_type(t.type)) ||
          !PyArray_ISNOTSWAPPED(arr)) {
        std::string dname = str(reinterpret_cast<PyObject *>(PyArray_DESCR(arr)));
        throw PyError(what() + " has numpy type " + dname + "; expected " + type_name_of(t.type));
      }
      size_t bytes = static_cast<size_t>(PyArray_NBYTES(arr));
      if (bytes != tensor_bytes(t))
        throw PyError(what() + " has " + std::to_string(bytes) + " bytes; expected " +
                      std::to_string(tensor_bytes(t)) + " (" + dims_text(t) + " " +
                      type_name_of(t.type) + ")");
      if (!batch.add(o)) throw_pending(what() + ": copying failed");
    }
    batch.commit(out);
  }

  // invoke-dynamic: this frame's input shapes in `in_info`; the arrays the script returns define
  // the output (dims = numpy shape reversed, type = dtype), lent like static outputs.
  void run_dynamic(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                   nns_tensors_desc &out_info, GstTensorMemory *out) {
    if (in_info.num_tensors < 1 || in_info.num_tensors > NNS_TENSOR_SIZE_LIMIT)
      throw PyError(where() + "invoke-dynamic with " + std::to_string(in_info.num_tensors) +
                    " input tensors");
    if (!runtime_alive()) throw PyError(where() + "the Python interpreter is shutting down");
    Gil gil;
    Ref res = call_script(in, in_info.num_tensors, in_info, true);
    Py_ssize_t n = PyList_GET_SIZE(res.get());
    if (n < 1 || n > NNS_TENSOR_SIZE_LIMIT)
      throw PyError(where() + "invoke() returned " + std::to_string(n) + " arrays; expected 1 to " +
                    std::to_string(NNS_TENSOR_SIZE_LIMIT));
    LendBatch batch(pending_, in, in_info.num_tensors);
    for (Py_ssize_t i = 0; i < n; i++) {
      PyObject *o = PyList_GET_ITEM(res.get(), i);
      auto what = [&] { return where() + "invoke() output " + std::to_string(i); };
      if (!PyArray_Check(o))
        throw PyError(what() + " is a " + type_name(o) + ", not a numpy array");
      auto *arr = reinterpret_cast<PyArrayObject *>(o);
      nns_tensor_desc &t = out_info.tensors[i];
      std::memset(&t, 0, sizeof t);
      t.type = tensor_type_from_dtype(reinterpret_cast<PyObject *>(PyArray_DESCR(arr)),
                                      what() + " type");
      int nd = PyArray_NDIM(arr);
      if (nd > NNS_TENSOR_RANK_LIMIT)
        throw PyError(what() + " has " + std::to_string(nd) + " dimensions; the limit is " +
                      std::to_string(NNS_TENSOR_RANK_LIMIT));
      if (PyArray_SIZE(arr) == 0) throw PyError(what() + " has no elements");
      t.dims[0] = 1;  // a 0-d array is one element
      for (int j = 0; j < nd; j++) {
        npy_intp d = PyArray_DIM(arr, nd - 1 - j);
        if (d > 0xffffffffLL) throw PyError(what() + " has a dimension above 4294967295");
        t.dims[j] = static_cast<uint32_t>(d);
      }
      if (!batch.add(o)) throw_pending(what() + ": copying failed");
    }
    out_info.num_tensors = static_cast<uint32_t>(n);
    out_info.format = _NNS_TENSOR_FORMAT_STATIC;
    batch.commit(out);
  }

  std::string path_, custom_;
  std::unique_ptr<Instance> inst_;
  nns_tensors_desc in_{}, out_{};
  bool in_known_ = false, out_known_ = false;
  std::vector<LentArray> pending_;  // per-invoke scratch, kept to avoid reallocation
};

void free_output(void *priv, void *data) {
  (void)priv;  // may already be closed: lent arrays are tracked process-wide
  release_lent(data);
}

}  // namespace
}  // namespace nns::py

extern "C" __attribute__((visibility("default"))) const nns_filter_backend_i *
nns_filter_backend_entry(void) {
  static const nns_filter_backend_i table = [] {
    nns_filter_backend_i t = nns::FilterBackendAdapter<nns::py::Python3Filter>::make(
        "python3", NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE | NNS_FILTER_FLAG_DYNAMIC,
        nns::py::kExtensions);
    t.free_output = &nns::py::free_output;
    return t;
  }();
  return &table;
}
