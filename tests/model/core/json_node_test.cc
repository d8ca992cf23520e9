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

}  // namespace
}  // namespace orcs
