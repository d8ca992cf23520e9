// orcs-broker: the broker as a program (docs/protocol.md). Prints the endpoints it listens on as one line on
// stdout, logs events on stderr, and serves until SIGINT or SIGTERM; then tells its peers and exits 0.
#include <csignal>
#include <exception>
#include <iostream>
#include <memory>

#include "broker/broker.h"
#include "broker/broker_options.h"

namespace {

orcs::broker::Broker* running_broker = nullptr;

extern "C" void OnSignal(int) {
  if (running_broker != nullptr) running_broker->Stop();  // async-signal-safe: an atomic store and a write()
}

}  // namespace

int main(int argc, char** argv) {
  orcs::broker::ParsedBrokerOptions parsed = orcs::broker::ParseBrokerOptions(argc, argv);
  if (parsed.exit_code >= 0) return parsed.exit_code;
  std::unique_ptr<orcs::broker::Broker> broker;
  try {
    broker = std::make_unique<orcs::broker::Broker>(parsed.options);
  } catch (const std::exception& error) {  // an address that cannot be bound, a port in use: bad input
    std::cerr << "orcs-broker: " << error.what() << "\n";
    return orcs::broker::kExitBadInput;
  }
  running_broker = broker.get();
  struct sigaction action = {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  std::cout << "orcs-broker clients=" << broker->client_endpoint() << " workers=" << broker->worker_endpoint()
            << std::endl;
  try {
    broker->Run();
  } catch (const std::exception& error) {
    std::cerr << "orcs-broker: " << error.what() << "\n";
    return orcs::broker::kExitRunFailed;
  }
  running_broker = nullptr;
  return orcs::broker::kExitOk;
}
