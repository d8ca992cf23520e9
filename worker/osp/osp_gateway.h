// The gateway orcs-osp serves, as one piece that orcs-osp and orcs-view's OSP-driven live mode (orcs-osp -gui)
// both build: the OSP 1.1 server on a simulation plus one ODCP 1.0 server per agent in the same thread
// (docs/osp.md, "Ports"). The ports come from the options, else from the repository's values as in the original.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "model/scene/simulation.h"
#include "worker/osp/odcp_server.h"
#include "worker/osp/osp_server.h"

namespace orcs::osp {

struct OspGatewayOptions {
  int port = -1;        ///< the OSP server port; -1 = /UDPCommunication/ServerPort; 0 = any free port
  int odcp_port = -1;   ///< the ODCP servers' base port; -1 = /SimpleUdpMotorInterface/ServerPort; 0 = any
  std::string bind_address = "127.0.0.1";  ///< every socket's interface; loopback unless told otherwise
  double client_timeout_seconds = 10.0;    ///< OspServerOptions::client_timeout, s
  /// Where the servers' log lines go (one event each); empty = stderr, prefixed "orcs-osp: ".
  std::function<void(std::string_view)> log;
  std::function<void(double time)> before_step;  ///< OspServerOptions::before_step
  std::function<void()> after_step;              ///< OspServerOptions::after_step
  std::function<void()> after_reset;             ///< OspServerOptions::after_reset
};

class OspGateway {
 public:
  /// Binds every socket for `simulation` (built and reset; it must outlive the gateway). Throws InputError for a
  /// port out of range, in use, or an address that cannot be bound.
  OspGateway(scene::Simulation& simulation, OspGatewayOptions options);
  OspGateway(const OspGateway&) = delete;
  OspGateway& operator=(const OspGateway&) = delete;

  /// What a client needs to find the servers, one line each: "PROGRAM osp=ADDRESS:PORT", then
  /// "PROGRAM odcp AGENT=ADDRESS:PORT" per agent.
  std::vector<std::string> EndpointLines(const std::string& program) const;
  /// Serves `service` in the gateway's thread too (before Run()).
  void AddService(DatagramService* service) { server_->AddService(service); }
  /// Serves until Stop().
  void Run() { server_->Run(); }
  /// Makes Run() return; safe from any thread and from a signal handler.
  void Stop() { server_->Stop(); }
  const OspServer& server() const { return *server_; }

 private:
  std::unique_ptr<OspServer> server_;
  std::vector<std::unique_ptr<AgentMotors>> motors_;  // what each ODCP server drives (outlives it)
  std::vector<std::unique_ptr<OdcpServer>> odcp_;     // by agent index
};

}  // namespace orcs::osp
