// SPDX-License-Identifier: LGPL-2.1-only
// Keeps README.md honest: every `gst-launch-1.0 ...` command in it must run to EOS.
// Paths: `../shared/` is the shared folder beside the source tree (commands using it are skipped
// when it is absent); `/tmp/<file>` outputs go to a temporary folder instead; `third_party/...`
// (npm models fetched by scripts/setup.sh) is the source tree's, commands using it are skipped
// when the file is absent; `build/...` (files the build makes, e.g. data/imagenet_labels_1000.txt)
// is this build tree's.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "pipelines/golden_util.h"

namespace {

// gst-launch-1.0 commands of a Markdown file, with "\" line continuations joined.
std::vector<std::string> launch_commands(const std::string &path) {
  std::ifstream f(path);
  std::vector<std::string> out;
  std::string line, cur;
  bool in_cmd = false;
  while (std::getline(f, line)) {
    std::string t = line;
    t.erase(0, t.find_first_not_of(" \t"));
    if (!in_cmd && t.rfind("gst-launch-1.0 ", 0) == 0) {
      in_cmd = true;
      cur.clear();
      t = t.substr(std::string("gst-launch-1.0 ").size());
    }
    if (!in_cmd) continue;
    bool cont = !t.empty() && t.back() == '\\';
    if (cont) t.pop_back();
    cur += t + " ";
    if (!cont) {
      out.push_back(cur);
      in_cmd = false;
    }
  }
  return out;
}

TEST(ReadmePipelines, EveryGstLaunchCommandRunsToEos) {
  std::string readme = std::string(NNS_SOURCE_DIR) + "/README.md";
  auto cmds = launch_commands(readme);
  ASSERT_GE(cmds.size(), 1u) << "no gst-launch-1.0 command found in " << readme;
  std::string shared = nns::test::shared_models_dir();  // .../shared/models/upstream
  std::string shared_root =
      shared.empty() ? "" : std::filesystem::path(shared).parent_path().parent_path().string();
  std::string tmp = nns::test::make_temp_dir();
  int ran = 0;
  for (std::string desc : cmds) {
    if (desc.find("../shared/") != std::string::npos) {
      if (shared_root.empty()) continue;
      nns::test::replace_all(&desc, "../shared/", shared_root + "/");
    }
    nns::test::replace_all(&desc, "location=/tmp/", "location=" + tmp + "/");
    nns::test::replace_all(&desc, "=build/", "=" + std::string(NNS_BUILD_DIR) + "/");
    // Models fetched by scripts/setup.sh (third_party/npm/...) are relative to the source tree;
    // a command needing one that is not fetched is skipped.
    if (desc.find("=third_party/") != std::string::npos) {
      const std::string root = std::string(NNS_SOURCE_DIR) + "/";
      nns::test::replace_all(&desc, "=third_party/", "=" + root + "third_party/");
      bool fetched = true;
      for (std::size_t at = desc.find(root + "third_party/"); at != std::string::npos;
           at = desc.find(root + "third_party/", at + 1)) {
        std::string path = desc.substr(at, desc.find_first_of(" \"", at) - at);
        fetched = fetched && std::filesystem::exists(path);
      }
      if (!fetched) continue;
    }
    auto r = nns::test::run_pipeline(desc, 30.0);
    EXPECT_TRUE(r.eos) << "README pipeline failed: gst-launch-1.0 " << desc << "\n  "
                       << (r.timed_out ? "timed out" : r.error_text);
    ++ran;
  }
  std::error_code ec;
  std::filesystem::remove_all(tmp, ec);
  if (ran == 0) GTEST_SKIP() << "every README pipeline needs ../shared";
}

}  // namespace
