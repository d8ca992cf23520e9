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

/// `value` to `digits` significant digits, for reports ("144.8", "0.0007", "2.6e+04").
std::string FormatSignificant(double value, int digits);

/// A tuple of numbers "(a, b, c)", "a,b,c" or "a b c" (parentheses optional, commas or spaces between);
/// nullopt when an element is not a number. An empty text gives an empty vector.
std::optional<std::vector<double>> ParseNumberTuple(std::string_view text);

/// Splits at `separator`, keeping empty fields; fields are not trimmed.
std::vector<std::string_view> Split(std::string_view text, char separator);

/// `text` with every byte that does not begin a well-formed UTF-8 character (truncated, overlong, a surrogate, beyond
/// U+10FFFF) replaced by U+FFFD: what a message must be to travel in a protobuf string, which the receiver refuses
/// to parse otherwise.
std::string ValidUtf8(std::string_view text);

/// The first `max_bytes` bytes of `text`, fewer (by at most 3) when that would cut a UTF-8 character in two (messages
/// with a broken character do not survive protobuf's UTF-8 check on the way back to a client).
std::string_view Prefix(std::string_view text, std::size_t max_bytes);

/// User text as an error message may show it, bounded and on one line: its first `max_bytes` bytes (never half a
/// UTF-8 character) followed by "..." when it was longer, with every control character escaped (\n, \r, \t, \xNN
/// for the other C0 bytes, NUL and DEL; \uNNNN for C1 controls, U+2028 and U+2029) and every byte that does not
/// begin a well-formed UTF-8 character written \xNN. A NUL cannot cut the message, a newline cannot make it two
/// lines, and a 100,000-character name costs 80 bytes. Every message that quotes what a user wrote — a name, a
/// value, a key, a path — quotes it through this (or Quote).
std::string Excerpt(std::string_view text, std::size_t max_bytes = 80);

/// Text quoted for an error message: 'text', as Excerpt shows it (shortened to 80 bytes — a long repository path
/// still shows whole —, control characters escaped).
std::string Quote(std::string_view text);

/// The most bytes a name may have that orcs also uses as a folder name: a scenario's name (the default output
/// folder runs/<name>) and a regression suite's.
inline constexpr std::size_t kMaxNameBytes = 128;

/// What the name rule asks, for messages: "a label of 1 to 128 bytes without '/', '\\' or control characters,
/// not '.' or '..'".
std::string NameRule();

/// Why `name` breaks the name rule (docs/scenarios.md, "name"): a name is a label, and it is also the folder its
/// results go to under runs/, so it must not be able to leave that folder or be the folder itself. "" when it is a
/// good name; else what is wrong: "it is empty", "it has 130 bytes", "it contains '/'", "it contains a control
/// character", "it is '..'", "it is not UTF-8".
std::string NameProblem(std::string_view name);

}  // namespace orcs::text
