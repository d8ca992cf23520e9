#include "proto/envelope.h"

namespace orcs::proto {

std::string_view Describe(EnvelopeCheck check) {
  switch (check) {
    case EnvelopeCheck::kOk: return "ok";
    case EnvelopeCheck::kUnparsable: return "not a protocol message (failed to parse)";
    case EnvelopeCheck::kWrongVersion: return "wrong protocol version";
    case EnvelopeCheck::kNoBody: return "message without a body";
  }
  return "?";
}

}  // namespace orcs::proto
