// The variable repository: every tunable parameter and observable quantity of one simulation, as a typed
// Value at a path such as "/AngularMotor/PID/Proportional" or "/Sim/Box/Position".
//
// One repository belongs to one simulation state; there is no global instance. Values keep their address for
// the repository's lifetime, so hot code looks a value up once and keeps the pointer. Each value also has a
// stable integer id (its registration index), which the OSP gateway hands out as value ids.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "model/core/value.h"

namespace orcs {

class VariableRepository {
 public:
  VariableRepository() = default;
  VariableRepository(const VariableRepository&) = delete;
  VariableRepository& operator=(const VariableRepository&) = delete;

  /// Registers a value at `path` (must start with '/'). If the path exists already with the same type, the
  /// existing value is kept and returned (first registration wins, as in the original); a different type
  /// is a programming error (ORCS_DEMAND).
  template <typename T>
  Value& Add(std::string_view path, T&& initial) {
    return AddValue(path, std::make_unique<Value>(std::forward<T>(initial)));
  }

  /// The value at `path`, or nullptr.
  Value* Find(std::string_view path);
  const Value* Find(std::string_view path) const;

  /// The value at `path`; throws InputError("unknown repository path ...") when there is none.
  Value& Get(std::string_view path);
  const Value& Get(std::string_view path) const;

  /// Parses `text` into the value at `path`. Throws InputError naming the path and what was expected.
  void Set(std::string_view path, std::string_view text);

  /// Ids of the values whose whole path matches the regular expression (RE2 syntax: the ECMAScript of the
  /// original without backreferences and lookaround), in registration order. Throws InputError for an invalid
  /// expression or one longer than PathPattern::kMaxLength (model/core/path_pattern.h).
  std::vector<int> Match(std::string_view regular_expression) const;


  int size() const { return static_cast<int>(entries_.size()); }
  /// Id of a path, or -1.
  int IdOf(std::string_view path) const;
  const std::string& path(int id) const { return entries_[id].path; }
  Value& value(int id) { return *entries_[id].value; }
  const Value& value(int id) const { return *entries_[id].value; }

 private:
  struct Entry {
    std::string path;
    std::unique_ptr<Value> value;
  };

  Value& AddValue(std::string_view path, std::unique_ptr<Value> value);

  std::vector<Entry> entries_;
  std::unordered_map<std::string, int> ids_;
};

}  // namespace orcs
