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

// The README's paths in `desc`, each rewritten once: `../shared/` to `shared_root`, `/tmp/` outputs
// to `tmp`, `=build/` to the build tree, `=third_party/` to the source tree's. The replacements
// are made in one left-to-right pass, so a replacement (a checkout or ../shared lying under /tmp)
// is never rewritten again.
std::string rewrite_paths(const std::string &desc, const std::string &shared_root,
                          const std::string &tmp, const std::string &build_dir,
                          const std::string &source_dir) {
  const std::pair<std::string, std::string> rules[] = {
      {"../shared/", shared_root + "/"},
      {"location=/tmp/", "location=" + tmp + "/"},
      {"=build/", "=" + build_dir + "/"},
      {"=third_party/", "=" + source_dir + "/third_party/"},
  };
  std::string out;
  for (std::size_t i = 0; i < desc.size();) {
    bool hit = false;
    for (const auto &[from, to] : rules)
      if (desc.compare(i, from.size(), from) == 0) {
        out += to;
        i += from.size();
        hit = true;
        break;
      }
    if (!hit) out += desc[i++];
  }
  return out;
}

// A checkout (and so ../shared) under /tmp: its paths are not taken for README outputs.
TEST(ReadmePipelines, PathsUnderTmpAreRewrittenOnce) {
  EXPECT_EQ(rewrite_paths("filesrc location=../shared/models/a.png ! filesink "
                          "location=/tmp/out.raw labels=build/x option=third_party/y",
                          "/tmp/clone/../shared", "/tmp/nns-xyz", "/tmp/clone/build", "/tmp/clone"),
            "filesrc location=/tmp/clone/../shared/models/a.png ! filesink "
            "location=/tmp/nns-xyz/out.raw labels=/tmp/clone/build/x "
            "option=/tmp/clone/third_party/y");
  EXPECT_EQ(rewrite_paths("a location=build/l.txt b=third_party/npm/m.onnx", "/s", "/t",
                          "/tmp/c/build", "/tmp/c"),
            "a location=/tmp/c/build/l.txt b=/tmp/c/third_party/npm/m.onnx");
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
    if (desc.find("../shared/") != std::string::npos && shared_root.empty()) continue;
    const bool fetched_model = desc.find("=third_party/") != std::string::npos;
    desc = rewrite_paths(desc, shared_root, tmp, NNS_BUILD_DIR, NNS_SOURCE_DIR);
    // Models fetched by scripts/setup.sh (third_party/npm/...) are relative to the source tree;
    // a command needing one that is not fetched is skipped.
    if (fetched_model) {
      const std::string root = std::string(NNS_SOURCE_DIR) + "/";
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
