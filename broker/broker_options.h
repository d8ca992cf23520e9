// The command line of orcs-broker (docs/protocol.md, "Running a broker").
#pragma once

#include <string>

#include "broker/broker.h"

namespace orcs::broker {

/// Exit codes, the same as every orcs program's (net/cli_style.h; broker/ may not include worker/).
constexpr int kExitOk = 0;
constexpr int kExitRunFailed = 1;  ///< the broker failed while running
constexpr int kExitBadInput = 2;   ///< bad option, address that cannot be bound, port in use

/// `orcs-broker status`: ask a running broker what it is doing (docs/protocol.md, "Status").
struct StatusCommandOptions {
  std::string broker = "tcp://127.0.0.1:5555";  ///< the broker's client endpoint
  bool json = false;                            ///< print the Status message as JSON instead of tables
  std::string curve_keys;                       ///< folder of the client's CURVE keys; "" = plain TCP
  double timeout_seconds = 3.0;                 ///< how long to wait for the answer
};

/// The result of parsing orcs-broker's command line.
struct ParsedBrokerOptions {
  BrokerOptions options;  ///< what to run with; ports default to 5555 (clients) and 5556 (workers)
  bool status = false;    ///< the `status` subcommand was given: ask, do not serve
  StatusCommandOptions status_options;  ///< its options
  int exit_code = -1;     ///< >= 0: exit now with this code (help printed, or a bad option reported)
};

/// Parses argv; on --help prints the help and asks to exit 0; on a bad option prints one line to stderr and asks
/// to exit 2.
ParsedBrokerOptions ParseBrokerOptions(int argc, const char* const* argv);

}  // namespace orcs::broker
