// SPDX-License-Identifier: LGPL-2.1-only
// Embedded-Python runtime shared by the python3 sub-plugins (filter now; converter and decoder
// later): one interpreter per process, GIL handling that works whether or not the host program is
// itself Python, script loading by path, and Python exceptions turned into readable messages.
//
// Rules every user of this header follows:
//  - call nns::py::ensure_runtime() before anything else (it initializes Python only when the
//    host has no interpreter yet, and never finalizes it);
//  - hold a nns::py::Gil for every Python call, from any thread;
//  - never call PyErr_Print (it exits the process on SystemExit): use error_text().
#pragma once

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdexcept>
#include <string>
#include <utility>

namespace nns::py {

// Owning reference to a Python object (nullptr allowed).
class Ref {
 public:
  Ref() = default;
  explicit Ref(PyObject *owned) noexcept : p_(owned) {}
  static Ref borrow(PyObject *b) noexcept {
    Py_XINCREF(b);
    return Ref(b);
  }
  Ref(const Ref &) = delete;
  Ref &operator=(const Ref &) = delete;
  Ref(Ref &&o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
  Ref &operator=(Ref &&o) noexcept {
    if (this != &o) {
      Py_XDECREF(p_);
      p_ = std::exchange(o.p_, nullptr);
    }
    return *this;
  }
  ~Ref() { Py_XDECREF(p_); }
  PyObject *get() const noexcept { return p_; }
  PyObject *release() noexcept { return std::exchange(p_, nullptr); }
  explicit operator bool() const noexcept { return p_ != nullptr; }

 private:
  PyObject *p_ = nullptr;
};

// Holds the GIL for its lifetime; works in threads Python has never seen and nests.
class Gil {
 public:
  Gil() noexcept : state_(PyGILState_Ensure()) {}
  ~Gil() { PyGILState_Release(state_); }
  Gil(const Gil &) = delete;
  Gil &operator=(const Gil &) = delete;

 private:
  PyGILState_STATE state_;
};

// Thrown for every failure in this module; the message is ready for the user.
class PyError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Makes the interpreter usable from this process: initializes it (without signal handlers,
// with the prefix of the Python the sub-plugin was built against) when the host has none, then
// imports numpy's C API and puts the nnstreamer_python module's folder on sys.path. Idempotent
// and thread-safe. Throws PyError (e.g. numpy missing) with the Python message.
void ensure_runtime();

// True when Python calls can be made (initialized and not finalizing). Release paths that may run
// at process exit check this before taking the GIL.
bool runtime_alive() noexcept;

// Keeps a Python thread state for the calling thread until the thread ends, so that a Gil taken
// per buffer on a streaming thread Python has never seen does not create and destroy one every
// time (with Python 3.11 that is an mmap/munmap pair and several microseconds per call). Call
// without holding the GIL, after ensure_runtime(); cheap after the first call in a thread; does
// nothing when the thread already holds the GIL (e.g. a Python host's own thread).
void pin_thread_state() noexcept;

// Takes the pending Python exception (clearing it) and formats it as
// "<Type>: <message>\n<traceback>" (traceback without the trailing newline). Returns
// "unknown Python error" when none is pending. Needs the GIL.
std::string error_text();

// Throws PyError("<what>: " + error_text()). Needs the GIL.
[[noreturn]] void throw_pending(const std::string &what);

// Appends `dir` to sys.path unless already present. Needs the GIL.
void add_sys_path(const std::string &dir);

// A script loaded as a module from its file path.
struct Script {
  Ref module;
  std::string path;  // as given
  std::string name;  // the module name it is registered under in sys.modules
};

// Loads the Python file at `path` as a fresh module (executed again on every call, so two
// filters on one script get separate module state): checks the file is readable, adds its folder
// to sys.path (so it can import its neighbours), compiles with `path` as file name and runs it.
// The module is named after the file stem unless that name belongs to another module. Throws
// PyError naming the path, with the Python traceback for syntax errors and exceptions. GIL.
Script load_script(const std::string &path);

// Removes a module load_script registered from sys.modules if it is still the registered one.
// GIL.
void unload_script(Script &script) noexcept;

// str(o) as UTF-8 ("<unprintable>" when that fails). GIL.
std::string str(PyObject *o);

// Python type name of `o` ("NoneType", "tuple", ...). GIL.
std::string type_name(PyObject *o);

}  // namespace nns::py
