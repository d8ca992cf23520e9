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

// Issue 47, item 5: a value or key with a NUL cut the error message there, and a 100,000-character one made a 100 kB
// error line. What an error quotes of the user's JSON is bounded and escaped.
TEST(JsonNodeTest, ErrorsQuoteUserStringsBoundedAndEscaped) {
  EXPECT_EQ(DescribeJson(nlohmann::json(std::string("a\0b\nc", 5))), "the string \"a\\x00b\\nc\"");
  EXPECT_EQ(DescribeJson(nlohmann::json(std::string(100000, 'v'))), "the string \"" + std::string(80, 'v') + "...\"");

  const nlohmann::json document = {{std::string(100000, 'k'), 1}, {"ok", 2}};
  const std::string source = "x.json";
  const JsonNode root(document, "", source);
  std::string error;
  try {
    root.ExpectOnly({"ok"});
  } catch (const InputError& e) {
    error = e.what();
  }
  EXPECT_LT(error.size(), 400u) << "the key is in the field's path and in what was found";
  EXPECT_NE(error.find("x.json: field '" + std::string(200, 'k') + "...' expected no such field (allowed: ok), found '" +
                       std::string(80, 'k') + "...'"),
            std::string::npos)
      << error;

  const nlohmann::json nul = {{std::string("k\0ey", 4), 1}};
  const JsonNode nul_root(nul, "", source);
  try {
    nul_root.ExpectOnly({"ok"});
  } catch (const InputError& e) {
    error = e.what();
  }
  EXPECT_EQ(error, "x.json: field 'k\\x00ey' expected no such field (allowed: ok), found 'k\\x00ey'");
}

TEST(ParseJsonTest, AMalformedLongStringIsQuotedBounded) {
  const std::string error = ErrorOf("[\"" + std::string(100000, 's') + "\\q\"]");
  EXPECT_NE(error.find("x.json:1: malformed JSON: "), std::string::npos) << error;
  EXPECT_LT(error.size(), 400u) << error.substr(0, 400);
}

}  // namespace
}  // namespace orcs
