#include "model/core/json_node.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs {
namespace {

using Json = nlohmann::json;

// A field path as an error shows it: far beyond any real one ("randomisation.parameters[12].normal.deviation"),
// short enough that a path built from a 100,000-character key does not make a 100 kB error line.
constexpr std::size_t kMaxShownPathBytes = 200;
// nlohmann's own parse message, which quotes the last token read.
constexpr std::size_t kMaxShownErrorBytes = 300;

// 1-based line of a byte offset, for nlohmann's parse errors.
int LineOf(const std::string& text, std::size_t byte) {
  const std::size_t end = std::min(byte, text.size());
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
}

// Throws when arrays and objects nest deeper than kMaxJsonDepth; a scan of the text before nlohmann builds
// anything, so no deep value ever exists. Brackets inside strings do not count.
void CheckJsonDepth(const std::string& text, const std::string& source) {
  int depth = 0;
  bool in_string = false;
  bool escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        throw InputError(source, LineOf(text, i),
                         "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
      }
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

}  // namespace

Json ParseJson(const std::string& text, const std::string& source) {
  CheckJsonDepth(text, source);
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& error) {
    // nlohmann's message starts "[json.exception.parse_error.101] parse error at line 3, column 5: ...".
    std::string what = error.what();
    const std::size_t colon = what.find(": ");
    if (colon != std::string::npos) what = what.substr(colon + 2);
    // "last read: '...'" quotes the token read, which may be a whole 100,000-character string: bounded.
    throw InputError(source, LineOf(text, error.byte), "malformed JSON: " + text::Excerpt(what, kMaxShownErrorBytes));
  } catch (const Json::out_of_range& error) {
    // A number beyond double's range: "[json.exception.out_of_range.406] number overflow parsing '1E400'", no
    // position; the line is where the number first appears.
    std::string what = error.what();
    const std::size_t bracket = what.find("] ");
    if (bracket != std::string::npos) what = what.substr(bracket + 2);
    const std::size_t open = what.find('\'');
    const std::size_t close = what.rfind('\'');
    const std::string number = open < close ? what.substr(open + 1, close - open - 1) : "";
    const std::size_t at = number.empty() ? std::string::npos : text.find(number);
    throw InputError(source, at == std::string::npos ? 0 : LineOf(text, at),
                     "malformed JSON: " + text::Excerpt(what, kMaxShownErrorBytes));
  }
}

std::string DescribeJson(const Json& value) {
  switch (value.type()) {
    case Json::value_t::string: {
      return "the string \"" + text::Excerpt(value.get_ref<const std::string&>()) + "\"";
    }
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float:
      return "the number " + value.dump();
    case Json::value_t::boolean:
      return std::string("the boolean ") + (value.get<bool>() ? "true" : "false");
    case Json::value_t::null:
      return "null";
    case Json::value_t::array:
      return "an array of " + std::to_string(value.size());
    case Json::value_t::object:
      return "an object";
    default:
      return "an unsupported value";
  }
}

void JsonNode::Fail(const std::string& expected, const std::string& found) const {
  // The path holds the user's keys (schedules./Servo/SupplyVoltage, an unknown key): shown bounded and escaped.
  throw InputError(source_, 0, "field '" + text::Excerpt(path_, kMaxShownPathBytes) + "' expected " + expected +
                                   ", found " + found);
}

JsonNode JsonNode::At(const std::string& key) const {
  if (!value_.is_object()) Fail("an object");
  const auto it = value_.find(key);
  if (it == value_.end()) JsonNode(value_, Child(key), source_).Fail("a value", "nothing (the field is missing)");
  return JsonNode(*it, Child(key), source_);
}

void JsonNode::ExpectOnly(std::initializer_list<std::string_view> allowed) const {
  if (!value_.is_object()) Fail("an object");
  for (const auto& [key, member] : value_.items()) {
    if (key == "comment") continue;
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (std::string_view name : allowed) list += (list.empty() ? "" : ", ") + std::string(name);
      JsonNode(member, Child(key), source_).Fail("no such field (allowed: " + list + ")", text::Quote(key));
    }
  }
}

std::vector<JsonNode> JsonNode::Elements() const {
  if (!value_.is_array()) Fail("an array");
  std::vector<JsonNode> elements;
  elements.reserve(value_.size());
  for (std::size_t i = 0; i < value_.size(); ++i) {
    elements.emplace_back(value_[i], path_ + "[" + std::to_string(i) + "]", source_);
  }
  return elements;
}

std::vector<std::pair<std::string, JsonNode>> JsonNode::Members() const {
  if (!value_.is_object()) Fail("an object");
  std::vector<std::pair<std::string, JsonNode>> members;
  for (auto it = value_.begin(); it != value_.end(); ++it) {
    members.emplace_back(it.key(), JsonNode(it.value(), Child(it.key()), source_));
  }
  return members;
}

double JsonNode::Number(const std::string& what) const {
  if (!value_.is_number()) Fail(what);
  const double number = value_.get<double>();
  if (!std::isfinite(number)) Fail(what);
  return number;
}

int JsonNode::Integer(const std::string& what) const {
  if (!value_.is_number_integer()) Fail(what);
  const auto number = value_.get<long long>();
  if (value_.is_number_unsigned() && value_.get<unsigned long long>() > std::numeric_limits<int>::max()) Fail(what);
  if (number < std::numeric_limits<int>::min() || number > std::numeric_limits<int>::max()) Fail(what);
  return static_cast<int>(number);
}

std::uint64_t JsonNode::Unsigned(const std::string& what) const {
  if (value_.is_number_unsigned()) return value_.get<std::uint64_t>();
  if (!value_.is_number_integer() || value_.get<long long>() < 0) Fail(what);
  return static_cast<std::uint64_t>(value_.get<long long>());
}

std::string JsonNode::String(const std::string& what) const {
  if (!value_.is_string()) Fail(what);
  return value_.get<std::string>();
}

bool JsonNode::Bool(const std::string& what) const {
  if (!value_.is_boolean()) Fail(what);
  return value_.get<bool>();
}

Eigen::Vector3d JsonNode::Vector3(const std::string& what) const {
  const std::vector<double> numbers = Numbers(what);
  if (numbers.size() != 3) Fail("an array of 3 numbers (" + what + ")");
  return {numbers[0], numbers[1], numbers[2]};
}

std::vector<double> JsonNode::Numbers(const std::string& what) const {
  if (!value_.is_array()) Fail("an array of numbers (" + what + ")");
  std::vector<double> numbers;
  numbers.reserve(value_.size());
  for (const JsonNode& element : Elements()) numbers.push_back(element.Number("a number (" + what + ")"));
  return numbers;
}

}  // namespace orcs
