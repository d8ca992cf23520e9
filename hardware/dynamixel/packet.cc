#include "hardware/dynamixel/packet.h"

#include <cstdio>

namespace orcs::dynamixel {

DecodeEvent FailedDecode(DecodeOutcome outcome, PacketKind kind, std::uint8_t id, std::size_t length) {
  DecodeEvent event;
  event.outcome = outcome;
  event.packet.kind = kind;
  event.packet.id = id;
  event.length = length;
  return event;
}

std::string InstructionName(std::uint8_t instruction) {
  switch (static_cast<Instruction>(instruction)) {
    case Instruction::kPing: return "ping";
    case Instruction::kRead: return "read";
    case Instruction::kWrite: return "write";
    case Instruction::kRegWrite: return "reg write";
    case Instruction::kAction: return "action";
    case Instruction::kFactoryReset: return "factory reset";
    case Instruction::kReboot: return "reboot";
    case Instruction::kStatus: return "status";
    case Instruction::kSyncRead: return "sync read";
    case Instruction::kSyncWrite: return "sync write";
    case Instruction::kBulkRead: return "bulk read";
  }
  char text[32];
  std::snprintf(text, sizeof text, "instruction 0x%02X", static_cast<unsigned>(instruction));
  return text;
}

std::string JoinErrorNames(const std::vector<std::string_view>& names) {
  if (names.empty()) return "no error";
  std::string text;
  for (const std::string_view name : names) {
    if (!text.empty()) text += ", ";
    text += name;
  }
  return text;
}

}  // namespace orcs::dynamixel
