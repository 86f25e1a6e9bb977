// SPDX-License-Identifier: LGPL-2.1-only
// Helpers for the nnsprofile tests: start the tracer in this process, run a named pipeline and
// read the tracer's figures for it.
#pragma once

#include <gst/gst.h>
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "profile/tracer.h"
#include "support/harness.h"

namespace nns::test {

using nlohmann::json;

// Starts the tracer once per process (interval 0: the file is written at stops and exit).
inline std::string profile_file() {
  static const std::string file = [] {
    std::string f = make_temp_dir() + "/prof.json";
    EXPECT_TRUE(nns::profile::activate(("file=" + f + ",interval=0,sample=2").c_str()));
    return f;
  }();
  return file;
}

// Runs `desc` as a pipeline named `name` to EOS.
inline RunResult run_named(const std::string &name, const std::string &desc, double timeout = 30) {
  profile_file();
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  EXPECT_TRUE(p && !err) << (err ? err->message : "");
  if (err) g_error_free(err);
  gst_object_set_name(GST_OBJECT(p), name.c_str());
  RunResult r = run_pipeline(p, timeout);
  gst_object_unref(p);
  return r;
}

// The figures of one pipeline: elements by name, links by "from>to" names.
struct Figures {
  json all;
  std::map<std::string, json> elements;
  std::map<std::string, json> links;
  std::vector<json> threads;
};

inline Figures figures_of(const std::string &pipeline) {
  Figures f;
  f.all = json::parse(nns::profile::snapshot());
  std::map<int, std::string> names;
  for (const auto &e : f.all["elements"])
    if (e["pipeline"] == pipeline) {
      names[e["id"].get<int>()] = e["name"].get<std::string>();
      f.elements[e["name"].get<std::string>()] = e;
    }
  for (const auto &l : f.all["links"]) {
    if (l["from"].is_null() || l["to"].is_null()) continue;
    auto a = names.find(l["from"].get<int>()), b = names.find(l["to"].get<int>());
    if (a != names.end() && b != names.end()) f.links[a->second + ">" + b->second] = l;
  }
  for (const auto &t : f.all["threads"])
    if (!t["root"].is_null() && names.count(t["root"].get<int>())) f.threads.push_back(t);
  return f;
}

inline double mean_ms(const json &e, const char *total, const char *count) {
  const double n = e[count].get<double>();
  return n > 0 ? e[total].get<double>() / n / 1e6 : -1;
}

}  // namespace nns::test
