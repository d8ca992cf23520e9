// orcs-broker: the broker as a program (docs/protocol.md). Prints the endpoints it listens on as one line on
// stdout, logs events on stderr, and serves until SIGINT or SIGTERM; then tells its peers and exits 0.
// `orcs-broker status` asks a running broker what it is doing instead.
#include <cmath>
#include <csignal>
#include <exception>
#include <iostream>
#include <memory>

#include "broker/broker.h"
#include "broker/broker_options.h"
#include "net/status_client.h"
#include "broker/status_text.h"

namespace {

orcs::broker::Broker* running_broker = nullptr;

extern "C" void OnSignal(int) {
  if (running_broker != nullptr) running_broker->Stop();  // async-signal-safe: an atomic store and a write()
}

int PrintStatus(const orcs::broker::StatusCommandOptions& options) {
  try {
    orcs::net::StatusClient client(
        {options.broker, options.curve_keys,
         std::chrono::milliseconds(std::max(1L, std::lround(options.timeout_seconds * 1000.0)))});
    const orcs::v1::Status status = client.Fetch();
    std::cout << (options.json ? orcs::net::StatusJson(status) + "\n"
                               : orcs::broker::StatusText(status, options.broker))
              << std::flush;
    return orcs::broker::kExitOk;
  } catch (const orcs::net::StatusClientError& error) {
    std::cerr << "orcs-broker status: " << error.what() << "\n";
    return orcs::broker::kExitRunFailed;
  } catch (const std::exception& error) {  // an endpoint ZeroMQ cannot parse, a missing key file
    std::cerr << "orcs-broker status: " << error.what() << "\n";
    return orcs::broker::kExitBadInput;
  }
}

}  // namespace

int main(int argc, char** argv) {
  orcs::broker::ParsedBrokerOptions parsed = orcs::broker::ParseBrokerOptions(argc, argv);
  if (parsed.exit_code >= 0) return parsed.exit_code;
  if (parsed.status) return PrintStatus(parsed.status_options);
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
