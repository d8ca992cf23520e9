// Seeded random streams. A stream is derived from (seed, purpose, index) alone — never from time, never from
// a global generator — so the same job draws the same numbers on any machine, in any order, at any worker
// count (docs/architecture.md, "Determinism"). Every distribution is computed here from raw 64-bit draws, because the
// standard library's distributions differ between implementations.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace orcs {

class RandomStream {
 public:
  /// A stream for one purpose ("sensor-noise", "parameter-set") and one index (agent, set, motor) of a seed.
  /// Different (seed, purpose, index) triples give independent streams.
  RandomStream(std::uint64_t seed, std::string_view purpose, std::uint64_t index = 0);

  /// Next raw 64-bit draw (xoshiro256**).
  std::uint64_t NextU64();
  /// Uniform in [0, 1), 53 bits.
  double Uniform();
  /// Uniform in [low, high).
  double Uniform(double low, double high) { return low + (high - low) * Uniform(); }
  /// Uniform integer in [0, n), n > 0, without modulo bias.
  std::uint64_t UniformInt(std::uint64_t n);
  /// Normal with the given mean and standard deviation (Marsaglia's polar method).
  double Normal(double mean = 0.0, double deviation = 1.0);

 private:
  std::array<std::uint64_t, 4> state_{};
  double spare_normal_ = 0.0;
  bool has_spare_normal_ = false;
};

}  // namespace orcs
