// SPDX-License-Identifier: LGPL-2.1-only
// The armnn back end opened, invoked and closed from 8 threads at once. Arm NN's CpuRef device
// is a dynamic back end: a runtime registers it when created and unregisters it when destroyed,
// so with one runtime per filter a close in one thread used to unregister CpuRef under another
// thread's open ("CpuRef has no IBackend factory registered"). The back end now shares one
// process-wide runtime. Its own executable: no other test may create a runtime first (that
// would hide the race).
#include <gtest/gtest.h>

#include <atomic>
#include <latch>
#include <string>
#include <thread>
#include <vector>

#include "backends/backend_loader.h"
#include "support/harness.h"

namespace {

using nns::test::Instance;
using nns::test::Props;

TEST(ArmnnThreads, OpenInvokeCloseFromEightThreads) {
  const nns::test::BackendLib &lib = nns::test::backend_lib("armnn");
  if (!lib.ok()) GTEST_SKIP() << "armnn back end: " << lib.error();
  NNS_REQUIRE_SHARED_MODELS();
  const std::string model = nns::test::shared_models_dir() + "/models/add.tflite";
  // The old code failed in about 1 of 10 runs of 8 x 12 rounds: 8 x 250 rounds caught it in
  // every run tried (5 of 5); they take ~0.5 s.
  constexpr int kThreads = 8, kRounds = 250;
  std::latch start(kThreads);
  std::atomic<int> failures{0}, done{0};
  std::vector<std::string> errors(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      start.arrive_and_wait();
      for (int r = 0; r < kRounds; ++r) {
        Props p;
        p.framework = "armnn";
        p.models = {model};
        Instance inst(lib.api(), p);
        if (inst.rc() != 0) {
          ++failures;
          errors[t] = "open: " + inst.error();
          return;
        }
        float x = static_cast<float>(t * 100 + r), o = -1;
        std::vector<GstTensorMemory> ins{{&x, 4}}, outs{{&o, 4}};
        if (inst.invoke(ins, outs) != 0 || o != x + 2.f) {
          ++failures;
          errors[t] = "invoke: " + inst.error() + " (got " + std::to_string(o) + ")";
          return;
        }
        ++done;
      }
    });
  for (auto &th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_EQ(errors[t], "") << "thread " << t;
  EXPECT_EQ(failures.load(), 0);
  EXPECT_EQ(done.load(), kThreads * kRounds);
}

}  // namespace
