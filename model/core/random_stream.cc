#include "model/core/random_stream.h"

#include <cmath>

namespace orcs {
namespace {

// SplitMix64: turns a 64-bit key into well-mixed state words (the seeding xoshiro's authors recommend).
std::uint64_t SplitMix64(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// FNV-1a: a fixed, portable hash of the purpose string.
std::uint64_t HashPurpose(std::string_view purpose) {
  std::uint64_t hash = 0xcbf29ce484222325ULL;
  for (unsigned char c : purpose) {
    hash ^= c;
    hash *= 0x100000001b3ULL;
  }
  return hash;
}

constexpr std::uint64_t RotateLeft(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

}  // namespace

RandomStream::RandomStream(std::uint64_t seed, std::string_view purpose, std::uint64_t index) {
  // Chain the three parts through SplitMix64 so that nearby seeds or indices give unrelated streams.
  std::uint64_t key = seed;
  key = SplitMix64(key) ^ HashPurpose(purpose);
  key = SplitMix64(key) ^ index;
  for (std::uint64_t& word : state_) word = SplitMix64(key);
}

std::uint64_t RandomStream::NextU64() {
  const std::uint64_t result = RotateLeft(state_[1] * 5, 7) * 9;
  const std::uint64_t t = state_[1] << 17;
  state_[2] ^= state_[0];
  state_[3] ^= state_[1];
  state_[1] ^= state_[2];
  state_[0] ^= state_[3];
  state_[2] ^= t;
  state_[3] = RotateLeft(state_[3], 45);
  return result;
}

double RandomStream::Uniform() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }

std::uint64_t RandomStream::UniformInt(std::uint64_t n) {
  // Rejection: draw below the largest multiple of n.
  const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
  std::uint64_t draw = NextU64();
  while (draw >= limit) draw = NextU64();
  return draw % n;
}

double RandomStream::Normal(double mean, double deviation) {
  if (has_spare_normal_) {
    has_spare_normal_ = false;
    return mean + deviation * spare_normal_;
  }
  double u = 0.0, v = 0.0, s = 0.0;
  do {
    u = 2.0 * Uniform() - 1.0;
    v = 2.0 * Uniform() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double factor = std::sqrt(-2.0 * std::log(s) / s);
  spare_normal_ = v * factor;
  has_spare_normal_ = true;
  return mean + deviation * u * factor;
}

}  // namespace orcs
