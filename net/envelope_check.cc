#include "net/envelope_check.h"

namespace orcs::net {

std::string DescribeRejection(proto::EnvelopeCheck check, std::uint32_t version_found) {
  if (check == proto::EnvelopeCheck::kOk) return {};
  std::string why(proto::Describe(check));
  // The version found is what tells an operator which side to upgrade.
  if (check == proto::EnvelopeCheck::kWrongVersion) {
    why += " " + std::to_string(version_found) + " (expected " + std::to_string(proto::kProtocolVersion) + ")";
  }
  return why;
}

}  // namespace orcs::net
