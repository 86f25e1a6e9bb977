// SPDX-License-Identifier: LGPL-2.1-only
// nns-profile as a user runs it: on a pipeline with a known bottleneck (an identity sleeping
// 4 ms per buffer), on the tracer file of a gst-launch-1.0 run (--from), and with bad input.
#include <glib.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/harness.h"

namespace nns::test {
namespace {

using nlohmann::json;

struct Out {
  int status = -1;
  std::string out, err;
};

Out spawn(std::vector<std::string> args, const std::vector<std::string> &env_extra = {}) {
  std::vector<char *> argv;
  for (auto &a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  gchar **env = g_get_environ();
  env = g_environ_setenv(env, "GST_PLUGIN_PATH", NNS_PLUGIN_DIR, TRUE);
  for (const auto &kv : env_extra) {
    auto eq = kv.find('=');
    env = g_environ_setenv(env, kv.substr(0, eq).c_str(), kv.substr(eq + 1).c_str(), TRUE);
  }
  gchar *o = nullptr, *e = nullptr;
  gint st = -1;
  GError *err = nullptr;
  Out r;
  if (g_spawn_sync(nullptr, argv.data(), env, G_SPAWN_SEARCH_PATH, nullptr, nullptr, &o, &e, &st,
                   &err)) {
    r.status = g_spawn_check_wait_status(st, nullptr) ? 0 : (WIFEXITED(st) ? WEXITSTATUS(st) : -1);
    r.out = o ? o : "";
    r.err = e ? e : "";
  } else {
    r.err = err ? err->message : "spawn failed";
    if (err) g_error_free(err);
  }
  g_free(o);
  g_free(e);
  g_strfreev(env);
  return r;
}

std::string slurp(const std::string &p) {
  std::ifstream f(p);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// Every non-void tag closes in order (script bodies skipped): the page is well formed.
std::string unbalanced_tag(const std::string &html) {
  static const std::vector<std::string> kVoid = {"meta", "br", "img", "input", "link", "hr"};
  std::vector<std::string> stack;
  std::size_t i = 0;
  while ((i = html.find('<', i)) != std::string::npos) {
    std::size_t end = html.find('>', i);
    if (end == std::string::npos) return "unterminated tag";
    std::string tag = html.substr(i + 1, end - i - 1);
    i = end + 1;
    if (tag.empty() || tag[0] == '!') continue;
    const bool closing = tag[0] == '/';
    const bool self = tag.back() == '/';
    std::string name = tag.substr(closing ? 1 : 0);
    name = name.substr(0, name.find_first_of(" /"));
    if (closing) {
      if (stack.empty() || stack.back() != name)
        return "</" + name + "> closes <" + (stack.empty() ? "" : stack.back()) + ">";
      stack.pop_back();
    } else if (!self && std::find(kVoid.begin(), kVoid.end(), name) == kVoid.end()) {
      stack.push_back(name);
      if (name == "script") {
        i = html.find("</script>", i);
        if (i == std::string::npos) return "unterminated script";
      }
    }
  }
  return stack.empty() ? "" : "<" + stack.back() + "> never closed";
}

class NnsProfileTool : public ::testing::Test {
 protected:
  void SetUp() override {
#ifdef NNS_SANITIZED
    GTEST_SKIP() << "runs the tool, which loads the plugin module: not in the sanitizer tree";
#endif
    dir_ = make_temp_dir();
  }
  std::string dir_;
};

TEST_F(NnsProfileTool, NamesTheSleepingIdentityAsBottleneck) {
  Out r =
      spawn({NNS_PROFILE_TOOL, "--progress", "--html", dir_ + "/r.html", "--json", dir_ + "/r.json",
             "videotestsrc num-buffers=50 ! video/x-raw,format=GRAY8,width=16,height=16 ! "
             "identity name=slow sleep-time=4000 ! tensor_converter name=conv ! "
             "fakesink name=out sync=false"},
            // An nnsprofile entry of the user's own gives way to the tool's.
            {"GST_TRACERS=nnsprofile(file=" + dir_ + "/user.json)"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("bottleneck: slow (identity)"), std::string::npos) << r.out;
  // The table lists slow first (highest share).
  const auto header = r.out.find("\nelement ");
  ASSERT_NE(header, std::string::npos) << r.out;
  EXPECT_EQ(r.out.compare(r.out.find('\n', header + 1) + 1, 5, "slow "), 0) << r.out;
  EXPECT_NE(r.err.find("buffers at sinks"), std::string::npos) << r.err;  // the progress line
  json j = json::parse(slurp(dir_ + "/r.json"));
  EXPECT_EQ(j["bottleneck"], "slow");
  std::map<std::string, json> el;
  for (const auto &e : j["elements"]) el[e["name"]] = e;
  ASSERT_TRUE(el.count("slow") && el.count("conv") && el.count("out"));
  EXPECT_EQ(el["slow"]["buffers"], 50);
  EXPECT_EQ(el["conv"]["buffers"], 50);
  EXPECT_EQ(el["out"]["buffers"], 50);
  EXPECT_GT(el["slow"]["share"].get<double>(), 0.9);
  // At least the 4 ms sleep; one thread, so per buffer at most the run's time per buffer.
  const double per = el["slow"]["per_buffer_ns"].get<double>();
  EXPECT_GE(per, 4e6);
  EXPECT_LE(per * 50, j["duration_ns"].get<double>() + 1e6);
  EXPECT_GT(el["slow"]["busy"].get<double>(), 0.8);
  EXPECT_LE(el["slow"]["busy"].get<double>(), 1.02);
  bool sink_latency = false;
  for (const auto &l : j["links"])
    if (l["to_sink"].get<bool>()) {
      sink_latency = true;
      EXPECT_EQ(l["latency"]["count"], 50);
      EXPECT_GE(l["latency"]["mean_ns"].get<double>(), per);
      EXPECT_LT(l["latency"]["mean_ns"].get<double>(), per + 20e6);  // margin for a loaded machine
    }
  EXPECT_TRUE(sink_latency);
  ASSERT_EQ(j["sinks"].size(), 1u);
  EXPECT_EQ(j["sinks"][0]["name"], "out");
  EXPECT_EQ(j["sinks"][0]["buffers"], 50);
  // The process figures of the run: mostly asleep, so well under one core.
  EXPECT_GT(j["process"]["cpu_ns"].get<double>(), 0);
  EXPECT_GE(j["process"]["wall_ns"].get<double>(), j["duration_ns"].get<double>());
  EXPECT_LT(j["process"]["cpu_share"].get<double>(), 0.9);
  EXPECT_GT(j["process"]["max_rss_kb"].get<double>(), 1000);
  EXPECT_NE(r.out.find("process: CPU "), std::string::npos);
  const std::string html = slurp(dir_ + "/r.html");
  EXPECT_EQ(unbalanced_tag(html), "");
  for (const char *n : {"slow", "conv", "out"})
    EXPECT_NE(html.find(std::string("data-name=\"") + n + "\""), std::string::npos) << n;
}

TEST_F(NnsProfileTool, ReadsTheTracerFileOfAnotherProgram) {
  const std::string trace = dir_ + "/t.json";
  Out g = spawn({"gst-launch-1.0", "-q", "videotestsrc", "num-buffers=30", "!", "identity",
                 "name=mid", "sleep-time=1000", "!", "fakesink", "name=end"},
                {"GST_TRACERS=nnsprofile(file=" + trace + ")"});
  ASSERT_EQ(g.status, 0) << g.err;
  Out r = spawn({NNS_PROFILE_TOOL, "--from", trace, "--html", "", "--json", dir_ + "/r.json"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("bottleneck: mid (identity)"), std::string::npos) << r.out;
  json j = json::parse(slurp(dir_ + "/r.json"));
  int seen = 0;
  for (const auto &e : j["elements"])
    if (e["name"] == "end") {
      ++seen;
      EXPECT_EQ(e["buffers"], 30);
    }
  EXPECT_EQ(seen, 1);
}

TEST_F(NnsProfileTool, ReportsBadInput) {
  Out r = spawn({NNS_PROFILE_TOOL, "--html", "", "--json", "", "videotestsrc ! nosuchelement"});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("cannot build the pipeline: no element \"nosuchelement\""),
            std::string::npos)
      << r.err;
  r = spawn({NNS_PROFILE_TOOL, "--bogus"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown option --bogus"), std::string::npos) << r.err;
  r = spawn({NNS_PROFILE_TOOL, "--from", dir_ + "/missing.json"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("cannot read nnsprofile output from"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace nns::test
