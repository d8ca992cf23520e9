// The repository values of the original's UDP interfaces (spec/osp.md, docs/osp.md): their ports and the two
// switches between the original's behaviour (the default) and the successor's. Registered before a value file
// is read, so that -val and -ival can set them as they could in the original.
#pragma once

#include <string_view>

#include "model/core/variable_repository.h"

namespace orcs::osp {

/// OSP's server port, 45454 (-port overrides it).
inline constexpr std::string_view kOspServerPortPath = "/UDPCommunication/ServerPort";
/// true (default, the original): the step reply 85 carries the client's observed values (54); false (the
/// successor): its value count is 0 and clients read values with 50.
inline constexpr std::string_view kObservedValuesInStepReplyPath = "/UDPCommunication/ObservedValuesInStepReply";
/// ODCP's base port, 45453 (-odcp_port overrides it).
inline constexpr std::string_view kOdcpServerPortPath = "/SimpleUdpMotorInterface/ServerPort";
/// false (default, the original): get-motors (150) reports each motor's angle sensor; true (the successor): the
/// goal angle last set.
inline constexpr std::string_view kOdcpReportGoalAnglesPath = "/SimpleUdpMotorInterface/ReportGoalAngles";

/// Adds the four values with their defaults, keeping any that exist already.
void AddProtocolValues(VariableRepository& repository);

/// The switch at `path` (one of the above), or `otherwise` when it is not in the repository.
bool ProtocolSwitch(const VariableRepository& repository, std::string_view path, bool otherwise);

}  // namespace orcs::osp
