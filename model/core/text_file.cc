#include "model/core/text_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "model/core/error.h"

namespace orcs {
namespace {

// What a non-regular file is, for "not a regular file (...)".
std::string KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a file";
}

// Closes a descriptor with its owner.
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) close(fd);
  }
};

}  // namespace

std::string DescribeByteLimit(std::uint64_t bytes) {
  if (bytes >= (1u << 20) && bytes % (1u << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  if (bytes >= (1u << 10) && bytes % (1u << 10) == 0) return std::to_string(bytes >> 10) + " KiB";
  return std::to_string(bytes) + " bytes";
}

std::string ReadTextFile(const std::string& path, std::uint64_t max_bytes, std::string_view kind) {
  // Opened without blocking (a FIFO with no writer would block open() for ever), then checked on the descriptor,
  // so that what is checked is what is read.
  Descriptor file{open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY)};
  if (file.fd < 0) {
    const int error = errno;
    if (error == ENOENT || error == ENOTDIR) throw InputError(path, 0, "cannot read the file: no such file");
    throw InputError(path, 0, std::string("cannot read the file: ") + std::strerror(error));
  }
  struct stat status {};
  if (fstat(file.fd, &status) != 0) {
    throw InputError(path, 0, std::string("cannot read the file: ") + std::strerror(errno));
  }
  if (!S_ISREG(status.st_mode)) throw InputError(path, 0, "not a regular file (" + KindOf(status.st_mode) + ")");
  const auto too_large = [&] {
    return InputError(path, 0, "larger than the " + DescribeByteLimit(max_bytes) + " limit for " + std::string(kind));
  };
  if (static_cast<std::uint64_t>(status.st_size) > max_bytes) throw too_large();
  // Read up to one byte beyond the bound: a file that grows while it is read (or a /proc file, whose size says 0)
  // is still bounded.
  std::string content;
  content.resize(static_cast<std::size_t>(status.st_size) + 1);
  std::size_t filled = 0;
  for (;;) {
    if (filled == content.size()) {
      if (content.size() > max_bytes) throw too_large();
      content.resize(std::min<std::uint64_t>(max_bytes + 1, std::max<std::size_t>(2 * content.size(), 4096)));
    }
    const ssize_t got = read(file.fd, content.data() + filled, content.size() - filled);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) throw InputError(path, 0, std::string("cannot read the file: ") + std::strerror(errno));
    if (got == 0) break;
    filled += static_cast<std::size_t>(got);
  }
  if (filled > max_bytes) throw too_large();
  content.resize(filled);
  return content;
}

}  // namespace orcs
