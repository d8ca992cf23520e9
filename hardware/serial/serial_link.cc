#include "hardware/serial/serial_link.h"

#include <fcntl.h>
#include <libserialport.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "model/core/error.h"

namespace orcs::hardware {
namespace {

constexpr unsigned kFirstPtySlaveMajor = 136;  // Linux: UNIX98 pseudo-terminal slaves have majors 136…143
constexpr unsigned kLastPtySlaveMajor = 143;

std::string OpenHint(int error) {
  if (error == EACCES) return " (add yourself to the 'dialout' group, then log in again)";
  if (error == ENOENT) return " (is the adapter plugged in? `ls /dev/ttyUSB* /dev/ttyACM*` lists the ports)";
  return "";
}

// A pseudo-terminal in raw mode through POSIX termios (libserialport cannot open one).
class TermiosLink final : public SerialLink {
 public:
  explicit TermiosLink(const std::string& path) : path_(path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
    if (fd_ < 0) {
      const int error = errno;
      throw InputError(path, 0, std::string("cannot open the serial port: ") + std::strerror(error) + OpenHint(error));
    }
    termios mode{};
    if (::tcgetattr(fd_, &mode) == 0) {
      ::cfmakeraw(&mode);
      ::tcsetattr(fd_, TCSANOW, &mode);
    }
  }
  ~TermiosLink() override { ::close(fd_); }
  TermiosLink(const TermiosLink&) = delete;
  TermiosLink& operator=(const TermiosLink&) = delete;

  void Write(std::span<const std::uint8_t> bytes) override {
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw std::runtime_error(path_ + ": write failed: " + std::strerror(errno));
      done += static_cast<std::size_t>(n);
    }
  }

  std::size_t Read(std::span<std::uint8_t> buffer, std::chrono::microseconds timeout) override {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now() + std::chrono::microseconds(999));
      if (left.count() <= 0) return 0;
      pollfd wait{fd_, POLLIN, 0};
      const int ready = ::poll(&wait, 1, static_cast<int>(left.count()));
      if (ready < 0 && errno == EINTR) continue;
      if (ready < 0) throw std::runtime_error(path_ + ": poll failed: " + std::strerror(errno));
      if (ready == 0) return 0;
      const ssize_t n = ::read(fd_, buffer.data(), buffer.size());
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n <= 0) throw std::runtime_error(path_ + ": the port closed (read " + std::to_string(n) + ")");
      return static_cast<std::size_t>(n);
    }
  }

  void DropInput() override { ::tcflush(fd_, TCIFLUSH); }
  const std::string& path() const override { return path_; }

 private:
  std::string path_;  // the device, for messages
  int fd_ = -1;       // the open pseudo-terminal
};

// libserialport's last error as text (its message is allocated and must be freed).
std::string LastSerialError() {
  char* message = sp_last_error_message();
  std::string text = message ? message : "unknown error";
  sp_free_error_message(message);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text;
}

// A real serial port through libserialport.
class LibSerialPortLink final : public SerialLink {
 public:
  LibSerialPortLink(const std::string& path, int baud) : path_(path) {
    Check(sp_get_port_by_name(path.c_str(), &port_), "cannot find the serial port");
    Check(sp_open(port_, SP_MODE_READ_WRITE), "cannot open the serial port");
    Check(sp_set_baudrate(port_, baud), "cannot set the baud rate " + std::to_string(baud));
    Check(sp_set_bits(port_, 8), "cannot set 8 data bits");
    Check(sp_set_parity(port_, SP_PARITY_NONE), "cannot set no parity");
    Check(sp_set_stopbits(port_, 1), "cannot set one stop bit");
    Check(sp_set_flowcontrol(port_, SP_FLOWCONTROL_NONE), "cannot turn flow control off");
  }
  ~LibSerialPortLink() override {
    if (port_) {
      sp_close(port_);
      sp_free_port(port_);
    }
  }
  LibSerialPortLink(const LibSerialPortLink&) = delete;
  LibSerialPortLink& operator=(const LibSerialPortLink&) = delete;

  void Write(std::span<const std::uint8_t> bytes) override {
    const sp_return n = sp_blocking_write(port_, bytes.data(), bytes.size(), 0);
    if (n < 0 || static_cast<std::size_t>(n) != bytes.size()) Fail("write failed");
    if (sp_drain(port_) != SP_OK) Fail("write failed");
  }

  std::size_t Read(std::span<std::uint8_t> buffer, std::chrono::microseconds timeout) override {
    const auto ms = static_cast<unsigned>((timeout.count() + 999) / 1000);
    const sp_return n = sp_blocking_read_next(port_, buffer.data(), buffer.size(), ms == 0 ? 1 : ms);
    if (n < 0) Fail("read failed");
    return static_cast<std::size_t>(n);
  }

  void DropInput() override { sp_flush(port_, SP_BUF_INPUT); }
  const std::string& path() const override { return path_; }

 private:
  void Check(sp_return result, const std::string& what) {
    if (result == SP_OK) return;
    const int error = errno;
    const std::string reason = result == SP_ERR_FAIL ? LastSerialError() : "no such serial port";
    if (port_ && result != SP_OK && what.starts_with("cannot find")) {
      sp_free_port(port_);
      port_ = nullptr;
    }
    throw InputError(path_, 0, what + ": " + reason + OpenHint(error));
  }
  [[noreturn]] void Fail(const std::string& what) {
    throw std::runtime_error(path_ + ": " + what + ": " + LastSerialError());
  }

  std::string path_;          // the device, for messages
  sp_port* port_ = nullptr;   // libserialport's handle
};

}  // namespace

bool IsPseudoTerminal(const std::string& path) {
  struct stat info{};
  if (::stat(path.c_str(), &info) != 0 || !S_ISCHR(info.st_mode)) return false;
  const unsigned device_major = major(info.st_rdev);
  return device_major >= kFirstPtySlaveMajor && device_major <= kLastPtySlaveMajor;
}

std::unique_ptr<SerialLink> OpenSerialLink(const std::string& path, int baud) {
  if (IsPseudoTerminal(path)) return std::make_unique<TermiosLink>(path);
  return std::make_unique<LibSerialPortLink>(path, baud);
}

}  // namespace orcs::hardware
