// The encoding shared by OSP 1.1 and ODCP 1.0 (docs/spec/osp.md, "Encoding"): bytes, little-endian int32,
// IEEE-754 binary32 floats sent as their bit pattern, NUL-terminated ASCII strings; at most 1024 bytes per
// datagram. A reader never reads past the end: a short or malformed datagram is a MalformedDatagram, which the
// servers answer as the protocol says or ignore, never a crash.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace orcs::osp {

/// The largest datagram either protocol sends or accepts, bytes.
constexpr std::size_t kMaxDatagramBytes = 1024;
/// The byte every OSP server datagram ends with (DATAGRAM_END).
constexpr std::uint8_t kDatagramEnd = 120;

/// A datagram that ends before a field, holds a string without NUL, or is longer than allowed.
class MalformedDatagram : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Reads the fields of one datagram in order.
class DatagramReader {
 public:
  explicit DatagramReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}

  std::uint8_t Byte();
  std::int32_t Int();
  float Float();
  /// ASCII up to the next NUL (consumed).
  std::string String();
  /// A count for n following items of `item_bytes` each: non-negative and not more than the bytes left can hold.
  std::int32_t Count(std::size_t item_bytes);

  std::size_t remaining() const { return bytes_.size() - position_; }
  /// True when only an optional trailing DATAGRAM_END (or nothing) is left.
  bool AtEnd() const;

 private:
  void Need(std::size_t count, const char* what) const;

  std::span<const std::uint8_t> bytes_;
  std::size_t position_ = 0;
};

/// Builds one datagram.
class DatagramWriter {
 public:
  DatagramWriter& Byte(std::uint8_t value);
  DatagramWriter& Int(std::int32_t value);
  DatagramWriter& Float(float value);
  /// The text (without NULs) and a NUL.
  DatagramWriter& String(std::string_view text);

  /// The bytes, with DATAGRAM_END appended when `osp_end` (OSP server datagrams). Throws MalformedDatagram when
  /// they exceed kMaxDatagramBytes (a reply the protocol cannot carry: a caller's bug or an over-long name).
  std::vector<std::uint8_t> Finish(bool osp_end = true) const;

  std::size_t size() const { return bytes_.size(); }

 private:
  std::vector<std::uint8_t> bytes_;
};

}  // namespace orcs::osp
