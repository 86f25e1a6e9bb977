// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/config_file.h"

#include <algorithm>
#include <fstream>
#include <sstream>

#include "core/tensor_info.h"

namespace nns::gst {

std::vector<std::string> apply_config_file(GObject *object, const std::string &path,
                                           const std::vector<std::string> &skip) {
  std::vector<std::string> problems;
  std::ifstream f(path);
  if (!f) {
    problems.push_back("config-file '" + path + "' cannot be read");
    return problems;
  }
  std::string line;
  int lineno = 0;
  GObjectClass *klass = G_OBJECT_GET_CLASS(object);
  while (std::getline(f, line)) {
    ++lineno;
    std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    auto where = "config-file '" + path + "' line " + std::to_string(lineno) + ": ";
    auto eq = t.find('=');
    if (eq == std::string::npos) {
      problems.push_back(where + "expected property=value, got '" + t + "'");
      continue;
    }
    std::string name = trim(t.substr(0, eq));
    std::string value = trim(t.substr(eq + 1));
    if (std::find(skip.begin(), skip.end(), name) != skip.end()) {
      problems.push_back(where + "property '" + name + "' cannot be set from a config file");
      continue;
    }
    GParamSpec *ps = g_object_class_find_property(klass, name.c_str());
    if (!ps) {
      problems.push_back(where + "unknown property '" + name + "'");
      continue;
    }
    if (!(ps->flags & G_PARAM_WRITABLE)) {
      problems.push_back(where + "property '" + name + "' is read-only");
      continue;
    }
    // gst_util_set_object_arg() only warns on bad values; check the conversion first.
    GValue v = G_VALUE_INIT;
    g_value_init(&v, G_PARAM_SPEC_VALUE_TYPE(ps));
    if (G_PARAM_SPEC_VALUE_TYPE(ps) == G_TYPE_STRING) {
      g_value_set_string(&v, value.c_str());
    } else if (!gst_value_deserialize(&v, value.c_str())) {
      problems.push_back(where + "'" + value + "' is not a valid value for property '" + name +
                         "' (" + g_type_name(G_PARAM_SPEC_VALUE_TYPE(ps)) + ")");
      g_value_unset(&v);
      continue;
    }
    if (g_param_value_validate(ps, &v)) {
      problems.push_back(where + "'" + value + "' is out of range for property '" + name + "'");
      g_value_unset(&v);
      continue;
    }
    g_object_set_property(object, name.c_str(), &v);
    g_value_unset(&v);
  }
  return problems;
}

}  // namespace nns::gst
