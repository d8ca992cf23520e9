// The one check both DEALER sides apply to a frame from the broker (docs/protocol.md, "Versions"): it must parse
// as the side's envelope, carry this build's protocol version and have a body; anything else is dropped with a
// reason for the log, e.g. "wrong protocol version 7 (expected 1)".
#pragma once

#include <cstdint>
#include <string>
#include <zmq.hpp>

#include "proto/envelope.h"

namespace orcs::net {

/// Why a frame failed `check`, for a log line: proto::Describe(check), and for a wrong version the version found
/// and this build's ("wrong protocol version 7 (expected 1)"; 0 when the field was missing). "" for
/// EnvelopeCheck::kOk. The broker's log uses the same text.
std::string DescribeRejection(proto::EnvelopeCheck check, std::uint32_t version_found);

/// Parses `frame` into `envelope` (BrokerToClient, BrokerToWorker, ...) and checks it. Returns "" when the
/// envelope may be acted on, else why it must be dropped (DescribeRejection).
template <typename Envelope>
std::string CheckEnvelope(const zmq::message_t& frame, Envelope& envelope) {
  const proto::EnvelopeCheck check = proto::ParseEnvelope(frame.data(), frame.size(), envelope);
  if (check == proto::EnvelopeCheck::kOk) return {};
  return DescribeRejection(check, envelope.protocol_version());
}

}  // namespace orcs::net
