// A typed value of the variable repository: bool, int, double, string, colour, 3-vector or quaternion.
//
// Every value parses and prints itself as a string, so value files, the OSP gateway, logs, sweeps and the
// fitter all work on paths and strings alike (docs/architecture.md). Observers hear about every change, and only about
// changes (setting the same value again is silent), as in the original.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>
#include "base/demand.h"

namespace orcs {

/// An RGBA colour, each channel 0..255.
struct Color {
  int r = 0;    ///< red, 0..255
  int g = 0;    ///< green, 0..255
  int b = 0;    ///< blue, 0..255
  int a = 255;  ///< alpha (opacity), 0..255
  bool operator==(const Color&) const = default;
};

enum class ValueType { kBool, kInt, kDouble, kString, kColor, kVector3, kQuaternion };

/// Name of a type as used in documentation and errors ("double", "vector3d").
std::string_view ValueTypeName(ValueType type);

class Value {
 public:
  using Observer = std::function<void(const Value&)>;

  explicit Value(bool value) : data_(value) {}
  explicit Value(int value) : data_(static_cast<std::int64_t>(value)) {}
  explicit Value(std::int64_t value) : data_(value) {}
  explicit Value(double value) : data_(value) {}
  explicit Value(std::string value) : data_(std::move(value)) {}
  explicit Value(const char* value) : data_(std::string(value)) {}
  explicit Value(Color value) : data_(value) {}
  explicit Value(const Eigen::Vector3d& value) : data_(value) {}
  explicit Value(const Eigen::Quaterniond& value) : data_(Eigen::Vector4d(value.w(), value.x(), value.y(), value.z())) {}

  Value(const Value&) = delete;  // observers hold on to a value's address
  Value& operator=(const Value&) = delete;

  ValueType type() const { return static_cast<ValueType>(data_.index()); }

  /// The printed form: bool "T"/"F", numbers in shortest round-trip form, colour "(r,g,b,a)",
  /// vector "(x,y,z)", quaternion "(w,x,y,z)", strings as they are.
  std::string ToString() const;

  /// Parses `text` as this value's type and sets it. Returns "" on success, otherwise what was expected
  /// (e.g. "a number", "T or F") and leaves the value unchanged.
  std::string SetFromString(std::string_view text);

  /// What SetFromString(text) would return, without changing anything.
  std::string CheckString(std::string_view text) const;

  /// Restricts a number (an int or a double value) to [min, max]: SetFromString and CheckString refuse a value
  /// outside it, saying "a number from MIN to MAX". Every writer from outside — value files, scenario values and
  /// overrides, sweeps, OSP command 52, orcs-view's editor — sets values through them. The typed setters are the
  /// program's own and are not checked.
  Value& SetRange(double min, double max) {
    range_ = std::make_pair(min, max);
    return *this;
  }

  /// Restricts a string value to `choices`, matched without regard to case and stored in the choice's spelling:
  /// SetFromString and CheckString refuse anything else, saying "one of A, B".
  Value& SetChoices(std::vector<std::string> choices) {
    choices_ = std::move(choices);
    return *this;
  }

  // Typed access; the type must match (ORCS_DEMAND).
  bool as_bool() const { return std::get<bool>(data_); }
  std::int64_t as_int() const { return std::get<std::int64_t>(data_); }
  double as_double() const { return std::get<double>(data_); }
  const std::string& as_string() const { return std::get<std::string>(data_); }
  Color as_color() const { return std::get<Color>(data_); }
  const Eigen::Vector3d& as_vector3() const { return std::get<Eigen::Vector3d>(data_); }
  Eigen::Quaterniond as_quaternion() const;

  /// Typed setters; notify observers when the value changes. The type must match (ORCS_DEMAND).
  void Set(bool value) { Assign(value); }
  void Set(int value) { Assign(static_cast<std::int64_t>(value)); }
  void Set(std::int64_t value) { Assign(value); }
  void Set(double value) { Assign(value); }
  void Set(std::string value) { Assign(std::move(value)); }
  void Set(const char* value) { Assign(std::string(value)); }
  void Set(Color value) { Assign(value); }
  void Set(const Eigen::Vector3d& value) { Assign(value); }
  void Set(const Eigen::Quaterniond& value) {
    Assign(Eigen::Vector4d(value.w(), value.x(), value.y(), value.z()));
  }

  /// Registers an observer called after every change; returns an id for RemoveObserver.
  int AddObserver(Observer observer);
  void RemoveObserver(int id);

 private:
  using Data = std::variant<bool, std::int64_t, double, std::string, Color, Eigen::Vector3d, Eigen::Vector4d>;

  static std::optional<Data> Parse(ValueType type, std::string_view text, std::string& expected);
  template <typename T>
  void Assign(T&& value);
  void Notify() const;

  // "" when `data` is within range_, else what was expected.
  std::string CheckRange(const Data& data) const;

  Data data_;
  std::optional<std::pair<double, double>> range_;  // SetRange()
  std::vector<std::string> choices_;                 // SetChoices()
  std::vector<std::pair<int, Observer>> observers_;
  int next_observer_id_ = 0;
};

template <typename T>
void Value::Assign(T&& value) {
  using Stored = std::decay_t<T>;
  ORCS_DEMAND_MSG(std::holds_alternative<Stored>(data_), "Value::Set with the wrong type");
  Stored& stored = std::get<Stored>(data_);
  if (stored == value) return;
  stored = std::forward<T>(value);
  Notify();
}

/// A colour by name ("red", "lightgray", ...) or "(r,g,b)" / "(r,g,b,a)"; nullopt when neither.
std::optional<Color> ParseColor(std::string_view text);

}  // namespace orcs
