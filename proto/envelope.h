// The protocol version and the check every receiver applies to an incoming envelope (docs/protocol.md):
// a message that fails to parse, carries another version or has no body is dropped, never acted on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace orcs::proto {

/// The wire protocol version this build speaks; every envelope, job and result carries it.
inline constexpr std::uint32_t kProtocolVersion = 1;

/// Why an incoming envelope was (or was not) accepted.
enum class EnvelopeCheck {
  kOk,            ///< parsed, right version, has a body
  kUnparsable,    ///< not a serialised envelope (garbage, truncated)
  kWrongVersion,  ///< parsed, but protocol_version is not kProtocolVersion (0 when missing)
  kNoBody,        ///< parsed, right version, but none of the body fields is set
};

/// One line describing `check` for a log, e.g. "wrong protocol version 7 (expected 1)".
std::string_view Describe(EnvelopeCheck check);

/// Parses `size` bytes at `data` into `envelope` (any of the four envelope messages of broker.proto) and checks
/// its version and body.
template <typename Envelope>
EnvelopeCheck ParseEnvelope(const void* data, std::size_t size, Envelope& envelope) {
  if (size > static_cast<std::size_t>(INT32_MAX) || !envelope.ParseFromArray(data, static_cast<int>(size))) {
    return EnvelopeCheck::kUnparsable;
  }
  if (envelope.protocol_version() != kProtocolVersion) return EnvelopeCheck::kWrongVersion;
  if (envelope.body_case() == Envelope::BODY_NOT_SET) return EnvelopeCheck::kNoBody;
  return EnvelopeCheck::kOk;
}

}  // namespace orcs::proto
