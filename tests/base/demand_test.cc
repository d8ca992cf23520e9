// The always-on invariant check fires in the build users run: the default build type (RelWithDebInfo) defines NDEBUG,
// which switched assert() off, so each test here would pass with assert() only in a debug build.
#include "base/demand.h"

#include <gtest/gtest.h>

#include "model/scene/simulation.h"

namespace orcs {
namespace {

TEST(DemandDeathTest, AFalseInvariantAbortsNamingItsConditionAndPlace) {
  const int parameter_sets = 0;
  EXPECT_DEATH(ORCS_DEMAND(parameter_sets > 0), "orcs: internal invariant failed: parameter_sets > 0 at .*demand_test\\.cc:[0-9]+");
  EXPECT_DEATH(ORCS_DEMAND_MSG(parameter_sets > 0, "one per set"), "parameter_sets > 0 \\(one per set\\)");
  EXPECT_DEATH(ORCS_UNREACHABLE("a kind refused earlier"), "unreachable \\(a kind refused earlier\\)");
}

TEST(DemandDeathTest, ATrueInvariantCostsNothingAndSaysNothing) {
  int evaluated = 0;
  ORCS_DEMAND(++evaluated == 1);  // the condition runs exactly once
  EXPECT_EQ(evaluated, 1);
}

// A shipped invariant of the simulation, in this (release) build: stepping a world never built is a bug in the
// caller, and it stops there instead of stepping garbage.
TEST(DemandDeathTest, TheSimulationsOwnInvariantsFireInTheReleaseBuild) {
#ifdef NDEBUG
  SCOPED_TRACE("built with NDEBUG: assert() would be off here");
#endif
  EXPECT_DEATH(
      {
        scene::Simulation simulation;
        simulation.Step();
      },
      "internal invariant failed: built\\(\\) \\(Step\\(\\) before Build\\(\\)\\)");
}

}  // namespace
}  // namespace orcs
