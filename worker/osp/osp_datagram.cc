#include "worker/osp/osp_datagram.h"

#include <bit>
#include <cstring>

namespace orcs::osp {

void DatagramReader::Need(std::size_t count, const char* what) const {
  if (remaining() < count) {
    throw MalformedDatagram("datagram ends at byte " + std::to_string(bytes_.size()) + " before " + what);
  }
}

std::uint8_t DatagramReader::Byte() {
  Need(1, "a byte");
  return bytes_[position_++];
}

std::int32_t DatagramReader::Int() {
  Need(4, "an int");
  std::uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = (value << 8) | bytes_[position_ + static_cast<std::size_t>(i)];
  position_ += 4;
  return static_cast<std::int32_t>(value);
}

float DatagramReader::Float() { return std::bit_cast<float>(Int()); }

std::string DatagramReader::String() {
  const std::uint8_t* begin = bytes_.data() + position_;
  const void* nul = std::memchr(begin, 0, remaining());
  if (nul == nullptr) throw MalformedDatagram("string without NUL at byte " + std::to_string(position_));
  const std::size_t length = static_cast<std::size_t>(static_cast<const std::uint8_t*>(nul) - begin);
  std::string text(reinterpret_cast<const char*>(begin), length);
  position_ += length + 1;
  return text;
}

std::int32_t DatagramReader::Count(std::size_t item_bytes) {
  const std::int32_t count = Int();
  if (count < 0 || static_cast<std::size_t>(count) * item_bytes > remaining()) {
    throw MalformedDatagram("count " + std::to_string(count) + " does not fit the " + std::to_string(remaining()) +
                            " bytes left");
  }
  return count;
}

bool DatagramReader::AtEnd() const {
  return remaining() == 0 || (remaining() == 1 && bytes_[position_] == kDatagramEnd);
}

DatagramWriter& DatagramWriter::Byte(std::uint8_t value) {
  bytes_.push_back(value);
  return *this;
}

DatagramWriter& DatagramWriter::Int(std::int32_t value) {
  const auto bits = static_cast<std::uint32_t>(value);
  for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
  return *this;
}

DatagramWriter& DatagramWriter::Float(float value) { return Int(std::bit_cast<std::int32_t>(value)); }

DatagramWriter& DatagramWriter::String(std::string_view text) {
  for (char c : text) {
    if (c != '\0') bytes_.push_back(static_cast<std::uint8_t>(c));
  }
  bytes_.push_back(0);
  return *this;
}

std::vector<std::uint8_t> DatagramWriter::Finish(bool osp_end) const {
  std::vector<std::uint8_t> bytes = bytes_;
  if (osp_end) bytes.push_back(kDatagramEnd);
  if (bytes.size() > kMaxDatagramBytes) {
    throw MalformedDatagram("a datagram of " + std::to_string(bytes.size()) + " bytes exceeds the " +
                            std::to_string(kMaxDatagramBytes) + "-byte limit");
  }
  return bytes;
}

}  // namespace orcs::osp
