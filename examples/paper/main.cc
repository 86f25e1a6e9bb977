// SPDX-License-Identifier: LGPL-2.1-only
// nns-paper: the four experiments of the NNStreamer paper (docs/paper-experiments.md), each as
// a pipeline of our elements (--mode nns) and as a hand-written "Control" loop (--mode
// control) over the same recorded inputs and models. One run = one process (so the memory
// figures are its own); the result is one JSON line appended to --out.
//
// usage: nns-paper --exp e1|e2|e3|e4 --mode nns|control --models DIR --inputs DIR
//                  [--config TEXT] [--frames N] [--live] [--rate FPS] [--out FILE]
//                  [--dump PREFIX] [--timeout S] [--ort-threads N]
// Both modes use the same ONNX Runtime threads (--ort-threads intra-op, default 1, one inter-op)
// and read their input files once before the measured interval, so the Control's batch loop
// never waits on the disk; run.sh pins both to the same cores (taskset). Each result records the
// load average before and after the run and the scheduling figures of measure.h.
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <vector>

#include "common.h"

namespace {

// "0.52 0.40 0.31" (1, 5, 15 minutes) from /proc/loadavg.
std::string loadavg() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  f >> a >> b >> c;
  return a + " " + b + " " + c;
}

int usage(const char *why) {
  std::cerr << "nns-paper: " << why
            << "\nusage: nns-paper --exp e1|e2|e3|e4 --mode nns|control --models DIR --inputs DIR"
               " [--config TEXT] [--frames N] [--live] [--rate FPS] [--out FILE]"
               " [--dump PREFIX] [--timeout S] [--ort-threads N]\n";
  return 2;
}

}  // namespace

int main(int argc, char **argv) {
  paper::Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto val = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "--exp")
        o.exp = val();
      else if (a == "--mode")
        o.mode = val();
      else if (a == "--config")
        o.config = val();
      else if (a == "--models")
        o.models = val();
      else if (a == "--inputs")
        o.inputs = val();
      else if (a == "--out")
        o.out = val();
      else if (a == "--dump")
        o.dump = val();
      else if (a == "--frames")
        o.frames = std::stoi(val());
      else if (a == "--rate")
        o.rate = std::stod(val());
      else if (a == "--timeout")
        o.timeout_s = std::stoi(val());
      else if (a == "--ort-threads")
        paper::set_ort_threads(std::stoi(val()));
      else if (a == "--live")
        o.live = true;
      else
        return usage(("unknown argument " + a).c_str());
    } catch (const std::exception &e) {
      return usage(e.what());
    }
  }
  if (o.mode != "nns" && o.mode != "control") return usage("--mode must be nns or control");
  if (o.models.empty() || o.inputs.empty()) return usage("--models and --inputs are needed");
  if (o.mode == "nns") gst_init(&argc, &argv);
  paper::Result r;
  r.exp = o.exp;
  r.mode = o.mode;
  r.config = o.config;
  r.info["live"] = o.live ? "yes" : "no";
  r.info["dump"] = o.dump.empty() ? "no" : "yes";
  r.info["ort_intra_threads"] = std::to_string(paper::ort_threads());
  r.info["loadavg_start"] = loadavg();
  // The experiment's recorded inputs, into the page cache before either side starts its clock.
  static const std::map<std::string, std::vector<std::string>> kInputs = {
      {"e1", {"e1.rgb"}},
      {"e2", {"e2.rgb", "e2.s16", "e2.imu"}},
      {"e3", {"e3.rgb"}},
      {"e4", {"e4.rgb"}}};
  if (auto it = kInputs.find(o.exp); it != kInputs.end())
    for (const auto &f : it->second) paper::warm_file(o.inputs + "/" + f);
  try {
    if (o.exp == "e1")
      paper::run_e1(o, r);
    else if (o.exp == "e2")
      paper::run_e2(o, r);
    else if (o.exp == "e3")
      paper::run_e3(o, r);
    else if (o.exp == "e4")
      paper::run_e4(o, r);
    else
      return usage("--exp must be e1, e2, e3 or e4");
  } catch (const std::exception &e) {
    std::cerr << "nns-paper " << o.exp << " " << o.mode << " " << o.config << ": " << e.what()
              << "\n";
    return 1;
  }
  r.info["loadavg_end"] = loadavg();
  const std::string line = r.json();
  std::cout << line;
  if (!o.out.empty()) {
    std::ofstream f(o.out, std::ios::app);
    f << line;
    if (!f) {
      std::cerr << "nns-paper: cannot write " << o.out << "\n";
      return 1;
    }
  }
  return 0;
}
