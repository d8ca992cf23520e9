#include "model/core/variable_repository.h"

#include <cassert>
#include <regex>

#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs {

Value& VariableRepository::AddValue(std::string_view path, std::unique_ptr<Value> value) {
  assert(!path.empty() && path.front() == '/' && "repository paths start with '/'");
  if (const int existing = IdOf(path); existing >= 0) {
    assert(entries_[existing].value->type() == value->type() && "path registered twice with different types");
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
  if (value == nullptr) throw InputError("unknown repository path '" + std::string(path) + "'");
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
  std::regex pattern;
  try {
    pattern = std::regex(std::string(regular_expression), std::regex::ECMAScript | std::regex::optimize);
  } catch (const std::regex_error& error) {
    throw InputError("invalid regular expression '" + std::string(regular_expression) + "': " + error.what());
  }
  std::vector<int> ids;
  for (int id = 0; id < size(); ++id) {
    if (std::regex_match(entries_[id].path, pattern)) ids.push_back(id);
  }
  return ids;
}

}  // namespace orcs
