#include "model/core/text.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "model/core/random_stream.h"

namespace orcs::text {
namespace {

// True when `parsed` holds exactly the bits of `expected` (so -0.0 differs from 0.0).
bool SameBits(std::optional<double> parsed, double expected) {
  return parsed.has_value() && std::bit_cast<std::uint64_t>(*parsed) == std::bit_cast<std::uint64_t>(expected);
}

TEST(TextTest, TrimRemovesLeadingAndTrailingWhiteSpaceOnly) {
  EXPECT_EQ(Trim("  a b \t\r\n"), "a b");
  EXPECT_EQ(Trim("\tx"), "x");
  EXPECT_EQ(Trim("x  "), "x");
  EXPECT_EQ(Trim("   "), "");
  EXPECT_EQ(Trim(""), "");
  EXPECT_EQ(Trim("a  b"), "a  b");
}

TEST(TextTest, ToLowerAndEqualsIgnoreCase) {
  EXPECT_EQ(ToLower("AbC/X1"), "abc/x1");
  EXPECT_TRUE(EqualsIgnoreCase("LightGray", "lightgray"));
  EXPECT_FALSE(EqualsIgnoreCase("gray", "grey"));
  EXPECT_FALSE(EqualsIgnoreCase("gray", "gray "));
}

TEST(TextTest, ParseDoubleAcceptsNumbers) {
  EXPECT_EQ(ParseDouble("1e-3"), 1e-3);
  EXPECT_EQ(ParseDouble("+2"), 2.0);
  EXPECT_EQ(ParseDouble(" 3 "), 3.0);
  EXPECT_EQ(ParseDouble("-4.25"), -4.25);
  EXPECT_EQ(ParseDouble("0.1"), 0.1);
  EXPECT_EQ(ParseDouble("inf"), std::numeric_limits<double>::infinity());
  EXPECT_EQ(ParseDouble("-inf"), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(ParseDouble("+inf"), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(SameBits(ParseDouble("-0"), -0.0));
}

TEST(TextTest, ParseDoubleRejectsNonNumbers) {
  for (const char* bad : {"", "   ", "abc", "1.5x", "x1.5", "nan", "NaN", "-nan", "1 2", "1,5", "+", "-", "+-2",
                          "++2", "--2", "+ 2", "1e", "1e999"}) {
    EXPECT_FALSE(ParseDouble(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(TextTest, ParseIntAcceptsIntegers) {
  EXPECT_EQ(ParseInt("42"), 42);
  EXPECT_EQ(ParseInt(" -7 "), -7);
  EXPECT_EQ(ParseInt("+3"), 3);
  EXPECT_EQ(ParseInt("0"), 0);
  EXPECT_EQ(ParseInt("9223372036854775807"), std::numeric_limits<long long>::max());
  EXPECT_EQ(ParseInt("-9223372036854775808"), std::numeric_limits<long long>::min());
}

TEST(TextTest, ParseIntRejectsNonIntegers) {
  for (const char* bad : {"", " ", "1.5", "1e3", "abc", "12a", "0x10", "+-5", "--5", "+", "1 2",
                          "9223372036854775808"}) {
    EXPECT_FALSE(ParseInt(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(TextTest, FormatDoubleIsShortest) {
  EXPECT_EQ(FormatDouble(0.1), "0.1");
  EXPECT_EQ(FormatDouble(1.0), "1");
  EXPECT_EQ(FormatDouble(-2.5), "-2.5");
  EXPECT_EQ(FormatDouble(1e-5), "1e-05");
  EXPECT_EQ(FormatDouble(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(FormatDouble(-std::numeric_limits<double>::infinity()), "-inf");
}

TEST(TextTest, FormatDoubleRoundTripsExactly) {
  const std::vector<double> values{0.1,
                                   1.0 / 3.0,
                                   2.0 / 3.0,
                                   1e-300,
                                   -1e300,
                                   -0.0,
                                   0.0,
                                   5e-324,  // smallest subnormal
                                   std::numeric_limits<double>::min(),
                                   std::numeric_limits<double>::max(),
                                   std::numeric_limits<double>::epsilon(),
                                   123456789.123456789,
                                   std::numeric_limits<double>::infinity()};
  for (double value : values) {
    EXPECT_TRUE(SameBits(ParseDouble(FormatDouble(value)), value)) << FormatDouble(value);
  }
}

TEST(TextTest, FormatDoubleRoundTripsRandomDraws) {
  RandomStream random(7, "text-round-trip");
  for (int i = 0; i < 10000; ++i) {
    // Uniform doubles, normals and arbitrary bit patterns (all exponents), skipping NaNs.
    const double uniform = random.Uniform(-1e6, 1e6);
    const double normal = random.Normal(0.0, 1e-3);
    const double bits = std::bit_cast<double>(random.NextU64());
    for (double value : {uniform, normal, bits}) {
      if (std::isnan(value)) continue;
      ASSERT_TRUE(SameBits(ParseDouble(FormatDouble(value)), value)) << FormatDouble(value);
    }
  }
}

TEST(TextTest, ParseNumberTupleAcceptsTheUsualForms) {
  const std::vector<double> expected{1.0, 2.0, 3.0};
  EXPECT_EQ(ParseNumberTuple("(1,2,3)"), expected);
  EXPECT_EQ(ParseNumberTuple("1 2 3"), expected);
  EXPECT_EQ(ParseNumberTuple("(1, 2 ,3)"), expected);
  EXPECT_EQ(ParseNumberTuple("1,2,3"), expected);
  EXPECT_EQ(ParseNumberTuple("1\t2 \t 3"), expected);  // tabs separate like spaces
  EXPECT_EQ(ParseNumberTuple("  ( 1   2  3 )  "), expected);
  EXPECT_EQ(ParseNumberTuple("(-0.5,1e3)"), (std::vector<double>{-0.5, 1000.0}));
  EXPECT_EQ(ParseNumberTuple("(7)"), std::vector<double>{7.0});
}

TEST(TextTest, ParseNumberTupleOfEmptyTextIsEmpty) {
  ASSERT_TRUE(ParseNumberTuple("").has_value());
  EXPECT_TRUE(ParseNumberTuple("")->empty());
  ASSERT_TRUE(ParseNumberTuple("()").has_value());
  EXPECT_TRUE(ParseNumberTuple("()")->empty());
}

TEST(TextTest, ParseNumberTupleRejectsMalformedTuples) {
  for (const char* bad : {"(1,,2)", "(1,a)", "(1,2,)", "(,1)", "(1,2", "1,2)", "((1,2))", "1 2, 3", "(1;2)",
                          "(1,nan)"}) {
    EXPECT_FALSE(ParseNumberTuple(bad).has_value()) << "'" << bad << "'";
  }
}

TEST(TextTest, SplitKeepsEmptyFieldsUntrimmed) {
  EXPECT_EQ(Split("a,,b", ','), (std::vector<std::string_view>{"a", "", "b"}));
  EXPECT_EQ(Split(",", ','), (std::vector<std::string_view>{"", ""}));
  EXPECT_EQ(Split("", ','), std::vector<std::string_view>{""});
  EXPECT_EQ(Split(" a , b", ','), (std::vector<std::string_view>{" a ", " b"}));
}

// Found by reading what the fuzzer's job target checks: cutting at 40 bytes could split a UTF-8 character, and a
// message holding half of one made the whole result unparsable at the broker.
TEST(TextTest, PrefixAndQuoteNeverCutACharacter) {
  const std::string thirty_nine(39, 'a');
  EXPECT_EQ(Prefix(thirty_nine + "\xc3\xa9z", 40), thirty_nine);  // "é" would be cut in two: left out
  EXPECT_EQ(Prefix(thirty_nine + "\xc3\xa9z", 41), thirty_nine + "\xc3\xa9");
  EXPECT_EQ(Prefix("\xe2\x82\xac", 2), "");  // "€" (three bytes)
  EXPECT_EQ(Prefix("abc", 40), "abc");
  const std::string seventy_nine(79, 'a');
  EXPECT_EQ(Quote(seventy_nine + "\xc3\xa9xyz"), "'" + seventy_nine + "...'");
}

TEST(TextTest, ValidUtf8KeepsCharactersAndReplacesBrokenBytes) {
  const std::string replacement = "\xEF\xBF\xBD";
  EXPECT_EQ(ValidUtf8("plain, \xC3\xA9, \xE2\x82\xAC, \xF0\x9F\x98\x80"), "plain, \xC3\xA9, \xE2\x82\xAC, \xF0\x9F\x98\x80");
  EXPECT_EQ(ValidUtf8(std::string("a\0b", 3)), std::string("a\0b", 3));
  EXPECT_EQ(ValidUtf8("'\xC6'"), "'" + replacement + "'");            // a lead byte cut off (nlohmann's "last read")
  EXPECT_EQ(ValidUtf8("\xE2\x82"), replacement + replacement);        // truncated at the end
  EXPECT_EQ(ValidUtf8("\xC0\xAF"), replacement + replacement);        // overlong '/'
  EXPECT_EQ(ValidUtf8("\xED\xA0\x80"), replacement + replacement + replacement);  // a surrogate
  EXPECT_EQ(ValidUtf8("\xF4\x90\x80\x80"), replacement + replacement + replacement + replacement);  // > U+10FFFF
  EXPECT_EQ(ValidUtf8("\xFF"), replacement);
}

TEST(TextTest, QuoteEscapesControlCharactersSoAnErrorStaysOneLine) {
  EXPECT_EQ(Quote("a\nb\r\tc"), "'a\\nb\\r\\tc'");
  EXPECT_EQ(Quote(std::string("x\0y\x1f\x7f", 5)), "'x\\x00y\\x1f\\x7f'");
  EXPECT_EQ(Quote("caf\xc3\xa9"), "'caf\xc3\xa9'") << "UTF-8 is kept";
}

TEST(TextTest, QuoteShortensLongText) {
  EXPECT_EQ(Quote("abc"), "'abc'");
  EXPECT_EQ(Quote(""), "''");
  const std::string eighty(80, 'x');
  EXPECT_EQ(Quote(eighty), "'" + eighty + "'");
  EXPECT_EQ(Quote(eighty + "yz"), "'" + eighty + "...'");
  EXPECT_EQ(Quote(std::string(100000, 'x')), "'" + eighty + "...'") << "a 100,000-character name: 85 bytes";
}

TEST(TextTest, ExcerptBoundsAndEscapesWhatAUserWrote) {
  EXPECT_EQ(Excerpt("plain"), "plain");
  EXPECT_EQ(Excerpt(std::string(100000, 'x')), std::string(80, 'x') + "...");
  EXPECT_EQ(Excerpt(std::string(100, 'x'), 20), std::string(20, 'x') + "...");
  EXPECT_EQ(Excerpt(std::string("a\0b", 3)), "a\\x00b") << "a NUL does not cut what follows";
  EXPECT_EQ(Excerpt("\xff\xfe"), "\\xff\\xfe") << "bytes that are not UTF-8";
  EXPECT_EQ(Excerpt("a\xc2\x85" "b\xe2\x80\xa8" "c"), "a\\u0085b\\u2028c") << "NEL and LINE SEPARATOR break lines too";
  EXPECT_EQ(Excerpt("caf\xc3\xa9 \xe2\x82\xac"), "caf\xc3\xa9 \xe2\x82\xac");
  // A run of continuation bytes is no character: it is shown, not cut away to nothing.
  EXPECT_EQ(Excerpt(std::string(100, '\x80'), 4), "\\x80\\x80\\x80\\x80...");
}

TEST(TextTest, ANameIsALabelThatIsAlsoASafeFolderName) {
  for (const char* good : {"hips", "a b", ".hidden", "inline.genome_2", "caf\xc3\xa9", "-x"}) {
    EXPECT_EQ(NameProblem(good), "") << good;
  }
  EXPECT_EQ(NameProblem(std::string(128, 'n')), "");
  EXPECT_EQ(NameProblem(std::string(129, 'n')), "it has 129 bytes");
  EXPECT_EQ(NameProblem(""), "it is empty");
  EXPECT_EQ(NameProblem("."), "it is '.'");
  EXPECT_EQ(NameProblem(".."), "it is '..'");
  EXPECT_EQ(NameProblem("../../escaped"), "it contains '/'");
  EXPECT_EQ(NameProblem("/abs"), "it contains '/'");
  EXPECT_EQ(NameProblem("a\\b"), "it contains '\\'");
  EXPECT_EQ(NameProblem(std::string("a\0b", 3)), "it contains a control character");
  EXPECT_EQ(NameProblem("a\x7f"), "it contains a control character");
  EXPECT_EQ(NameProblem("a\xff"), "it is not UTF-8");
}

}  // namespace
}  // namespace orcs::text
