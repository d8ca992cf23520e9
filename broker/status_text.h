// The broker's status as people read it: `orcs-broker status` prints StatusText (tables); `--json` prints
// net::StatusJson (net/status_client.h).
#pragma once

#include <string>

#include "orcs/v1/status.pb.h"

namespace orcs::broker {

/// A summary line, a table of workers and a table of batches with each batch's recent failures. `endpoint` is
/// the client endpoint the status came from.
std::string StatusText(const v1::Status& status, const std::string& endpoint);

}  // namespace orcs::broker
