// The seam between an optimiser and whatever runs its jobs: orcs-gap's fits and diagnosis ask a JobEvaluator for
// results, so that they run through the broker in use (JobRunner) and on an analytic stand-in in unit tests.
#pragma once

#include <cstdint>
#include <vector>

#include "orcs/v1/job.pb.h"
#include "orcs/v1/result.pb.h"

namespace orcs::runtime {

class JobEvaluator {
 public:
  virtual ~JobEvaluator() = default;

  /// Runs `jobs` and returns their results in the same order. Thread-safe: several fits call it at once.
  virtual std::vector<v1::Result> Run(std::vector<v1::Job> jobs) = 0;

  /// Jobs run so far.
  virtual std::uint64_t jobs_run() const = 0;
};

}  // namespace orcs::runtime
