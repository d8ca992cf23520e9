// The ODE 0.16 (double precision) backend of PhysicsWorld.
#pragma once

#include <memory>

#include "model/physics/physics_world.h"

namespace orcs::physics {

/// Creates an ODE world for `model`. ODE is initialised once per process and once per thread on first use;
/// ODE's error and debug handlers are replaced so that an engine error becomes StepStatus::kEngineError of
/// the run that caused it instead of aborting the process.
std::unique_ptr<PhysicsWorld> MakeOdeWorld(std::shared_ptr<const PhysicsModel> model);

}  // namespace orcs::physics
