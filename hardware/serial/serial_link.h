// A byte link to a servo bus: the serial port a Dynamixel bus hangs on (a USB2Dynamixel, a U2D2, a USB2AX) or the
// pseudo-terminal of the servo-bus emulator (hardware/emulator/). The bus driver reads and writes bytes through it
// and never sees which.
//
// Real ports are opened with libserialport (Debian's libserialport0): baud rate, 8 data bits, no parity, one stop
// bit, no flow control. libserialport refuses pseudo-terminals — it looks the device up in sysfs and sets modem
// lines, which a pseudo-terminal has neither of — so a pseudo-terminal (the emulator's, in tests) is opened through
// POSIX termios in raw mode instead; its baud rate means nothing there (docs/hardware.md, "The serial port").
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace orcs::hardware {

class SerialLink {
 public:
  virtual ~SerialLink() = default;
  /// Sends every byte, waiting until the driver has taken them all. Throws std::runtime_error when the port fails
  /// (a USB adapter unplugged): the bus driver turns that into a bus error.
  virtual void Write(std::span<const std::uint8_t> bytes) = 0;
  /// Waits up to `timeout` for bytes and reads those that have arrived into `buffer` (at most its size), returning
  /// as soon as any have: the number read (0 on a timeout). Throws std::runtime_error when the port fails.
  virtual std::size_t Read(std::span<std::uint8_t> buffer, std::chrono::microseconds timeout) = 0;
  /// Drops bytes received but not read (the rest of a corrupt reply, an echo), so the next read starts clean.
  virtual void DropInput() = 0;
  /// The port's path, for messages.
  virtual const std::string& path() const = 0;
};

/// Opens `path` at `baud` bits per second. Throws InputError naming the path with the reason and a hint (no such
/// device; permission denied: the dialout group) when it cannot be opened.
std::unique_ptr<SerialLink> OpenSerialLink(const std::string& path, int baud);

/// Whether `path` is a pseudo-terminal's device (a /dev/pts/N, or a link to one), which OpenSerialLink opens with
/// termios rather than libserialport.
bool IsPseudoTerminal(const std::string& path);

}  // namespace orcs::hardware
