// Small text helpers shared by every reader: trimming, number parsing and printing, tuples "(a,b,c)".
// Numbers print in the shortest form that reads back to the same bits, so files and logs round-trip exactly.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace orcs::text {

/// Text without leading and trailing white space.
std::string_view Trim(std::string_view text);

/// Lower-case ASCII copy.
std::string ToLower(std::string_view text);

/// Case-insensitive ASCII equality.
bool EqualsIgnoreCase(std::string_view a, std::string_view b);

/// The whole (trimmed) text as a finite double or ±inf; nullopt for anything else (NaN included).
std::optional<double> ParseDouble(std::string_view text);

/// The whole (trimmed) text as a 64-bit integer; nullopt otherwise.
std::optional<long long> ParseInt(std::string_view text);

/// Shortest decimal form that parses back to exactly `value` ("0.1", "1e-05", "inf").
std::string FormatDouble(double value);

/// A tuple of numbers "(a, b, c)", "a,b,c" or "a b c" (parentheses optional, commas or spaces between);
/// nullopt when an element is not a number. An empty text gives an empty vector.
std::optional<std::vector<double>> ParseNumberTuple(std::string_view text);

/// Splits at `separator`, keeping empty fields; fields are not trimmed.
std::vector<std::string_view> Split(std::string_view text, char separator);

/// `text` with every byte that does not begin a well-formed UTF-8 character (truncated, overlong, a surrogate, beyond
/// U+10FFFF) replaced by U+FFFD: what a message must be to travel in a protobuf string, which the receiver refuses
/// to parse otherwise.
std::string ValidUtf8(std::string_view text);

/// The first `max_bytes` bytes of `text`, fewer when that would cut a UTF-8 character in two (messages with a
/// broken character do not survive protobuf's UTF-8 check on the way back to a client).
std::string_view Prefix(std::string_view text, std::size_t max_bytes);

/// Text quoted for an error message: 'text', shortened to 40 characters.
std::string Quote(std::string_view text);

}  // namespace orcs::text
