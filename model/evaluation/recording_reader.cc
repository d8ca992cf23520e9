#include "model/evaluation/recording_reader.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>

#include "model/core/error.h"
#include "model/core/json_node.h"
#include "model/core/text_file.h"
#include "model/evaluation/recorder.h"

namespace orcs::evaluation {
namespace {

constexpr std::size_t kPrefixBytes = 16;                      // magic, version, header length
constexpr std::uint32_t kMaxHeaderBytes = 16u << 20;          // 16 MiB
constexpr std::size_t kContactBytes = 2 * 4 + 7 * 4;          // two int32, seven float32
constexpr std::uint32_t kMaxContactsPerFrame = 1u << 16;

std::uint32_t ReadU32(std::string_view bytes, std::size_t offset) {
  std::uint32_t value = 0;
  std::memcpy(&value, bytes.data() + offset, sizeof value);
  return value;
}

// Inflates the frame stream, refusing more than `limit` bytes, and a stream that does not end unless
// `allow_unfinished`; `finished` says whether it ended.
std::string Inflate(std::string_view compressed, const std::string& name, std::uint64_t limit, bool allow_unfinished,
                    bool& finished) {
  z_stream stream{};
  if (inflateInit(&stream) != Z_OK) throw InputError(name, 0, "cannot start decompressing (zlib)");
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
  stream.avail_in = static_cast<uInt>(compressed.size());
  std::string out;
  unsigned char buffer[65536];
  int status = Z_OK;
  while (status != Z_STREAM_END) {
    stream.next_out = buffer;
    stream.avail_out = sizeof buffer;
    status = inflate(&stream, Z_NO_FLUSH);
    if (status != Z_OK && status != Z_STREAM_END) {
      inflateEnd(&stream);
      const bool ended = status == Z_BUF_ERROR;  // no more input before the end of the stream
      if (ended && allow_unfinished) {
        finished = false;
        return out;
      }
      throw InputError(name, 0, ended ? "truncated: the frame stream ends early"
                                      : "corrupt frame stream (zlib: " + std::string(stream.msg ? stream.msg : "?") + ")");
    }
    out.append(reinterpret_cast<const char*>(buffer), sizeof buffer - stream.avail_out);
    if (out.size() > limit) {
      inflateEnd(&stream);
      throw InputError(name, 0, "frames exceed " + std::to_string(limit >> 20) + " MiB when decompressed");
    }
  }
  inflateEnd(&stream);
  finished = true;
  return out;
}

nlohmann::json ParseHeader(std::string_view bytes, const std::string& name) {
  if (bytes.size() < kPrefixBytes || std::memcmp(bytes.data(), kRecordingMagic, sizeof kRecordingMagic) != 0) {
    throw InputError(name, 0, "not an orcs recording (no ORCSREC signature)");
  }
  const std::uint32_t version = ReadU32(bytes, 8);
  if (version > kRecordingVersion || version == 0) {
    throw InputError(name, 0, "recording format version " + std::to_string(version) + " is newer than this orcs reads (" +
                                  std::to_string(kRecordingVersion) + "): update orcs");
  }
  const std::uint32_t length = ReadU32(bytes, 12);
  if (length > kMaxHeaderBytes || length > bytes.size() - kPrefixBytes) {
    throw InputError(name, 0, "truncated: the header says " + std::to_string(length) + " bytes, the file holds " +
                                  std::to_string(bytes.size() - kPrefixBytes));
  }
  nlohmann::json header = ParseJson(std::string(bytes.substr(kPrefixBytes, length)), name + " (header)");
  if (!header.is_object() || !header.contains("channels") || !header["channels"].is_array() ||
      !header.contains("bodies") || !header["bodies"].is_array()) {
    throw InputError(name, 0, "header: expected an object with 'channels' and 'bodies' arrays");
  }
  for (const nlohmann::json& channel : header["channels"]) {
    if (!channel.is_string()) throw InputError(name, 0, "header: 'channels' must hold strings");
  }
  return header;
}

// Walks the frames: time, contact count, XOR-ed values, contacts. A frame cut short is an error, or — in a stream
// still being written (`complete` false) — where the frames so far end.
void ReadFrames(std::string_view frames, const std::string& name, bool complete, Recording& recording) {
  const std::size_t channels = recording.channels.size();
  std::vector<std::uint32_t> bits(channels, 0);
  std::size_t at = 0;
  recording.contact_offsets.push_back(0);
  while (at < frames.size()) {
    const int frame = recording.frame_count();
    const auto truncated = [&] { return InputError(name, 0, "truncated inside frame " + std::to_string(frame)); };
    if (frames.size() - at < 12 + channels * 4) {
      if (!complete) break;
      throw truncated();
    }
    double time = 0;
    std::memcpy(&time, frames.data() + at, sizeof time);
    const std::uint32_t contacts = ReadU32(frames, at + 8);
    if (contacts > kMaxContactsPerFrame) {
      throw InputError(name, 0, "frame " + std::to_string(frame) + " claims " + std::to_string(contacts) + " contacts");
    }
    if (frames.size() - at - 12 - channels * 4 < contacts * kContactBytes) {
      if (!complete) break;
      throw truncated();
    }
    at += 12;
    for (std::size_t c = 0; c < channels; ++c) {
      bits[c] ^= ReadU32(frames, at + 4 * c);
      recording.values.push_back(std::bit_cast<float>(bits[c]));
    }
    at += 4 * channels;
    for (std::uint32_t k = 0; k < contacts; ++k) {
      RecordedContact contact;
      std::memcpy(&contact.body1, frames.data() + at, 4);
      std::memcpy(&contact.body2, frames.data() + at + 4, 4);
      std::memcpy(contact.position, frames.data() + at + 8, 12);
      std::memcpy(contact.normal, frames.data() + at + 20, 12);
      std::memcpy(&contact.depth, frames.data() + at + 32, 4);
      recording.contacts.push_back(contact);
      at += kContactBytes;
    }
    recording.times.push_back(time);
    recording.contact_offsets.push_back(static_cast<std::uint32_t>(recording.contacts.size()));
  }
  if (recording.times.empty()) throw InputError(name, 0, "holds no frame");
}

}  // namespace

int Recording::FindChannel(std::string_view name) const {
  const auto it = std::find(channels.begin(), channels.end(), name);
  return it == channels.end() ? -1 : static_cast<int>(it - channels.begin());
}

Recording ParseRecording(std::string_view bytes, const std::string& name, const RecordingLimits& limits) {
  Recording recording;
  recording.header = ParseHeader(bytes, name);
  for (const nlohmann::json& channel : recording.header["channels"]) recording.channels.push_back(channel);
  const std::size_t frames_at = kPrefixBytes + ReadU32(bytes, 12);
  const std::string frames =
      Inflate(bytes.substr(frames_at), name, limits.max_decompressed_bytes, limits.allow_unfinished, recording.finished);
  ReadFrames(frames, name, recording.finished, recording);
  return recording;
}

Recording ReadRecording(const std::string& path, const RecordingLimits& limits) {
  return ParseRecording(ReadTextFile(path, limits.max_file_bytes, "a recording"), path, limits);
}

}  // namespace orcs::evaluation
