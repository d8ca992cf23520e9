#include "model/core/variable_repository.h"

#include "base/demand.h"
#include "model/core/path_pattern.h"


#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs {

namespace {

// `text` in full with control characters escaped: a path or a pattern (and RE2's message, which repeats part of it) may hold a
// newline, and an error is one line.
std::string OneLine(std::string_view text) {
  std::string line;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte == 0x7f) {
      static constexpr char kHex[] = "0123456789abcdef";
      line += {'\\', 'x', kHex[byte >> 4], kHex[byte & 0xf]};
    } else {
      line += c;
    }
  }
  return line;
}

}  // namespace

Value& VariableRepository::AddValue(std::string_view path, std::unique_ptr<Value> value) {
  ORCS_DEMAND_MSG(!path.empty() && path.front() == '/', "repository paths start with '/'");
  if (const int existing = IdOf(path); existing >= 0) {
    ORCS_DEMAND_MSG(entries_[existing].value->type() == value->type(), "path registered twice with different types");
    return *entries_[existing].value;
  }
  ids_.emplace(std::string(path), size());
  entries_.push_back({std::string(path), std::move(value)});
  return *entries_.back().value;
}

int VariableRepository::IdOf(std::string_view path) const {
  const auto it = ids_.find(std::string(path));
  return it == ids_.end() ? -1 : it->second;
}

Value* VariableRepository::Find(std::string_view path) {
  const int id = IdOf(path);
  return id < 0 ? nullptr : entries_[id].value.get();
}

const Value* VariableRepository::Find(std::string_view path) const {
  const int id = IdOf(path);
  return id < 0 ? nullptr : entries_[id].value.get();
}

Value& VariableRepository::Get(std::string_view path) {
  return const_cast<Value&>(static_cast<const VariableRepository*>(this)->Get(path));
}

const Value& VariableRepository::Get(std::string_view path) const {
  const Value* value = Find(path);
  if (value == nullptr) throw InputError("unknown repository path '" + OneLine(path) + "'");
  return *value;
}

void VariableRepository::Set(std::string_view path, std::string_view text) {
  Value& value = Get(path);
  const std::string expected = value.SetFromString(text);
  if (!expected.empty()) {
    throw InputError(std::string(path) + ": expected " + expected + ", found " + text::Quote(text));
  }
}


std::vector<int> VariableRepository::Match(std::string_view regular_expression) const {
  const PathPattern pattern(regular_expression);
  std::vector<int> ids;
  for (int id = 0; id < size(); ++id) {
    if (pattern.Matches(entries_[id].path)) ids.push_back(id);
  }
  return ids;
}

}  // namespace orcs
