// The bus driver against the servo-bus emulator, through a real pseudo-terminal: discovery, reads and writes, sync
// read/write in both protocols, and the faults a real bus has — a garbled answer, a silent servo, an alarm.
#include "hardware/dynamixel/dynamixel_bus.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>

#include "hardware/emulator/servo_bus_emulator.h"
#include "hardware/serial/serial_link.h"

namespace orcs::dynamixel {
namespace {

using hardware::EmulatorOptions;
using hardware::ServoBusEmulator;
using ::testing::ElementsAre;
using ::testing::HasSubstr;

DynamixelBus BusOn(const ServoBusEmulator& emulator, Protocol protocol, int retries = 2) {
  BusOptions options;
  options.protocol = protocol;
  options.timeout = std::chrono::milliseconds(250);  // generous: a loaded CI machine may be slow to schedule the
                                                     // emulator, and a late answer would count as a timeout
  options.retries = retries;
  return DynamixelBus(hardware::OpenSerialLink(emulator.port(), 1000000), options);
}

TEST(DynamixelBusTest, TheEmulatorsPortIsAPseudoTerminal) {
  ServoBusEmulator emulator(hardware::KinematicBus(kAx12, {1}, 684.0));
  EXPECT_TRUE(hardware::IsPseudoTerminal(emulator.port()));
  EXPECT_FALSE(hardware::IsPseudoTerminal("/dev/null"));
}

TEST(DynamixelBusTest, DiscoveryFindsExactlyTheServosOnTheBus) {
  ServoBusEmulator emulator(hardware::KinematicBus(kAx12, {1, 4, 7}, 684.0));
  DynamixelBus bus = BusOn(emulator, Protocol::kV1);
  EXPECT_THAT(bus.Discover(0, 8), ElementsAre(1, 4, 7));
  EXPECT_TRUE(bus.Ping(4));
  EXPECT_FALSE(bus.Ping(5));
  EXPECT_EQ(bus.counts().timeouts, 6u + 3u) << "6 empty ids of 0…8 asked once each, then id 5 three times";
}

TEST(DynamixelBusTest, AWrittenGoalMovesTheShaftAndReadsBackAsThePresentPosition) {
  ServoBusEmulator emulator(hardware::KinematicBus(kAx12, {3}, 684.0));
  DynamixelBus bus = BusOn(emulator, Protocol::kV1);
  EXPECT_THAT(bus.Read(3, 0, 2), ElementsAre(12, 0)) << "the AX-12's model number";
  bus.Write(3, kAx12.torque_enable, std::vector<std::uint8_t>{1});
  bus.Write(3, kAx12.goal_position, LittleEndian(512 + 100, 2));  // +29.3°
  std::int64_t present = 0;
  // The shaft needs about 45 ms at 684 °/s: the reads await it, bounded by a deadline far beyond that.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (present != 612 && std::chrono::steady_clock::now() < deadline) {
    present = FromLittleEndian(bus.Read(3, kAx12.present_position, 2));
  }
  EXPECT_EQ(present, 612);
  EXPECT_NEAR(emulator.Angle(3), 100 * kAx12.degrees_per_tick, kAx12.degrees_per_tick / 2) << "within the tick read";
}

TEST(DynamixelBusTest, SyncWriteReachesEveryServoInOnePacket) {
  ServoBusEmulator emulator(hardware::KinematicBus(kAx12, {1, 2, 3}, 684.0));
  DynamixelBus bus = BusOn(emulator, Protocol::kV1);
  const std::vector<SyncWriteEntry> goals{{1, LittleEndian(500, 2)}, {2, LittleEndian(510, 2)}, {3, LittleEndian(520, 2)}};
  bus.SyncWrite(kAx12.goal_position, 2, goals);
  const auto values = bus.SyncRead(std::vector<std::uint8_t>{1, 2, 3}, kAx12.goal_position, 2);
  ASSERT_EQ(values.size(), 3u);
  EXPECT_EQ(FromLittleEndian(values[0]), 500);
  EXPECT_EQ(FromLittleEndian(values[1]), 510);
  EXPECT_EQ(FromLittleEndian(values[2]), 520);
  EXPECT_EQ(bus.counts().instructions, 4u) << "one SYNC_WRITE, then a READ per servo (the AX-12 has no SYNC_READ)";
}

TEST(DynamixelBusTest, Protocol2SyncReadAnswersEveryServoFromOneInstruction) {
  ServoBusEmulator emulator(hardware::KinematicBus(kXl330, {1, 2}, 600.0));
  DynamixelBus bus = BusOn(emulator, Protocol::kV2);
  EXPECT_THAT(bus.Discover(0, 3), ElementsAre(1, 2));
  const std::vector<SyncWriteEntry> goals{{1, LittleEndian(2100, 4)}, {2, LittleEndian(1900, 4)}};
  bus.SyncWrite(kXl330.goal_position, 4, goals);
  const std::size_t before = bus.counts().instructions;
  const auto values = bus.SyncRead(std::vector<std::uint8_t>{1, 2}, kXl330.goal_position, 4);
  EXPECT_EQ(bus.counts().instructions, before + 1);
  ASSERT_EQ(values.size(), 2u);
  EXPECT_EQ(FromLittleEndian(values[0]), 2100);
  EXPECT_EQ(FromLittleEndian(values[1]), 1900);
}

TEST(DynamixelBusTest, AGarbledAnswerIsCountedAndAskedAgain) {
  for (const auto& table : {kAx12, kXl330}) {
    ServoBusEmulator emulator(hardware::KinematicBus(table, {7}, 600.0));
    DynamixelBus bus = BusOn(emulator, table.protocol);
    emulator.CorruptAnswers(7, 2);
    EXPECT_EQ(FromLittleEndian(bus.Read(7, 0, 2)), table.model_number) << table.name;
    EXPECT_EQ(bus.counts().checksum_errors, 2u) << table.name;
    EXPECT_EQ(bus.counts().retries, 2u) << table.name;
    emulator.CorruptAnswers(7, 3);
    EXPECT_THROW(bus.Read(7, 0, 2), BusError) << table.name << ": three garbled answers exhaust two retries";
    EXPECT_EQ(bus.counts().checksum_errors, 5u) << table.name;
  }
}

TEST(DynamixelBusTest, ASilentServoTimesOutAfterItsRetriesWithAMessageThatSuggestsTheFix) {
  ServoBusEmulator emulator(hardware::KinematicBus(kAx12, {9}, 684.0));
  DynamixelBus bus = BusOn(emulator, Protocol::kV1, 1);
  emulator.Silence(9, true);
  try {
    bus.Read(9, kAx12.present_position, 2);
    FAIL() << "a silent servo must not read";
  } catch (const BusError& e) {
    EXPECT_THAT(e.what(), HasSubstr("servo 9 gave no intact answer"));
    EXPECT_THAT(e.what(), HasSubstr("2 tries"));
    EXPECT_THAT(e.what(), HasSubstr("baud rate"));
  }
  EXPECT_EQ(bus.counts().timeouts, 2u);
  emulator.Silence(9, false);
  EXPECT_TRUE(bus.Ping(9)) << "the bus recovers once the servo answers";
}

TEST(DynamixelBusTest, AServoAlarmIsRaisedByName) {
  ServoBusEmulator emulator(hardware::KinematicBus(kAx12, {2}, 684.0));
  DynamixelBus bus = BusOn(emulator, Protocol::kV1);
  emulator.RaiseAlarm(2, protocol1::kOverloadError | protocol1::kOverheatingError);
  try {
    bus.Read(2, kAx12.present_position, 2);
    FAIL() << "an alarm must not pass for a reading";
  } catch (const ServoAlarm& alarm) {
    EXPECT_EQ(alarm.id(), 2);
    EXPECT_THAT(alarm.what(), HasSubstr("servo 2 reports"));
    EXPECT_THAT(alarm.what(), HasSubstr("overload"));
    EXPECT_THAT(alarm.what(), HasSubstr("overheating"));
  }
  EXPECT_EQ(bus.counts().alarms, 1u);
  EXPECT_EQ(bus.counts().retries, 0u) << "an alarm is an answer: not asked again";
}

}  // namespace
}  // namespace orcs::dynamixel
