// OspServer driven without polling (OspServer::Deliver), on the default A-Series world; the protocol over real
// sockets is tested in tests/integration/osp_gateway_test.cc.
#include "worker/osp/osp_server.h"

#include <gtest/gtest.h>

#include "model/scene/environment_reader.h"
#include "worker/osp/osp_protocol.h"

namespace orcs::osp {
namespace {

Datagram Init(std::uint16_t port) {
  Datagram datagram;
  datagram.bytes = {kInit, kMajorVersion, kMinorVersion};
  datagram.from = {0x7f000001, port};
  return datagram;
}

// Found by the fuzzer: every INIT opened a socket, so a flood of them used up the process's files and the next
// one threw out of Run(), ending the gateway. Now INITs beyond max_clients are ignored and the server goes on.
TEST(OspServerTest, InitsBeyondMaxClientsAreIgnored) {
  scene::Simulation simulation;
  simulation.LoadEnvironment(
      scene::EnvironmentReader::ReadString(R"(<ORCS version="1.0" defaultRobot="false"><Agent><ASeries name="A"/></Agent></ORCS>)", "t"));
  simulation.Build();
  OspServerOptions options;
  options.port = 0;
  options.max_clients = 2;
  options.log = [](std::string_view) {};
  OspServer server(simulation, options);
  for (std::uint16_t i = 0; i < 5; ++i) server.Deliver(0, Init(static_cast<std::uint16_t>(40000 + i)));
  EXPECT_EQ(server.stats().clients, 2);
  EXPECT_EQ(server.stats().datagrams_ignored, 3u);
  Datagram end;
  end.bytes = {kEnd};
  end.from = {0x7f000001, 40000};
  server.Deliver(1, end);  // a client leaves: room for one more
  server.Deliver(0, Init(40010));
  EXPECT_EQ(server.stats().clients, 2);
  EXPECT_EQ(server.stats().datagrams_ignored, 3u);
}

}  // namespace
}  // namespace orcs::osp
