// SPDX-License-Identifier: LGPL-2.1-only
// Embedded-Python runtime for the python3 sub-plugins; see nns_python.h.
#define NNS_PY_NUMPY_DEFINE 1
#include "nns_numpy.h"

#include <dlfcn.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>

#ifndef NNS_PYTHON_EXECUTABLE
#define NNS_PYTHON_EXECUTABLE ""
#endif
#ifndef NNS_PYTHON_MODULE_INSTALL_DIR
#define NNS_PYTHON_MODULE_INSTALL_DIR ""
#endif

namespace nns::py {
namespace {

std::once_flag g_init_once;
std::string g_init_error;  // set when initialization failed (under g_init_once)
bool g_ready = false;      // numpy and sys.path prepared (guarded by the GIL)

// libpython is a dependency of an RTLD_LOCAL sub-plugin, so its symbols are not global; numpy's
// extension modules do not link libpython and need them global. Promote the already-loaded
// library, unless the host program (a python executable) provides the symbols itself.
void promote_libpython() {
  // The main program's handle searches the global scope only (RTLD_DEFAULT would also search
  // this library's own local dependencies, libpython included).
  if (void *self = dlopen(nullptr, RTLD_NOW)) {
    bool global = dlsym(self, "PyExc_SystemError") != nullptr;
    dlclose(self);
    if (global) return;
  }
  Dl_info info{};
  if (!dladdr(reinterpret_cast<void *>(&Py_IsInitialized), &info) || !info.dli_fname) return;
  if (!std::strstr(info.dli_fname, "libpython")) return;
  // RTLD_NOLOAD: no second copy, only a change of scope. The handle is kept for the process.
  (void)dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL);
}

std::string status_text(PyStatus st) {
  std::string s = st.func ? std::string(st.func) + ": " : std::string();
  s += st.err_msg ? st.err_msg : "unknown error";
  return s;
}

// Starts an interpreter for a host that has none. Runs once per process.
void initialize_interpreter() {
  promote_libpython();
  if (Py_IsInitialized()) return;  // the host is Python (or another sub-plugin started it)

  PyConfig config;
  PyConfig_InitPythonConfig(&config);
  config.install_signal_handlers = 0;  // SIGINT stays with the host application
  config.parse_argv = 0;
  // Without an argv, sys.argv is missing and libraries that read it fail.
  wchar_t empty[] = L"";
  wchar_t *argv[] = {empty};
  PyStatus st = PyConfig_SetArgv(&config, 1, argv);
  // The prefix (and so the standard library and site-packages with numpy) is found from the
  // program name; the default, "python3" searched on PATH, may be a different Python build than
  // the libpython we are linked with. Use the interpreter we were built against when present.
  const char *exe = NNS_PYTHON_EXECUTABLE;
  if (!PyStatus_Exception(st) && exe[0] && access(exe, X_OK) == 0 && !getenv("PYTHONHOME"))
    st = PyConfig_SetBytesString(&config, &config.program_name, exe);
  if (!PyStatus_Exception(st)) st = Py_InitializeFromConfig(&config);
  PyConfig_Clear(&config);
  if (PyStatus_Exception(st)) {
    g_init_error = "cannot initialize the Python interpreter: " + status_text(st);
    return;
  }
  // Py_InitializeFromConfig leaves this thread holding the GIL; every user takes it with
  // PyGILState_Ensure, so release it for good. The interpreter is never finalized: numpy does not
  // support re-initialization, and buffers may still reference Python arrays at exit.
  (void)PyEval_SaveThread();
}

// The folder holding nnstreamer_python.py: beside this sub-plugin in the build tree
// (build/subplugins/<kind>s/ -> build/python) or installed (<libdir>/nnstreamer/<kind>s/ ->
// <libdir>/nnstreamer/python3), then the configured install folder.
void add_module_dirs() {
  namespace fs = std::filesystem;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void *>(&add_module_dirs), &info) && info.dli_fname) {
    std::error_code ec;
    fs::path so_dir = fs::absolute(fs::path(info.dli_fname), ec).parent_path();
    for (const fs::path &cand : {so_dir / ".." / ".." / "python", so_dir / ".." / "python3"}) {
      if (fs::exists(cand / "nnstreamer_python.py", ec))
        add_sys_path(fs::weakly_canonical(cand, ec).string());
    }
  }
  const std::string installed = NNS_PYTHON_MODULE_INSTALL_DIR;
  std::error_code ec;
  if (!installed.empty() && fs::exists(fs::path(installed) / "nnstreamer_python.py", ec))
    add_sys_path(installed);
}

}  // namespace

namespace {

// The extra PyGILState_Ensure that pin_thread_state() keeps per thread; released when the
// thread exits (unless the interpreter is finalizing by then).
struct PinnedThreadState {
  bool pinned = false;
  PyGILState_STATE state{};
  PyThreadState *saved = nullptr;
  ~PinnedThreadState() {
    if (!pinned || !runtime_alive()) return;
    PyEval_RestoreThread(saved);
    PyGILState_Release(state);
  }
};
thread_local PinnedThreadState t_pinned;

}  // namespace

void pin_thread_state() noexcept {
  if (t_pinned.pinned || !runtime_alive() || PyGILState_Check()) return;
  t_pinned.state = PyGILState_Ensure();
  t_pinned.saved = PyEval_SaveThread();
  t_pinned.pinned = true;
}

bool runtime_alive() noexcept {
  if (!Py_IsInitialized()) return false;
#if PY_VERSION_HEX >= 0x030D0000
  return !Py_IsFinalizing();
#else
  return !_Py_IsFinalizing();
#endif
}

void ensure_runtime() {
  // A Python host of another version provides its own libpython's symbols, which our calls then
  // reach: refuse instead of running with a mismatched ABI.
  const std::string built =
      std::to_string(PY_MAJOR_VERSION) + "." + std::to_string(PY_MINOR_VERSION) + ".";
  const char *running = Py_GetVersion();
  if (!running || std::strncmp(running, built.c_str(), built.size()) != 0) {
    std::string r = running ? running : "?";
    throw PyError("this sub-plugin was built for Python " + built.substr(0, built.size() - 1) +
                  ", but the program runs Python " + r.substr(0, r.find(' ')));
  }
  std::call_once(g_init_once, initialize_interpreter);
  if (!g_init_error.empty()) throw PyError(g_init_error);
  if (!Py_IsInitialized()) throw PyError("the Python interpreter is not initialized");
  Gil gil;
  if (g_ready) return;
  if (_import_array() < 0) throw_pending("cannot import numpy (python3-numpy)");
  add_module_dirs();
  g_ready = true;
}

std::string type_name(PyObject *o) {
  return o ? std::string(Py_TYPE(o)->tp_name) : std::string("NULL");
}

std::string str(PyObject *o) {
  Ref s(PyObject_Str(o));
  if (!s) {
    PyErr_Clear();
    return "<unprintable>";
  }
  const char *u = PyUnicode_AsUTF8(s.get());
  if (!u) {
    PyErr_Clear();
    return "<unprintable>";
  }
  return u;
}

namespace {

// "".join(traceback.<fn>(value)) with the trailing newline removed, or "" on failure.
std::string format_with(const char *fn, PyObject *value) {
  Ref mod(PyImport_ImportModule("traceback"));
  if (!mod) {
    PyErr_Clear();
    return {};
  }
  Ref lines(PyObject_CallMethod(mod.get(), fn, "O", value));
  if (!lines) {
    PyErr_Clear();
    return {};
  }
  std::string out;
  Ref it(PyObject_GetIter(lines.get()));
  if (!it) {
    PyErr_Clear();
    return {};
  }
  while (Ref line{PyIter_Next(it.get())}) out += str(line.get());
  PyErr_Clear();
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

}  // namespace

std::string error_text() {
  if (!PyErr_Occurred()) return "unknown Python error";
  PyObject *type = nullptr, *value = nullptr, *tb = nullptr;
  PyErr_Fetch(&type, &value, &tb);
  PyErr_NormalizeException(&type, &value, &tb);
  Ref t(type), v(value), b(tb);
  if (v && b) PyException_SetTraceback(v.get(), b.get());
  if (!v) return type ? type_name(type) : std::string("unknown Python error");
  // First line "<Type>: <message>" (a SyntaxError's message names file and line), so a
  // truncated message still says what happened; then the formatted traceback.
  std::string msg = str(v.get());
  std::string head = msg.empty() ? type_name(v.get()) : type_name(v.get()) + ": " + msg;
  std::string full = format_with("format_exception", v.get());
  // The formatted exception ends with the head again: drop it (hosts cap message lengths).
  size_t last = full.rfind('\n');
  if (last != std::string::npos && head.rfind(full.substr(last + 1), 0) == 0) full.resize(last);
  if (full.empty() || full == head) return head;
  return head + "\n" + full;
}

void throw_pending(const std::string &what) {
  throw PyError(what + ": " + error_text());
}

void add_sys_path(const std::string &dir) {
  PyObject *path = PySys_GetObject("path");  // borrowed
  if (!path || !PyList_Check(path)) return;
  Ref d(PyUnicode_DecodeFSDefault(dir.c_str()));
  if (!d) {
    PyErr_Clear();
    return;
  }
  int has = PySequence_Contains(path, d.get());
  if (has == 0) PyList_Append(path, d.get());
  PyErr_Clear();
}

Script load_script(const std::string &path) {
  namespace fs = std::filesystem;
  struct stat sb {};
  if (path.empty()) throw PyError("no Python script given (model= is empty)");
  if (stat(path.c_str(), &sb) != 0)
    throw PyError("cannot open Python script '" + path + "': " + std::strerror(errno));
  if (!S_ISREG(sb.st_mode)) throw PyError("Python script '" + path + "' is not a regular file");
  FILE *f = fopen(path.c_str(), "rb");
  if (!f) throw PyError("cannot open Python script '" + path + "': " + std::strerror(errno));
  std::string source;
  char buf[65536];
  for (size_t n; (n = fread(buf, 1, sizeof buf, f)) > 0;) source.append(buf, n);
  bool read_error = ferror(f) != 0;
  fclose(f);
  if (read_error) throw PyError("cannot read Python script '" + path + "'");

  std::error_code ec;
  fs::path abs = fs::absolute(fs::path(path), ec);
  add_sys_path(abs.parent_path().string());

  Script s;
  s.path = path;
  s.name = abs.stem().string();
  PyObject *modules = PyImport_GetModuleDict();  // borrowed
  if (PyObject *old = PyDict_GetItemString(modules, s.name.c_str())) {
    // Reuse the name only when it is an earlier load of the same file.
    PyObject *file = PyObject_GetAttrString(old, "__file__");
    const char *u = file && PyUnicode_Check(file) ? PyUnicode_AsUTF8(file) : nullptr;
    bool same = u && abs.string() == u;
    Py_XDECREF(file);
    PyErr_Clear();
    if (!same) s.name = "nnstreamer_script_" + s.name;
  }

  // Compiling with the file name gives tracebacks and SyntaxErrors that point into the script;
  // the source is passed as bytes so a PEP 263 coding line is honoured.
  Ref code(Py_CompileStringExFlags(source.c_str(), abs.c_str(), Py_file_input, nullptr, -1));
  if (!code) throw_pending("Python script '" + path + "' failed to load");
  Ref module(PyModule_New(s.name.c_str()));
  if (!module) throw_pending("Python script '" + path + "' failed to load");
  PyObject *dict = PyModule_GetDict(module.get());  // borrowed
  Ref file(PyUnicode_DecodeFSDefault(abs.c_str()));
  if (!file || PyDict_SetItemString(dict, "__file__", file.get()) < 0 ||
      PyDict_SetItemString(dict, "__builtins__", PyEval_GetBuiltins()) < 0 ||
      PyDict_SetItemString(modules, s.name.c_str(), module.get()) < 0)
    throw_pending("Python script '" + path + "' failed to load");
  Ref result(PyEval_EvalCode(code.get(), dict, dict));
  if (!result) {
    std::string err = error_text();
    if (PyDict_GetItemString(modules, s.name.c_str()) == module.get())
      PyDict_DelItemString(modules, s.name.c_str());
    PyErr_Clear();
    throw PyError("Python script '" + path + "' failed to load: " + err);
  }
  s.module = std::move(module);
  return s;
}

void unload_script(Script &script) noexcept {
  if (!script.module) return;
  PyObject *modules = PyImport_GetModuleDict();
  if (PyDict_GetItemString(modules, script.name.c_str()) == script.module.get())
    PyDict_DelItemString(modules, script.name.c_str());
  PyErr_Clear();
  script.module = Ref();
}

}  // namespace nns::py
