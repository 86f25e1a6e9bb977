// SPDX-License-Identifier: LGPL-2.1-only
// A time limit for test steps that could deadlock (state changes, waits across threads).
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace nns::test {

// Runs `f` on another thread and waits up to `seconds` for it. When it does not finish in time
// (a deadlock), prints what hung and ends the process with a failure right away: the hung
// thread holds locks that any cleanup (setting the pipeline to NULL, unreffing it) would wait
// for, and a std::async future would wait for it in its destructor, so the test would hang
// until ctest's TIMEOUT instead of failing. gtest_discover_tests runs every test in its own
// process, so only the hung test is lost. `f` may use the caller's locals: after the time-out
// nothing returns to the caller.
inline void finish_within(double seconds, const std::string &what, std::function<void()> f) {
  struct Done {
    std::mutex m;
    std::condition_variable cv;
    bool done = false;
  };
  auto d = std::make_shared<Done>();
  std::thread([d, f = std::move(f)] {
    f();
    std::lock_guard<std::mutex> l(d->m);
    d->done = true;
    d->cv.notify_all();
  }).detach();
  std::unique_lock<std::mutex> l(d->m);
  if (d->cv.wait_for(l, std::chrono::duration<double>(seconds), [&] { return d->done; })) return;
  const auto *info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::fprintf(stderr, "[  FAILED  ] %s.%s: %s did not finish within %g s (deadlock?)\n",
               info ? info->test_suite_name() : "?", info ? info->name() : "?", what.c_str(),
               seconds);
  std::fflush(stderr);
  std::fflush(stdout);
  std::_Exit(EXIT_FAILURE);
}

}  // namespace nns::test
