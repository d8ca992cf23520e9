// The broker's status as people and programs read it: `orcs-broker status` prints StatusText (tables) or
// StatusJson (the Status message in protobuf's JSON mapping, field names as in status.proto).
#pragma once

#include <string>

#include "orcs/v1/status.pb.h"

namespace orcs::broker {

/// A summary line, a table of workers and a table of batches with each batch's recent failures. `endpoint` is
/// the client endpoint the status came from.
std::string StatusText(const v1::Status& status, const std::string& endpoint);

/// One JSON object, every field present (zeros and empty lists too), snake_case names as in status.proto.
std::string StatusJson(const v1::Status& status);

}  // namespace orcs::broker
