// Contact friction and restitution between materials: the original's tables (spec/aseries.md §7).
#pragma once

#include <array>
#include <string>
#include <string_view>

namespace orcs::physics {

/// Friction and restitution of one contact pair.
struct ContactMaterial {
  double static_friction = 0.0;   ///< Coulomb coefficient while not sliding, -
  double dynamic_friction = 0.0;  ///< Coulomb coefficient while sliding, - (before FrictionScaling)
  double restitution = 0.0;       ///< ODE bounce factor, 0..1
};

/// The run-time values of the two user materials (repository /MaterialProperties/Custom1|2/...).
struct CustomMaterial {
  double static_friction = 1.2;   ///< /MaterialProperties/CustomN/StateFriction [sic], -
  double dynamic_friction = 0.8;  ///< /MaterialProperties/CustomN/DynamicFriction, -
  double restitution = 0.1;       ///< /MaterialProperties/CustomN/Restitution, -
};

/// Fallback parameters of a body, used when a material is unknown.
struct BodyFrictionParameters {
  double static_friction = 0.0;   ///< -
  double dynamic_friction = 0.0;  ///< -
  double elasticity = 0.05;       ///< -
};

/// The material table. Indices follow the original: 0 PlasticsWhite, 1 PlasticsGray, 2 ABS, 3 Latex, 4 PVC,
/// 5 Wood, 6 Carpet, 7 Default, 8 Light, 9 Custom1, 10 Custom2; -1 means unknown.
class MaterialTable {
 public:
  static constexpr int kCount = 11;
  static constexpr int kUnknown = -1;
  static constexpr int kCustom1 = 9;
  static constexpr int kCustom2 = 10;

  /// Index of a material name (case-insensitive), or kUnknown.
  static int IndexOf(std::string_view name);
  /// Canonical name of an index ("ABS"); "" for kUnknown.
  static std::string_view NameOf(int index);

  /// Properties of the pair (first, second) in the order the collision routine reports them; the tables are
  /// stored as the original had them (row = first), including its one asymmetric cell (Default × PlasticsWhite).
  /// Rules, in order: Custom1 in the pair → custom1; else Custom2 → custom2; else either unknown → fallback
  /// (static = sum of the bodies' static friction, dynamic = sum of their dynamic friction, restitution =
  /// product of their elasticities); else the table cells.
  static ContactMaterial Lookup(int first, int second, const BodyFrictionParameters& first_body,
                                const BodyFrictionParameters& second_body, const CustomMaterial& custom1,
                                const CustomMaterial& custom2);
};

}  // namespace orcs::physics
