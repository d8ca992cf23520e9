// FNV-1a, 64 bit: a small, stable, non-cryptographic hash for detecting that inputs changed (a regression case's
// job, the scenario an evolution checkpoint was made for). Stable across machines and builds: byte streams only.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace orcs {

class Fnv1a64 {
 public:
  void AddByte(std::uint8_t byte) {
    hash_ ^= byte;
    hash_ *= kPrime;
  }
  void AddBytes(std::string_view bytes) {
    for (const char c : bytes) AddByte(static_cast<std::uint8_t>(c));
  }
  /// Little-endian, 8 bytes.
  void AddNumber(std::uint64_t number) {
    for (int i = 0; i < 8; ++i) AddByte(static_cast<std::uint8_t>(number >> (8 * i)));
  }
  /// The length first, so that "ab" + "c" and "a" + "bc" hash differently.
  void AddField(std::string_view text) {
    AddNumber(text.size());
    AddBytes(text);
  }
  std::uint64_t hash() const { return hash_; }
  /// The hash as 16 lower-case hex digits.
  std::string Hex() const {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash_));
    return text;
  }

 private:
  // Offset basis and prime from the algorithm's definition.
  static constexpr std::uint64_t kOffsetBasis = 14695981039346656037ULL;
  static constexpr std::uint64_t kPrime = 1099511628211ULL;
  std::uint64_t hash_ = kOffsetBasis;
};

}  // namespace orcs
