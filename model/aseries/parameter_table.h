// A table of (repository path, struct member) pairs for a parameter struct, so that the caller can register
// and read a model's parameters generically instead of naming every path twice. The step functions of the
// motor and sensor models never touch the repository; the caller fills their parameter struct from it with
// ReadParameters whenever a value changes (or once per step, which costs one hash lookup per field).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

#include "model/core/variable_repository.h"

namespace orcs::aseries {

/// One parameter: its repository path and the member of `Parameters` it fills. The member type decides the
/// repository value type: double → double, int → int, bool → bool.
template <typename Parameters>
struct ParameterField {
  std::string_view path;
  std::variant<double Parameters::*, int Parameters::*, bool Parameters::*> member;
};

/// Registers every field of `table` with the value of `defaults` as its initial value. A path that exists
/// already keeps its value (first registration wins, as in the original, spec §6e).
template <typename Parameters, std::size_t N>
void AddParameters(VariableRepository& repository, const std::array<ParameterField<Parameters>, N>& table,
                   const Parameters& defaults = Parameters{}) {
  for (const ParameterField<Parameters>& field : table) {
    std::visit(
        [&](auto member) {
          const auto initial = defaults.*member;  // a plain copy: GCC 12 warns falsely on the member access
          repository.Add(field.path, initial);
        },
        field.member);
  }
}

/// Copies the repository's current values of every field of `table` into `parameters`: the values at
/// `prefix` + the field's path (per-motor copies, "/Sim/Humanoid/Right/Knee" + "/AngularMotor/..."), or at the
/// field's path itself for an empty prefix and for `no_copy` (a global that has no per-motor copy, such as
/// /Servo/Enabled). Throws InputError when a path is not registered.
template <typename Parameters, std::size_t N>
void ReadParameters(const VariableRepository& repository, const std::array<ParameterField<Parameters>, N>& table,
                    Parameters& parameters, std::string_view prefix = {}, std::string_view no_copy = {}) {
  for (const ParameterField<Parameters>& field : table) {
    const bool global = prefix.empty() || field.path == no_copy;
    const Value& value = global ? repository.Get(field.path) : repository.Get(std::string(prefix) + std::string(field.path));
    std::visit(
        [&](auto member) {
          using Member = std::remove_reference_t<decltype(parameters.*member)>;
          if constexpr (std::is_same_v<Member, double>) {
            parameters.*member = value.as_double();
          } else if constexpr (std::is_same_v<Member, int>) {
            parameters.*member = static_cast<int>(value.as_int());
          } else {
            parameters.*member = value.as_bool();
          }
        },
        field.member);
  }
}

}  // namespace orcs::aseries
