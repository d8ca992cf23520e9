#include "model/core/value.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "model/core/text.h"

namespace orcs {
namespace {

struct NamedColor {
  std::string_view name;
  Color color;
};

// The original's colour names: Qt's global colours (Qt::darkYellow and the rest, with Qt's values), which its
// environment files and Simulation Properties used; then a few common names orcs adds (orange, brown, purple,
// grey). Names match without regard to case ("lightgray", "LightGray").
constexpr std::array<NamedColor, 22> kNamedColors{{
    {"white", {255, 255, 255, 255}},  {"black", {0, 0, 0, 255}},         {"red", {255, 0, 0, 255}},
    {"darkRed", {128, 0, 0, 255}},    {"green", {0, 255, 0, 255}},       {"darkGreen", {0, 128, 0, 255}},
    {"blue", {0, 0, 255, 255}},       {"darkBlue", {0, 0, 128, 255}},    {"cyan", {0, 255, 255, 255}},
    {"darkCyan", {0, 128, 128, 255}}, {"magenta", {255, 0, 255, 255}},   {"darkMagenta", {128, 0, 128, 255}},
    {"yellow", {255, 255, 0, 255}},   {"darkYellow", {128, 128, 0, 255}}, {"gray", {160, 160, 164, 255}},
    {"darkGray", {128, 128, 128, 255}}, {"lightGray", {192, 192, 192, 255}}, {"transparent", {0, 0, 0, 0}},
    {"grey", {160, 160, 164, 255}},   {"orange", {255, 165, 0, 255}},    {"brown", {139, 69, 19, 255}},
    {"purple", {128, 0, 128, 255}},
}};

std::optional<bool> ParseBool(std::string_view text) {
  text = text::Trim(text);
  for (std::string_view yes : {"T", "true", "1"})
    if (text::EqualsIgnoreCase(text, yes)) return true;
  for (std::string_view no : {"F", "false", "0"})
    if (text::EqualsIgnoreCase(text, no)) return false;
  return std::nullopt;
}

template <int N>
std::optional<Eigen::Matrix<double, N, 1>> ParseFixedTuple(std::string_view text) {
  const auto numbers = text::ParseNumberTuple(text);
  if (!numbers || numbers->size() != N) return std::nullopt;
  Eigen::Matrix<double, N, 1> result;
  for (int i = 0; i < N; ++i) result[i] = (*numbers)[i];
  return result;
}

std::string FormatTuple(std::initializer_list<double> numbers) {
  std::string out = "(";
  for (double number : numbers) {
    if (out.size() > 1) out += ',';
    out += text::FormatDouble(number);
  }
  return out + ")";
}

}  // namespace

std::string_view ValueTypeName(ValueType type) {
  switch (type) {
    case ValueType::kBool: return "bool";
    case ValueType::kInt: return "int";
    case ValueType::kDouble: return "double";
    case ValueType::kString: return "string";
    case ValueType::kColor: return "color";
    case ValueType::kVector3: return "vector3d";
    case ValueType::kQuaternion: return "quaternion";
  }
  return "?";
}

std::optional<Color> ParseColor(std::string_view text) {
  text = text::Trim(text);
  for (const NamedColor& named : kNamedColors)
    if (text::EqualsIgnoreCase(text, named.name)) return named.color;
  const auto numbers = text::ParseNumberTuple(text);
  if (!numbers || (numbers->size() != 3 && numbers->size() != 4)) return std::nullopt;
  std::array<int, 4> channels{0, 0, 0, 255};
  for (size_t i = 0; i < numbers->size(); ++i) {
    const double channel = (*numbers)[i];
    if (channel < 0 || channel > 255 || channel != std::floor(channel)) return std::nullopt;
    channels[i] = static_cast<int>(channel);
  }
  return Color{channels[0], channels[1], channels[2], channels[3]};
}

Eigen::Quaterniond Value::as_quaternion() const {
  const auto& q = std::get<Eigen::Vector4d>(data_);
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

std::string Value::ToString() const {
  switch (type()) {
    case ValueType::kBool: return as_bool() ? "T" : "F";
    case ValueType::kInt: return std::to_string(as_int());
    case ValueType::kDouble: return text::FormatDouble(as_double());
    case ValueType::kString: return as_string();
    case ValueType::kColor: {
      const Color c = as_color();
      return "(" + std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b) + "," +
             std::to_string(c.a) + ")";
    }
    case ValueType::kVector3: {
      const auto& v = as_vector3();
      return FormatTuple({v.x(), v.y(), v.z()});
    }
    case ValueType::kQuaternion: {
      const auto& q = std::get<Eigen::Vector4d>(data_);
      return FormatTuple({q[0], q[1], q[2], q[3]});
    }
  }
  return "";
}

std::optional<Value::Data> Value::Parse(ValueType type, std::string_view text, std::string& expected) {
  // Each branch: parse, and either return the new data or say what was expected.
  const auto result = [&expected](const auto& parsed, std::string_view what) -> std::optional<Data> {
    if (!parsed) {
      expected = what;
      return std::nullopt;
    }
    return Data(*parsed);
  };
  switch (type) {
    case ValueType::kBool: return result(ParseBool(text), "T or F");
    case ValueType::kInt: {
      const auto parsed = text::ParseInt(text);
      return result(parsed ? std::optional<std::int64_t>(*parsed) : std::nullopt, "an integer");
    }
    case ValueType::kDouble: return result(text::ParseDouble(text), "a number");
    case ValueType::kString: return Data(std::string(text));
    case ValueType::kColor: return result(ParseColor(text), "a colour name or (r,g,b[,a]) with channels 0..255");
    case ValueType::kVector3: return result(ParseFixedTuple<3>(text), "a vector (x,y,z)");
    case ValueType::kQuaternion: return result(ParseFixedTuple<4>(text), "a quaternion (w,x,y,z)");
  }
  expected = "a value";
  return std::nullopt;
}

std::string Value::CheckRange(const Data& data) const {
  if (const auto* chosen = std::get_if<std::string>(&data); chosen != nullptr && !choices_.empty()) {
    for (const std::string& choice : choices_) {
      if (text::ToLower(*chosen) == text::ToLower(choice)) return "";
    }
    std::string expected = "one of ";
    for (std::size_t i = 0; i < choices_.size(); ++i) expected += (i > 0 ? ", " : "") + choices_[i];
    return expected;
  }
  if (!range_) return "";
  double number = 0.0;
  if (const auto* integer = std::get_if<std::int64_t>(&data)) {
    number = static_cast<double>(*integer);
  } else if (const auto* real = std::get_if<double>(&data)) {
    number = *real;
  } else {
    return "";
  }
  if (number >= range_->first && number <= range_->second) return "";
  return "a number from " + text::FormatDouble(range_->first) + " to " + text::FormatDouble(range_->second);
}

std::string Value::SetFromString(std::string_view text) {
  std::string expected;
  std::optional<Data> parsed = Parse(type(), text, expected);
  if (!parsed) return expected;
  if (std::string out_of_range = CheckRange(*parsed); !out_of_range.empty()) return out_of_range;
  if (auto* chosen = std::get_if<std::string>(&*parsed)) {
    for (const std::string& choice : choices_) {
      if (text::ToLower(*chosen) == text::ToLower(choice)) *chosen = choice;  // the choice's own spelling
    }
  }
  if (!(*parsed == data_)) {
    data_ = std::move(*parsed);
    Notify();
  }
  return "";
}

std::string Value::CheckString(std::string_view text) const {
  std::string expected;
  const std::optional<Data> parsed = Parse(type(), text, expected);
  return parsed ? CheckRange(*parsed) : expected;
}

int Value::AddObserver(Observer observer) {
  observers_.emplace_back(next_observer_id_, std::move(observer));
  return next_observer_id_++;
}

void Value::RemoveObserver(int id) {
  std::erase_if(observers_, [id](const auto& entry) { return entry.first == id; });
}

void Value::Notify() const {
  for (const auto& [id, observer] : observers_) observer(*this);
}

}  // namespace orcs
