#include "model/physics/material_table.h"

#include <cstddef>

namespace orcs::physics {
namespace {

// Materials 0..8 have table cells; Custom1/Custom2 (9, 10) are resolved by rule before the tables are read.
constexpr int kTableSize = 9;
using Matrix = double[kTableSize][kTableSize];

constexpr std::string_view kNames[MaterialTable::kCount] = {
    "PlasticsWhite", "PlasticsGray", "ABS", "Latex", "PVC", "Wood", "Carpet", "Default", "Light", "Custom1", "Custom2",
};

// spec/aseries.md §7, as the original stored them: row = first geom's material, column = second's.
// Order: PlasticsWhite, PlasticsGray, ABS, Latex, PVC, Wood, Carpet, Default, Light.
constexpr Matrix kStaticFriction = {
    {0.11935, 0.08835, 0.2659, 0, 0.14024, 0.0955, 0.3119, 0.83462, 0},
    {0.08835, 0, 0.6782, 0, 0.24739, 0.2297, 0.36235, 0.83462, 0},
    {0.2659, 0.6782, 0.8097, 0, 0.20874, 0.2237, 0.55167, 0.83462, 0},
    {0, 0, 0, 0, 0.83462, 1.0135, 1.25193, 0.83462, 0},
    {0.14024, 0.24739, 0.20874, 0.83462, 0, 0, 0, 0.83462, 0},
    {0.0955, 0.2297, 0.2237, 1.0135, 0, 0, 0, 0.83462, 0},
    {0.3119, 0.36235, 0.55167, 1.25193, 0, 0, 0, 0.83462, 0},
    {0.83462, 0.83462, 0.83462, 0.83462, 0.83462, 0.83462, 0.83462, 0.83462, 0},
    {0, 0, 0, 0, 0, 0, 0, 0, 0},
};

// Note the one asymmetric cell: (Default, PlasticsWhite) = 0 while (PlasticsWhite, Default) = 1.237. The
// original never filled it; we keep it so that runs match the original.
constexpr Matrix kDynamicFriction = {
    {0.09548, 0.07363, 0.239, 0, 0.15516, 0.1343, 0.297, 1.237, 0},
    {0.07363, 0, 0.4183, 0, 0.25034, 0.215, 0.3004, 1.237, 0},
    {0.239, 0.4183, 0.5677, 0, 0.20874, 0.2058, 0.47116, 1.237, 0},
    {0, 0, 0, 0, 0.83462, 1.1923, 1.237, 1.237, 0},
    {0.15516, 0.25034, 0.20874, 0.83462, 0, 0, 0, 1.237, 0},
    {0.1343, 0.215, 0.2058, 1.1923, 0, 0, 0, 1.237, 0},
    {0.297, 0.3004, 0.47116, 1.237, 0, 0, 0, 1.237, 0},
    {0, 1.237, 1.237, 1.237, 1.237, 1.237, 1.237, 1.237, 0},
    {0, 0, 0, 0, 0, 0, 0, 0, 0},
};

constexpr Matrix kRestitution = {
    {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1},
    {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1},
    {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1},
    {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1},
    {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.5, 0.1},
    {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.5, 0.1},
    {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1},
    {0.1, 0.1, 0.1, 0.1, 0.5, 0.5, 0.1, 0.1, 0.1},
    {0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1, 0.1},
};

constexpr char ToLower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// ASCII-only comparison: material names are ASCII, and this avoids the locale.
constexpr bool EqualsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (ToLower(a[i]) != ToLower(b[i])) return false;
  }
  return true;
}

constexpr bool InTable(int index) { return index >= 0 && index < kTableSize; }

ContactMaterial FromCustom(const CustomMaterial& custom) {
  return {custom.static_friction, custom.dynamic_friction, custom.restitution};
}

}  // namespace

int MaterialTable::IndexOf(std::string_view name) {
  for (int i = 0; i < kCount; ++i) {
    if (EqualsIgnoreCase(name, kNames[i])) return i;
  }
  return kUnknown;
}

std::string_view MaterialTable::NameOf(int index) {
  if (index < 0 || index >= kCount) return {};
  return kNames[index];
}

ContactMaterial MaterialTable::Lookup(int first, int second, const BodyFrictionParameters& first_body,
                                      const BodyFrictionParameters& second_body, const CustomMaterial& custom1,
                                      const CustomMaterial& custom2) {
  // Order matters and follows the original: Custom1 wins over Custom2, and both win over an unknown partner.
  if (first == kCustom1 || second == kCustom1) return FromCustom(custom1);
  if (first == kCustom2 || second == kCustom2) return FromCustom(custom2);
  if (!InTable(first) || !InTable(second)) {
    // The spec says the restitution is the sum of the elasticities; the issue tracker decided on the product,
    // which stays within 0..1 for factors within 0..1.
    return {first_body.static_friction + second_body.static_friction,
            first_body.dynamic_friction + second_body.dynamic_friction,
            first_body.elasticity * second_body.elasticity};
  }
  return {kStaticFriction[first][second], kDynamicFriction[first][second], kRestitution[first][second]};
}

}  // namespace orcs::physics
