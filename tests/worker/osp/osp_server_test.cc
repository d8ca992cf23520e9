// OspServer driven without polling (OspServer::Deliver), on the default A-Series world; the protocol over real
// sockets is tested in tests/integration/osp_gateway_test.cc.
#include "worker/osp/osp_server.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

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

// Issue 47, item 5: every bad datagram on the server port was a line on stderr (100,000 one-byte datagrams: 6.9 MB
// in a second). Now the first from each sender address is logged (64 senders at most), the rest counted, and one
// line per interval gives the count — as the handler ports log once per client.
TEST(OspServerTest, TheServerPortLogsOncePerSenderAndCountsTheRest) {
  scene::Simulation simulation;
  simulation.LoadEnvironment(
      scene::EnvironmentReader::ReadString(R"(<ORCS version="1.0" defaultRobot="false"><Agent><ASeries name="A"/></Agent></ORCS>)", "t"));
  simulation.Build();
  std::vector<std::string> lines;
  OspServerOptions options;
  options.port = 0;
  options.server_log_summary_interval = std::chrono::hours(1);  // no count line within the test...
  options.log = [&](std::string_view line) { lines.emplace_back(line); };
  {
    OspServer server(simulation, options);
    auto garbage = [](std::uint16_t port) {
      Datagram datagram;
      datagram.bytes = {0x42};
      datagram.from = {0x7f000001, port};
      return datagram;
    };
    for (int i = 0; i < 100000; ++i) server.Deliver(0, garbage(50000));
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(lines[0], "ignored a datagram on the server port that is not INIT 1.1, from 127.0.0.1:50000 (further "
                        "ignored datagrams from it are counted, not logged)");
    // 1,000 senders: the first 64 are named, one line each.
    for (std::uint16_t port = 1; port <= 1000; ++port) server.Deliver(0, garbage(port));
    EXPECT_EQ(lines.size(), 64u);
    EXPECT_EQ(server.stats().datagrams_ignored, 101000u);
    // A good client is served all the same.
    server.Deliver(0, Init(40000));
    EXPECT_EQ(server.stats().clients, 1);
  }
  // ... but at the end (Run() returning) and with a short interval, the count is given.
  lines.clear();
  options.server_log_summary_interval = std::chrono::milliseconds(0);
  OspServer server(simulation, options);
  Datagram empty;
  empty.from = {0x7f000001, 50001};
  server.Deliver(0, empty);  // logged: the first from this sender
  server.Deliver(0, empty);  // counted, and the count is due at once
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(lines[0].find("from 127.0.0.1:50001 (further ignored datagrams from it are counted, not logged)"),
            std::string::npos) << lines[0];
  EXPECT_EQ(lines[1].rfind("ignored 1 more datagram(s) on the server port in the last ", 0), 0u) << lines[1];
  EXPECT_NE(lines[1].find(" s, from 1 sender(s) (the first from each of the first 64 senders is logged)"),
            std::string::npos) << lines[1];
}

}  // namespace
}  // namespace orcs::osp
