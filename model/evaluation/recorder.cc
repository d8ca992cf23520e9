#include "model/evaluation/recorder.h"

#include <utility>

#include <bit>

#include "base/demand.h"
#include "model/core/atomic_file.h"

namespace orcs::evaluation {
namespace {

static_assert(std::endian::native == std::endian::little, "recordings are little-endian; the recorder copies bytes");

template <typename T>
void Append(std::vector<unsigned char>& out, const T& value) {
  const auto* bytes = reinterpret_cast<const unsigned char*>(&value);
  out.insert(out.end(), bytes, bytes + sizeof(T));
}

}  // namespace

Recorder::Recorder(const scene::Simulation& simulation, const RecordingSource& source)
    : simulation_(simulation), layout_(simulation, source) {
  const std::string text = layout_.header().dump();
  out_.append(kRecordingMagic, sizeof kRecordingMagic);
  const std::uint32_t version = kRecordingVersion;
  const auto length = static_cast<std::uint32_t>(text.size());
  out_.append(reinterpret_cast<const char*>(&version), sizeof version);
  out_.append(reinterpret_cast<const char*>(&length), sizeof length);
  out_ += text;

  const int ok = deflateInit(&stream_, Z_BEST_SPEED);
  ORCS_DEMAND_MSG(ok == Z_OK, "zlib initialises");
  (void)ok;
  values_.resize(layout_.channel_count());
  previous_.assign(layout_.channel_count(), 0);
  Sample();
}

Recorder::~Recorder() { deflateEnd(&stream_); }

void Recorder::Sample() { SampleAt(simulation_.time()); }

void Recorder::SampleAt(double time) {
  ORCS_DEMAND_MSG(!finished_, "Sample() after Finish()");
  layout_.ReadValues(values_.data());
  layout_.ReadContacts(contacts_);
  frame_.clear();
  Append(frame_, time);
  Append(frame_, static_cast<std::uint32_t>(contacts_.size()));
  for (std::size_t c = 0; c < values_.size(); ++c) {
    const auto bits = std::bit_cast<std::uint32_t>(values_[c]);
    Append(frame_, bits ^ previous_[c]);  // an unchanged value is stored as 0 and compresses away
    previous_[c] = bits;
  }
  for (const ContactSample& contact : contacts_) {
    Append(frame_, contact.body1);
    Append(frame_, contact.body2);
    for (float v : contact.position) Append(frame_, v);
    for (float v : contact.normal) Append(frame_, v);
    Append(frame_, contact.depth);
  }
  Deflate(frame_.data(), frame_.size(), Z_NO_FLUSH);
  ++frames_;
}

std::string Recorder::TakeFlushed() {
  ORCS_DEMAND_MSG(!finished_, "TakeFlushed() after Finish()");
  Deflate(nullptr, 0, Z_SYNC_FLUSH);
  return std::exchange(out_, std::string());
}

std::string Recorder::Finish() {
  ORCS_DEMAND_MSG(!finished_, "Finish() twice");
  Deflate(nullptr, 0, Z_FINISH);
  finished_ = true;
  return std::move(out_);
}

void Recorder::Deflate(const void* data, std::size_t size, int flush) {
  stream_.next_in = static_cast<Bytef*>(const_cast<void*>(data));
  stream_.avail_in = static_cast<uInt>(size);
  unsigned char buffer[16384];
  int status = Z_OK;
  do {
    stream_.next_out = buffer;
    stream_.avail_out = sizeof buffer;
    status = deflate(&stream_, flush);
    ORCS_DEMAND_MSG(status != Z_STREAM_ERROR, "zlib stream state intact");
    out_.append(reinterpret_cast<const char*>(buffer), sizeof buffer - stream_.avail_out);
  } while (stream_.avail_out == 0 || (flush == Z_FINISH && status != Z_STREAM_END));
}

void WriteRecording(const std::string& path, const std::string& bytes) {
  AtomicFile file(path);
  file.stream().write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  file.Commit();
}

}  // namespace orcs::evaluation
