// Runs one batch through a real broker's client endpoint and gathers what comes back, for the multi-process tests
// that submit jobs and check their results (batch, worker faults, worker reconnect, adversarial input).
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "orcs/v1/job.pb.h"
#include "orcs/v1/result.pb.h"

namespace orcs::test_support {

/// What one batch brought back.
struct CollectedBatch {
  std::map<std::string, v1::Result> results;  ///< the first result of each job, by job id
  std::vector<std::string> duplicate_ids;     ///< a job id each time a result came again for a job already answered
};

/// Submits `jobs` through a BatchClient on `endpoint` (heartbeats every 100 ms) and gathers results until every job
/// has one or `limit` has passed (polled every 100 ms, so the wait is bounded). `on_result(n)`, if given, is told
/// the number of jobs answered so far after each new one.
CollectedBatch CollectBatch(const std::string& endpoint, std::vector<v1::Job> jobs, std::chrono::seconds limit,
                            const std::function<void(int answered)>& on_result = {});

}  // namespace orcs::test_support
