// Unpredictable bytes from the operating system (getrandom(2)), for secrets on the wire: lease tokens, batch
// ids, batch owner tokens, the viewer's control token. Never for simulations: those draw from seeded streams
// (model/core/random_stream.h), so that the same job gives the same bits anywhere.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace orcs::proto {

/// `count` random bytes from the OS. Throws std::runtime_error when the OS cannot supply them.
std::string SecureRandomBytes(std::size_t count);

/// `bytes` random bytes as lower-case hex (2 × bytes characters).
std::string SecureRandomHex(std::size_t bytes);

/// A random 64-bit number, never 0 (0 means "none" in the protocol's token fields).
std::uint64_t SecureRandomToken();

}  // namespace orcs::proto
