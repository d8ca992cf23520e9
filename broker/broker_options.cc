#include "broker/broker_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>

#include "net/cli_style.h"

namespace orcs::broker {

ParsedBrokerOptions ParseBrokerOptions(int argc, const char* const* argv) {
  ParsedBrokerOptions parsed;
  BrokerOptions& o = parsed.options;
  o.client_port = 5555;
  o.worker_port = 5556;
  double heartbeat_seconds = 1.0;
  CLI::App app{"orcs-broker: hands batches of jobs from clients to workers (docs/protocol.md)", "orcs-broker"};
  app.add_option("--bind", o.bind_address,
                 "interface to listen on: an IPv4 address, '*' for all, or an interface name (default 127.0.0.1)");
  app.add_option("--client-port", o.client_port, "TCP port clients connect to; 0 = any free port (default 5555)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--worker-port", o.worker_port, "TCP port workers connect to; 0 = any free port (default 5556)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--heartbeat", heartbeat_seconds, "seconds between heartbeats (default 1)")
      ->check(CLI::Range(0.001, 3600.0));
  app.add_option("--liveness", o.liveness, "heartbeats a peer may miss before it is declared lost (default 5)")
      ->check(CLI::Range(2, 1000));
  app.add_option("--max-worker-losses", o.max_worker_losses,
                 "workers a job may lose before it fails with WORKER_LOST (default 3)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--journal", o.journal,
                 "SQLite file recording jobs, dispatches and results; a broker started again on it resumes "
                 "(default: none, state in memory only)");
  app.add_option("--curve-keys", o.curve_keys,
                 "folder of CURVE keys: encrypt and admit only the allowed keys (docs/security.md); default: off");
  app.add_option("--max-crashes", o.max_crashes,
                 "workers' simulation processes a job may crash before it fails as poisonous with CRASHED (default 3)")
      ->check(CLI::Range(1, 1000));
  app.add_option("--default-time-limit", o.default_time_limit_seconds,
                 "seconds a job without a time limit of its own may take before its lease runs out (default 3600; "
                 "the lease is 1.5 × the limit + 2 s + the liveness period, docs/protocol.md \"Leases\")")
      ->check(CLI::Range(0.001, 1e7));
  double client_grace_seconds = 60.0;
  app.add_option("--client-grace", client_grace_seconds,
                 "seconds a silent client's batches wait for it to come back before they are dropped and their "
                 "running jobs revoked (default 60; docs/protocol.md \"Endings\")")
      ->check(CLI::Range(0.0, 86400.0));
  app.add_option("--max-credit", o.max_credit,
                 "most jobs one worker connection may hold at once, whatever credit it asks for (default 16)")
      ->check(CLI::Range(1, 1024));
  StatusCommandOptions& status = parsed.status_options;
  CLI::App* status_command = app.add_subcommand(
      "status", "ask a running broker what it is doing: workers, batches, queue, jobs/s (docs/protocol.md, \"Status\")");
  status_command->add_option("--broker", status.broker, "the broker's client endpoint (default tcp://127.0.0.1:5555)")
      ->check(cli::Endpoint());
  status_command->add_flag("--json", status.json, "print one JSON object (the Status message of status.proto)");
  status_command->add_option("--curve-keys", status.curve_keys,
                             "folder of this client's CURVE keys (docs/security.md); with CURVE, other keys' "
                             "batches show their counts only");
  status_command->add_option("--timeout", status.timeout_seconds, "seconds to wait for the answer (default 3)")
      ->check(CLI::Range(0.001, 3600.0));
  app.require_subcommand(0, 1);
  try {
    app.parse(argc, argv);
    parsed.status = status_command->parsed();
    if (parsed.status && status.broker.empty()) throw CLI::ValidationError("--broker", "needs an endpoint");
    if (o.bind_address.empty()) throw CLI::ValidationError("--bind", "needs an address");
    if (app.count("--curve-keys") > 0 && o.curve_keys.empty()) {
      throw CLI::ValidationError("--curve-keys", "needs a folder");  // never plain TCP by an empty argument
    }
    if (o.client_port != 0 && o.client_port == o.worker_port) {
      throw CLI::ValidationError("--worker-port", "must differ from --client-port");
    }
    o.heartbeat_interval = std::chrono::milliseconds(std::lround(heartbeat_seconds * 1000.0));
    if (o.heartbeat_interval.count() < 1) o.heartbeat_interval = std::chrono::milliseconds(1);
    o.client_grace = std::chrono::milliseconds(std::llround(client_grace_seconds * 1000.0));
  } catch (const CLI::CallForHelp&) {
    std::cout << app.help();
    parsed.exit_code = kExitOk;
  } catch (const CLI::ParseError& error) {
    std::cerr << "orcs-broker: " << error.what() << " (see orcs-broker --help)\n";
    parsed.exit_code = kExitBadInput;
  }
  return parsed;
}

}  // namespace orcs::broker
