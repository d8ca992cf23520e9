// A real orcs-broker in the background, for tests of whole programs: started with the given options, and the
// client and worker endpoints it printed on its first line.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "tests/support/background_process.h"

namespace orcs::test_support {

/// A running orcs-broker, or why it is not running.
struct BrokerProcess {
  std::unique_ptr<BackgroundProcess> process;  ///< null when it did not start
  std::string clients;                         ///< its client endpoint, e.g. "tcp://127.0.0.1:5555"
  std::string workers;                         ///< its worker endpoint
  std::string error;                           ///< "" when it started; else what went wrong, with its stderr
};

/// Starts `ORCS_BINARY_DIR/bin/orcs-broker options...` and waits (10 s at most) for its endpoints line.
BrokerProcess StartBrokerProcess(const std::vector<std::string>& options);

/// The port of an endpoint: "5556" of "tcp://127.0.0.1:5556".
std::string PortOf(const std::string& endpoint);

}  // namespace orcs::test_support
