#include "worker/osp/protocol_values.h"

namespace orcs::osp {

void AddProtocolValues(VariableRepository& repository) {
  if (repository.Find(kOspServerPortPath) == nullptr) repository.Add(kOspServerPortPath, 45454);
  if (repository.Find(kObservedValuesInStepReplyPath) == nullptr) repository.Add(kObservedValuesInStepReplyPath, true);
  if (repository.Find(kOdcpServerPortPath) == nullptr) repository.Add(kOdcpServerPortPath, 45453);
  if (repository.Find(kOdcpReportGoalAnglesPath) == nullptr) repository.Add(kOdcpReportGoalAnglesPath, false);
}

bool ProtocolSwitch(const VariableRepository& repository, std::string_view path, bool otherwise) {
  const Value* value = repository.Find(path);
  return value == nullptr ? otherwise : value->as_bool();
}

}  // namespace orcs::osp
