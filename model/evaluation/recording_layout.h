// What a recording holds about one simulation, taken apart from how it is stored: the header (the static world —
// bodies, geoms, colours, joints, agents — and the channel list) and, on demand, the current values of every
// channel and the current contacts. The Recorder writes these into a file; orcs-view's live mode sends them to the
// page. docs/recording.md describes both.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "model/core/value.h"
#include "model/scene/simulation.h"

namespace orcs::evaluation {

/// Where a recording came from; written into its header's "source" and "program".
struct RecordingSource {
  std::string program = "orcs";  ///< the program that wrote it ("orcs-sim", "orcs-worker", ...)
  std::string environment;       ///< environment file or "<inline>"
  std::string scenario;          ///< scenario name, "" = none
  std::uint64_t seed = 0;        ///< the run's seed
  int set = 0;                   ///< the scenario's parameter set index
  nlohmann::json genome;         ///< the genome, null = none
};

/// One contact as recorded: bodies and where.
struct ContactSample {
  std::int32_t body1 = -1;  ///< body index in the header's "bodies"
  std::int32_t body2 = -1;  ///< body index, or -1
  float position[3] = {};   ///< contact point, world, m
  float normal[3] = {};     ///< unit normal, world
  float depth = 0;          ///< penetration, m
};

/// "box", "sphere", "capsule" or "plane".
std::string_view ShapeName(physics::Shape shape);
/// A geom's size as recordings and `orcs-sim --describe` print it: box [w, h, d], sphere [r], capsule [r, length],
/// plane [].
nlohmann::json GeomSizeJson(const physics::GeomDescription& geom);

class RecordingLayout {
 public:
  /// Describes `simulation` (built): its channels are the repository's numeric values as registered now.
  RecordingLayout(const scene::Simulation& simulation, const RecordingSource& source);

  /// The header JSON (docs/recording.md), without frame counts.
  const nlohmann::json& header() const { return header_; }
  int channel_count() const { return static_cast<int>(channels_.size()); }

  /// Writes every channel's current value into `out` (channel_count() floats).
  void ReadValues(float* out) const;
  /// The contacts of the last step that made constraints (excluded pairs left out), into `out` (cleared first).
  void ReadContacts(std::vector<ContactSample>& out) const;

 private:
  struct Channel {
    const Value* value;  // the repository value
    int component;       // 0 for scalars; x/y/z or w/x/y/z of vectors and quaternions
  };

  void AddChannels();
  void DescribeWorld();

  const scene::Simulation& simulation_;
  std::vector<Channel> channels_;
  nlohmann::json header_;
};

}  // namespace orcs::evaluation
