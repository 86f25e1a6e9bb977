// SPDX-License-Identifier: LGPL-2.1-only
#include "core/custom_options.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace nns {
namespace {

std::string error_of(const char *text) {
  try {
    CustomOptions o(text, "backend", {"NumThreads", "Mode"});
    return "";
  } catch (const Error &e) {
    EXPECT_EQ(e.kind(), ErrorKind::kSettings);
    return e.what();
  }
}

TEST(CustomOptions, ParsesKeysCaseInsensitively) {
  CustomOptions o("numthreads:4, Mode : Fast", "backend", {"NumThreads", "Mode"});
  ASSERT_EQ(o.entries().size(), 2u);
  EXPECT_EQ(o.entries()[0].first, "NumThreads");
  EXPECT_EQ(o.get_int("NumThreads", 1, 8), 4);
  EXPECT_EQ(o.get("mode"), "Fast");
  EXPECT_EQ(o.get_choice("Mode", {"slow", "fast"}), 1u);
}

TEST(CustomOptions, EmptyAndNull) {
  EXPECT_TRUE(CustomOptions(nullptr, "b", {"A"}).entries().empty());
  EXPECT_TRUE(CustomOptions("", "b", {"A"}).entries().empty());
  EXPECT_FALSE(CustomOptions("", "b", {"A"}).get("A").has_value());
}

TEST(CustomOptions, UnknownKeyNamesKeyAndAcceptedOnes) {
  std::string e = error_of("Threads:2");
  EXPECT_NE(e.find("backend"), std::string::npos) << e;
  EXPECT_NE(e.find("'Threads'"), std::string::npos) << e;
  EXPECT_NE(e.find("NumThreads, Mode"), std::string::npos) << e;
}

TEST(CustomOptions, MalformedAndDuplicate) {
  EXPECT_NE(error_of("NumThreads").find("Key:Value"), std::string::npos);
  EXPECT_NE(error_of("NumThreads:1,numthreads:2").find("twice"), std::string::npos);
}

TEST(CustomOptions, BadValues) {
  CustomOptions o("NumThreads:x,Mode:medium", "b", {"NumThreads", "Mode", "Flag"});
  try {
    o.get_int("NumThreads", 0, 64);
    FAIL();
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("NumThreads:x"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[0, 64]"), std::string::npos) << e.what();
  }
  EXPECT_THROW(o.get_choice("Mode", {"slow", "fast"}), Error);
  EXPECT_THROW(CustomOptions("NumThreads:100", "b", {"NumThreads"}).get_int("NumThreads", 0, 64),
               Error);
  EXPECT_EQ(CustomOptions("Flag:Yes", "b", {"Flag"}).get_bool("Flag"), true);
  EXPECT_EQ(CustomOptions("Flag:0", "b", {"Flag"}).get_bool("Flag"), false);
  EXPECT_THROW(CustomOptions("Flag:2", "b", {"Flag"}).get_bool("Flag"), Error);
}

}  // namespace
}  // namespace nns
