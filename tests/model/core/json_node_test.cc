#include "model/core/json_node.h"

#include <gtest/gtest.h>

#include "model/core/error.h"

namespace orcs {
namespace {

std::string ErrorOf(const std::string& text) {
  try {
    ParseJson(text, "x.json");
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(ParseJsonTest, MalformedTextNamesTheLine) {
  EXPECT_EQ(ErrorOf("{\n  \"a\": }"),
            "x.json:2: malformed JSON: syntax error while parsing value - unexpected '}'; expected '[', '{', or a literal");
}

// Found by the fuzzer: a number beyond double's range was nlohmann's out_of_range, not an InputError, and ended
// every program that read it with std::terminate.
TEST(ParseJsonTest, ANumberBeyondDoubleIsAnInputErrorNamingTheLine) {
  EXPECT_EQ(ErrorOf("{\n  \"duration\": 1E400\n}"), "x.json:2: malformed JSON: number overflow parsing '1E400'");
  EXPECT_EQ(ParseJson("[1E308]", "x.json")[0].get<double>(), 1e308);
}

// Issue 18: 100,000 nested arrays crashed orcs-batch with SIGSEGV (nlohmann copies, prints and destroys values
// recursively). Depth is bounded where JSON enters; brackets inside strings do not count.
TEST(ParseJsonTest, NestingDeeperThanTheBoundIsAnInputErrorNamingTheLine) {
  const auto nested = [](int depth, const std::string& open, const std::string& close) {
    std::string text;
    for (int i = 0; i < depth; ++i) text += open;
    for (int i = 0; i < depth; ++i) text += close;
    return text;
  };
  EXPECT_EQ(ErrorOf("\n" + nested(100000, "[", "]")), "x.json:2: JSON nested deeper than 256 levels");
  EXPECT_EQ(ErrorOf(nested(257, "{\"a\":", "}")), "x.json:1: JSON nested deeper than 256 levels");
  EXPECT_NO_THROW(ParseJson(nested(256, "[", "]"), "x.json"));
  EXPECT_NO_THROW(ParseJson("[\"" + std::string(1000, '[') + "\\\"[\"]", "x.json"));  // brackets in a string
}

}  // namespace
}  // namespace orcs
