#include "proto/secure_random.h"

#include <sys/random.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace orcs::proto {

std::string SecureRandomBytes(std::size_t count) {
  std::string bytes(count, '\0');
  std::size_t filled = 0;
  while (filled < count) {
    const ssize_t got = ::getrandom(bytes.data() + filled, count - filled, 0);
    if (got < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error(std::string("cannot read random bytes from the OS: getrandom: ") + std::strerror(errno));
    }
    filled += static_cast<std::size_t>(got);
  }
  return bytes;
}

std::string SecureRandomHex(std::size_t bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text;
  text.reserve(2 * bytes);
  for (unsigned char c : SecureRandomBytes(bytes)) {
    text += kDigits[c >> 4];
    text += kDigits[c & 0xf];
  }
  return text;
}

std::uint64_t SecureRandomToken() {
  while (true) {
    const std::string bytes = SecureRandomBytes(sizeof(std::uint64_t));
    std::uint64_t token = 0;
    std::memcpy(&token, bytes.data(), sizeof token);
    if (token != 0) return token;
  }
}

}  // namespace orcs::proto
