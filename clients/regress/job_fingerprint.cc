#include "clients/regress/job_fingerprint.h"

#include <cstdint>
#include <cstdio>
#include <string_view>

namespace orcs::regress {
namespace {

// FNV-1a, 64 bit: offset basis and prime from the algorithm's definition.
constexpr std::uint64_t kOffsetBasis = 14695981039346656037ULL;
constexpr std::uint64_t kPrime = 1099511628211ULL;

class Fnv1a64 {
 public:
  void AddByte(std::uint8_t byte) {
    hash_ ^= byte;
    hash_ *= kPrime;
  }
  void AddBytes(std::string_view bytes) {
    for (const char c : bytes) AddByte(static_cast<std::uint8_t>(c));
  }
  // Little-endian, 8 bytes.
  void AddNumber(std::uint64_t number) {
    for (int i = 0; i < 8; ++i) AddByte(static_cast<std::uint8_t>(number >> (8 * i)));
  }
  // The length first, so that "ab" + "c" and "a" + "bc" hash differently.
  void AddField(std::string_view text) {
    AddNumber(text.size());
    AddBytes(text);
  }
  std::uint64_t hash() const { return hash_; }

 private:
  std::uint64_t hash_ = kOffsetBasis;
};

}  // namespace

std::string JobFingerprint(const v1::Job& job) {
  Fnv1a64 fnv;
  fnv.AddField(job.scenario_json());
  fnv.AddField(job.genome_json());
  fnv.AddNumber(job.seed());
  fnv.AddNumber(static_cast<std::uint64_t>(job.overrides_size()));
  for (const v1::Override& override : job.overrides()) {
    fnv.AddField(override.path());
    fnv.AddField(override.value());
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(fnv.hash()));
  return std::string("fnv1a64:") + text;
}

}  // namespace orcs::regress
