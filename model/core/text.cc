#include "model/core/text.h"

#include <cctype>
#include <charconv>
#include <cstdio>
#include <cmath>
#include <cstdint>
#include <system_error>

namespace orcs::text {

std::string_view Trim(std::string_view text) {
  const auto is_space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

std::string ToLower(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower;
}

bool EqualsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(a[i])) != std::tolower(static_cast<unsigned char>(b[i])))
      return false;
  }
  return true;
}

std::optional<double> ParseDouble(std::string_view text) {
  text = Trim(text);
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (!text.empty() && text.front() == '-') return std::nullopt;  // "+-2" is not a number
  }
  if (text.empty()) return std::nullopt;
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || std::isnan(value)) return std::nullopt;
  return value;
}

std::optional<long long> ParseInt(std::string_view text) {
  text = Trim(text);
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (!text.empty() && text.front() == '-') return std::nullopt;  // "+-2" is not a number
  }
  if (text.empty()) return std::nullopt;
  long long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

std::string FormatDouble(double value) {
  char buffer[32];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, value);
  return error == std::errc() ? std::string(buffer, end) : std::string("nan");
}

std::string FormatSignificant(double value, int digits) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
  return buffer;
}

std::optional<std::vector<double>> ParseNumberTuple(std::string_view text) {
  text = Trim(text);
  if (text.size() >= 2 && text.front() == '(' && text.back() == ')') text = Trim(text.substr(1, text.size() - 2));
  std::vector<double> numbers;
  if (text.empty()) return numbers;
  // Commas separate when present ("1, 2,3"); otherwise white space does ("1 2 3").
  std::vector<std::string_view> fields;
  if (text.find(',') != std::string_view::npos) {
    fields = Split(text, ',');
  } else {
    size_t pos = 0;
    while ((pos = text.find_first_not_of(" \t", pos)) != std::string_view::npos) {
      const size_t end = text.find_first_of(" \t", pos);
      fields.push_back(text.substr(pos, end == std::string_view::npos ? text.npos : end - pos));
      pos = end;
    }
  }
  for (std::string_view field : fields) {
    const auto number = ParseDouble(field);
    if (!number) return std::nullopt;
    numbers.push_back(*number);
  }
  return numbers;
}

std::vector<std::string_view> Split(std::string_view text, char separator) {
  std::vector<std::string_view> fields;
  size_t pos = 0;
  while (true) {
    const size_t end = text.find(separator, pos);
    fields.push_back(text.substr(pos, end == std::string_view::npos ? text.npos : end - pos));
    if (end == std::string_view::npos) return fields;
    pos = end + 1;
  }
}

std::string_view Prefix(std::string_view text, std::size_t max_bytes) {
  if (text.size() <= max_bytes) return text;
  // text[max_bytes] continues a character: back to its lead byte, at most 3 bytes before. Without one, the bytes are
  // no character, and cutting them breaks nothing.
  const auto continues = [&](std::size_t i) { return (static_cast<unsigned char>(text[i]) & 0xC0) == 0x80; };
  const std::size_t lowest = max_bytes >= 3 ? max_bytes - 3 : 0;
  std::size_t cut = max_bytes;
  while (cut > lowest && continues(cut)) --cut;
  return text.substr(0, continues(cut) ? max_bytes : cut);
}

namespace {

// Bytes of the well-formed UTF-8 character at the start of `text`, 0 when there is none.
std::size_t CharacterLength(std::string_view text) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  const unsigned char lead = byte(0);
  const std::size_t length = lead < 0x80 ? 1 : (lead >> 5) == 0x6 ? 2 : (lead >> 4) == 0xE ? 3 : (lead >> 3) == 0x1E ? 4 : 0;
  if (length <= 1) return length;
  if (text.size() < length) return 0;
  std::uint32_t code = lead & (0x7Fu >> length);
  for (std::size_t i = 1; i < length; ++i) {
    if ((byte(i) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i) & 0x3Fu);
  }
  constexpr std::uint32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};  // below: an overlong encoding
  const bool surrogate = code >= 0xD800 && code <= 0xDFFF;
  return code < kSmallest[length] || code > 0x10FFFF || surrogate ? 0 : length;
}

}  // namespace

std::string ValidUtf8(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  while (!text.empty()) {
    const std::size_t length = CharacterLength(text);
    out += length == 0 ? std::string_view("\xEF\xBF\xBD") : text.substr(0, length);
    text.remove_prefix(length == 0 ? 1 : length);
  }
  return out;
}

std::string Excerpt(std::string_view text, std::size_t max_bytes) {
  const bool shortened = text.size() > max_bytes;
  if (shortened) text = Prefix(text, max_bytes);
  static constexpr char kHex[] = "0123456789abcdef";
  std::string shown;
  shown.reserve(text.size() + 3);
  while (!text.empty()) {
    const auto byte = static_cast<unsigned char>(text[0]);
    const std::size_t length = CharacterLength(text);
    if (byte == '\n') {
      shown += "\\n";
    } else if (byte == '\r') {
      shown += "\\r";
    } else if (byte == '\t') {
      shown += "\\t";
    } else if (length == 0 || byte < 0x20 || byte == 0x7f) {  // a C0 control, DEL, or not UTF-8
      shown += {'\\', 'x', kHex[byte >> 4], kHex[byte & 0xf]};
    } else {
      std::uint32_t code = byte;
      if (length == 2) code = ((byte & 0x1Fu) << 6) | (static_cast<unsigned char>(text[1]) & 0x3Fu);
      if (length == 3) {
        code = ((byte & 0x0Fu) << 12) | ((static_cast<unsigned char>(text[1]) & 0x3Fu) << 6) |
               (static_cast<unsigned char>(text[2]) & 0x3Fu);
      }
      if ((code >= 0x80 && code <= 0x9F) || code == 0x2028 || code == 0x2029) {  // C1 controls, line separators
        shown += {'\\', 'u', kHex[(code >> 12) & 0xf], kHex[(code >> 8) & 0xf], kHex[(code >> 4) & 0xf],
                  kHex[code & 0xf]};
      } else {
        shown += text.substr(0, length);
      }
    }
    text.remove_prefix(length == 0 ? 1 : length);
  }
  return shortened ? shown + "..." : shown;
}

std::string Quote(std::string_view text) { return "'" + Excerpt(text) + "'"; }

std::string NameRule() {
  return "a label of 1 to " + std::to_string(kMaxNameBytes) +
         " bytes of UTF-8 without '/', '\\' or control characters, not '.' or '..'";
}

std::string NameProblem(std::string_view name) {
  if (name.empty()) return "it is empty";
  if (name == "." || name == "..") return "it is '" + std::string(name) + "'";
  if (name.find('/') != std::string_view::npos) return "it contains '/'";
  if (name.find('\\') != std::string_view::npos) return "it contains '\\'";
  for (std::string_view rest = name; !rest.empty();) {
    const std::size_t length = CharacterLength(rest);
    if (length == 0) return "it is not UTF-8";
    const std::string_view character = rest.substr(0, length);
    if (Excerpt(character) != character) return "it contains a control character";  // Excerpt escapes exactly those
    rest.remove_prefix(length);
  }
  if (name.size() > kMaxNameBytes) return "it has " + std::to_string(name.size()) + " bytes";
  return "";
}

}  // namespace orcs::text
