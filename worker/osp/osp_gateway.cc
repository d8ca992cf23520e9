#include "worker/osp/osp_gateway.h"

#include <cmath>
#include <stdexcept>

#include "model/core/error.h"
#include "worker/osp/protocol_values.h"

namespace orcs::osp {
namespace {

// The port of an option, or of its repository value when the option was not given; InputError when out of range.
int PortOf(int option, const VariableRepository& repository, std::string_view path) {
  const std::int64_t port = option >= 0 ? option : repository.Get(path).as_int();
  if (port < 0 || port > 65535) {
    throw InputError(std::string(path), 0, "expected a port 0..65535, found " + std::to_string(port));
  }
  return static_cast<int>(port);
}

}  // namespace

OspGateway::OspGateway(scene::Simulation& simulation, OspGatewayOptions options) {
  OspServerOptions server_options;
  server_options.bind_address = options.bind_address;
  server_options.port = static_cast<std::uint16_t>(PortOf(options.port, simulation.repository(), kOspServerPortPath));
  server_options.client_timeout = std::chrono::milliseconds(std::lround(options.client_timeout_seconds * 1000.0));
  server_options.log = options.log;
  server_options.before_step = std::move(options.before_step);
  server_options.after_step = std::move(options.after_step);
  server_options.after_reset = std::move(options.after_reset);
  try {
    server_ = std::make_unique<OspServer>(simulation, server_options);
  } catch (const std::runtime_error& error) {  // a port in use, an address that cannot be bound: bad input
    throw InputError(error.what());
  }
  const int base = PortOf(options.odcp_port, simulation.repository(), kOdcpServerPortPath);
  try {
    const std::vector<std::uint16_t> ports = OdcpPorts(base, simulation.agent_count(), server_->endpoint().port);
    for (int a = 0; a < simulation.agent_count(); ++a) {
      motors_.push_back(std::make_unique<AgentMotors>(MakeAgentInterface(simulation, a),
                                                      simulation.repository().Find(kOdcpReportGoalAnglesPath)));
      OdcpServerOptions odcp_options;
      odcp_options.bind_address = options.bind_address;
      odcp_options.port = ports[static_cast<std::size_t>(a)];
      odcp_options.name = "orcs-osp: ODCP " + motors_.back()->name();
      odcp_.push_back(std::make_unique<OdcpServer>(*motors_.back(), odcp_options));
      server_->AddService(odcp_.back().get());
    }
  } catch (const std::runtime_error& error) {  // a port in use or beyond 65535: bad input
    throw InputError(std::string("-odcp_port: ") + error.what());
  }
}

std::vector<std::string> OspGateway::EndpointLines(const std::string& program) const {
  std::vector<std::string> lines = {program + " osp=" + server_->endpoint().ToString()};
  for (std::size_t a = 0; a < odcp_.size(); ++a) {
    lines.push_back(program + " odcp " + motors_[a]->name() + "=" + odcp_[a]->endpoint().ToString());
  }
  return lines;
}

}  // namespace orcs::osp
