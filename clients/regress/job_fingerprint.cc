#include "clients/regress/job_fingerprint.h"

#include <cstdint>

#include "model/core/fnv1a64.h"

namespace orcs::regress {

std::string JobFingerprint(const v1::Job& job) {
  Fnv1a64 fnv;
  fnv.AddField(job.scenario_json());
  fnv.AddField(job.genome_json());
  fnv.AddNumber(job.seed());
  fnv.AddNumber(static_cast<std::uint64_t>(job.overrides_size()));
  for (const v1::Override& override : job.overrides()) {
    fnv.AddField(override.path());
    fnv.AddField(override.value());
  }
  return "fnv1a64:" + fnv.Hex();
}

}  // namespace orcs::regress
