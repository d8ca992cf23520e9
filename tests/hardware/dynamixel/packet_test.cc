#include "hardware/dynamixel/packet.h"

#include <gtest/gtest.h>

namespace orcs::dynamixel {
namespace {

TEST(DynamixelPacketTest, InstructionNamesKnownCodesAndShowsUnknownOnesInHex) {
  EXPECT_EQ(InstructionName(0x01), "ping");
  EXPECT_EQ(InstructionName(0x82), "sync read");
  EXPECT_EQ(InstructionName(0x55), "status");
  EXPECT_EQ(InstructionName(0x42), "instruction 0x42");
}

TEST(DynamixelPacketTest, JoinErrorNamesSaysNoErrorForNoneAndJoinsWithCommas) {
  EXPECT_EQ(JoinErrorNames({}), "no error");
  EXPECT_EQ(JoinErrorNames({"overload"}), "overload");
  EXPECT_EQ(JoinErrorNames({"overload", "overheating"}), "overload, overheating");
}

}  // namespace
}  // namespace orcs::dynamixel
