// SPDX-License-Identifier: LGPL-2.1-only
#include "core/nns_conf.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>

namespace nns {
namespace {

namespace fs = std::filesystem;

class ConfTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/nns-conf-XXXXXX";
    dir_ = mkdtemp(tmpl);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string write(const std::string &name, const std::string &text) {
    std::string p = dir_ + "/" + name;
    fs::create_directories(fs::path(p).parent_path());
    std::ofstream(p) << text;
    return p;
  }
  Conf::EnvFn env() {
    return [this](const char *n) -> const char * {
      auto it = env_.find(n);
      return it == env_.end() ? nullptr : it->second.c_str();
    };
  }

  std::string dir_;
  std::map<std::string, std::string> env_;
};

TEST(ConfParse, GroupsKeysCommentsAndSpaces) {
  auto ini = Conf::parse_ini(
      "# comment\n[common]\nenable_envvar = True\n; other\n\n[filter]\n"
      "filters=/a/b/\n framework_priority_tflite = tensorflow-lite, armnn \nbroken line\n");
  EXPECT_EQ(ini["common"]["enable_envvar"], "True");
  EXPECT_EQ(ini["filter"]["filters"], "/a/b/");
  EXPECT_EQ(ini["filter"]["framework_priority_tflite"], "tensorflow-lite, armnn");
  EXPECT_EQ(ini["filter"].count("broken line"), 0u);
}

TEST(ConfParse, Booleans) {
  EXPECT_TRUE(parse_bool("True", false));
  EXPECT_TRUE(parse_bool("yes", false));
  EXPECT_TRUE(parse_bool("1", false));
  EXPECT_TRUE(parse_bool("on", false));
  EXPECT_FALSE(parse_bool("off", true));
  EXPECT_FALSE(parse_bool("FALSE", true));
  EXPECT_FALSE(parse_bool("n", true));
  EXPECT_TRUE(parse_bool("", true));
  EXPECT_FALSE(parse_bool("maybe", false));
}

TEST_F(ConfTest, SubpluginDirsOrderEnvIniBuiltin) {
  std::string ini = write("nns.ini",
                          "[common]\nenable_envvar=true\n[filter]\nfilters=/ini/filters/\n"
                          "[converter]\nconverters=/ini/conv\n");
  env_["NNSTREAMER_FILTERS"] = "/env/filters";
  Conf c = Conf::load(ini, env());
  auto dirs = c.subplugin_dirs(SubpluginKind::kFilter);
  ASSERT_GE(dirs.size(), 3u);
  EXPECT_EQ(dirs[0], "/env/filters");
  EXPECT_EQ(dirs[1], "/ini/filters");
  EXPECT_EQ(dirs[2], "/usr/lib/nnstreamer/filters");
  auto conv = c.subplugin_dirs(SubpluginKind::kConverter);
  EXPECT_EQ(conv[0], "/ini/conv");
  EXPECT_EQ(conv[1], "/usr/lib/nnstreamer/converters");
}

TEST_F(ConfTest, EnvIgnoredUnlessEnabled) {
  std::string ini = write("nns.ini", "[filter]\nfilters=/ini/filters\nx=ini\n");
  env_["NNSTREAMER_FILTERS"] = "/env/filters";
  env_["NNSTREAMER_filter_x"] = "env";
  Conf c = Conf::load(ini, env());
  EXPECT_FALSE(c.env_enabled());
  EXPECT_EQ(c.subplugin_dirs(SubpluginKind::kFilter)[0], "/ini/filters");
  EXPECT_EQ(c.value("filter", "x").value(), "ini");
}

TEST_F(ConfTest, NoFileHonoursEnv) {
  env_["NNSTREAMER_DECODERS"] = "/env/dec:/env/dec2/";
  Conf c = Conf::load(dir_ + "/missing.ini", env());
  EXPECT_EQ(c.path(), "");
  auto dirs = c.subplugin_dirs(SubpluginKind::kDecoder);
  EXPECT_EQ(dirs[0], "/env/dec");
  EXPECT_EQ(dirs[1], "/env/dec2");
}

TEST_F(ConfTest, ValuesWithEnvOverride) {
  std::string ini =
      write("nns.ini",
            "[common]\nenable_envvar=1\n[filter]\nframework_priority_tflite=tensorflow-lite,"
            "armnn\n[pytorch]\nenable_use_gpu=false\n");
  Conf c = Conf::load(ini, env());
  EXPECT_EQ(c.framework_priority("tflite"), (std::vector<std::string>{"tensorflow-lite", "armnn"}));
  EXPECT_EQ(c.framework_priority(".tflite").size(), 2u);
  EXPECT_TRUE(c.framework_priority("onnx").empty());
  EXPECT_FALSE(c.bool_value("pytorch", "enable_use_gpu", true));
  env_["NNSTREAMER_pytorch_enable_use_gpu"] = "true";
  EXPECT_TRUE(c.bool_value("pytorch", "enable_use_gpu", false));
  EXPECT_FALSE(c.value("nothing", "here").has_value());
}

TEST_F(ConfTest, ListsAndFindsSubpluginFiles) {
  write("a/libnnstreamer_converter_foo.so", "x");
  write("a/libnnstreamer_converter_bar.so", "x");
  write("a/libnnstreamer_decoder_baz.so", "x");
  write("a/notes.txt", "x");
  write("b/libnnstreamer_converter_foo.so", "x");
  fs::create_symlink(dir_ + "/a/libnnstreamer_converter_bar.so",
                     dir_ + "/b/libnnstreamer_converter_link.so");
  std::string ini = write("nns.ini", "[converter]\nconverters=" + dir_ + "/a:" + dir_ + "/b\n");
  Conf c = Conf::load(ini, env());
  auto list = c.subplugins(SubpluginKind::kConverter);
  std::vector<std::string> names;
  for (auto &s : list) names.push_back(s.name);
  EXPECT_EQ(names, (std::vector<std::string>{"bar", "foo"}));  // symlink skipped, foo once
  EXPECT_EQ(c.find_subplugin(SubpluginKind::kConverter, "foo").value(),
            dir_ + "/a/libnnstreamer_converter_foo.so");
  EXPECT_FALSE(c.find_subplugin(SubpluginKind::kConverter, "link").has_value());
  EXPECT_FALSE(c.find_subplugin(SubpluginKind::kConverter, "baz").has_value());
  EXPECT_FALSE(c.find_subplugin(SubpluginKind::kConverter, "../a/x").has_value());

  std::string ini2 =
      write("nns2.ini", "[common]\nenable_symlink=yes\n[converter]\nconverters=" + dir_ + "/b\n");
  Conf c2 = Conf::load(ini2, env());
  EXPECT_TRUE(c2.find_subplugin(SubpluginKind::kConverter, "link").has_value());
}

TEST(ConfSingleton, ReadsNnstreamerConfAndReloads) {
  char tmpl[] = "/tmp/nns-conf-XXXXXX";
  std::string d = mkdtemp(tmpl);
  std::string p = d + "/x.ini";
  std::ofstream(p) << "[decoder]\ndecoders=/first\n";
  setenv("NNSTREAMER_CONF", p.c_str(), 1);
  Conf::reload();
  const Conf &a = Conf::get();
  EXPECT_EQ(a.path(), p);
  EXPECT_EQ(a.subplugin_dirs(SubpluginKind::kDecoder)[0], "/first");
  std::ofstream(p) << "[decoder]\ndecoders=/second\n";
  Conf::reload();
  EXPECT_EQ(Conf::get().subplugin_dirs(SubpluginKind::kDecoder)[0], "/second");
  EXPECT_EQ(a.subplugin_dirs(SubpluginKind::kDecoder)[0], "/first");  // old one still valid
  fs::remove_all(d);
}

}  // namespace
}  // namespace nns
