// A robot's morphology as repository values (docs/model.md, "The robot's values"): every body's and extra geom's
// mass, size, material and colour and every motor's hinge stops, under the agent, so that value files, scenarios,
// sweeps, randomised parameter sets, OSP and the viewer can change the robot as they change a box.
//
// Paths, for agent A (e.g. "Humanoid"), body B (e.g. "Right/Foot"), extra geom G of B (its name in CamelCase,
// e.g. "RightSolePadHeel") and motor M (e.g. "Right/Knee"):
//   /Sim/A/B/Mass                    double, kg, the main box's mass (extra geoms and boards add theirs)
//   /Sim/A/B/Width, Height, Depth    double, m, the main box's edge lengths along the body's x, y, z
//   /Sim/A/B/Material                string, a material of the material table ("ABS", "Latex", ...)
//   /Sim/A/B/Color                   colour, display only
//   /Sim/A/B/G/Mass, Width, Height, Depth, Material, Color   the same for an extra geom
//   /Sim/A/M/MinAngle, MaxAngle      double, degrees, the hinge stops relative to the initial pose
// They are structure values: read when the world is compiled, so a change applies at the next reset
// (scene::Simulation recompiles the world then). A size resizes the box about its centre; the joints stay where
// they are (a different skeleton is a different robot file).
#pragma once

#include <string>
#include <vector>

#include "model/aseries/aseries_morphology.h"
#include "model/core/variable_repository.h"

namespace orcs::aseries {

/// The extra geom's path segment: its name's words joined in CamelCase ("Right sole pad heel" → "RightSolePadHeel").
std::string GeomValueName(const std::string& geom_name);

/// Registers agent `agent`'s morphology values with `morphology`'s numbers as their initial values (a path that
/// exists keeps its value, as every registration does). Ranges refuse what cannot be built where it is written:
/// masses and sizes must be positive and finite, materials must be the table's.
void AddMorphologyValues(const ASeriesMorphology& morphology, const std::string& agent, VariableRepository& values);

/// The paths AddMorphologyValues registers, in registration order.
std::vector<std::string> MorphologyValuePaths(const ASeriesMorphology& morphology, const std::string& agent);

/// `morphology` with agent `agent`'s values from `values` applied. Throws InputError naming the path for a hinge
/// whose MinAngle exceeds its MaxAngle.
ASeriesMorphology ApplyMorphologyValues(const ASeriesMorphology& morphology, const std::string& agent,
                                        const VariableRepository& values);

}  // namespace orcs::aseries
