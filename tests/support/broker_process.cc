#include "tests/support/broker_process.h"

#include <chrono>
#include <optional>
#include <regex>

namespace orcs::test_support {

BrokerProcess StartBrokerProcess(const std::vector<std::string>& options) {
  std::vector<std::string> argv = {ORCS_BINARY_DIR "/bin/orcs-broker"};
  argv.insert(argv.end(), options.begin(), options.end());
  BrokerProcess broker;
  broker.process = std::make_unique<BackgroundProcess>(argv);
  const std::optional<std::string> line = broker.process->ReadLine(std::chrono::milliseconds(10000));
  std::smatch match;
  static const std::regex kLine("orcs-broker clients=(\\S+) workers=(\\S+)");
  if (!line || !std::regex_match(*line, match, kLine)) {
    broker.error = "orcs-broker did not print its endpoints (first line: '" + line.value_or("") +
                   "'); stderr: " + broker.process->err();
    return broker;
  }
  broker.clients = match[1];
  broker.workers = match[2];
  return broker;
}

std::string PortOf(const std::string& endpoint) { return endpoint.substr(endpoint.rfind(':') + 1); }

}  // namespace orcs::test_support
