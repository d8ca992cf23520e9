#include "tests/support/batch_collector.h"

#include <cstdint>
#include <optional>
#include <utility>

#include "clients/runtime/batch_client.h"

namespace orcs::test_support {

CollectedBatch CollectBatch(const std::string& endpoint, std::vector<v1::Job> jobs, std::chrono::seconds limit,
                            const std::function<void(int answered)>& on_result) {
  constexpr std::chrono::milliseconds kPoll{100};
  runtime::BatchClientOptions options;
  options.endpoint = endpoint;
  options.heartbeat_interval = kPoll;
  runtime::BatchClient client(options);
  const std::size_t count = jobs.size();
  client.Submit(std::move(jobs));
  CollectedBatch batch;
  const std::int64_t polls = limit / kPoll;
  for (std::int64_t poll = 0; batch.results.size() < count && poll < polls; ++poll) {
    std::optional<v1::Result> result = client.Next(kPoll);
    if (!result) continue;
    if (batch.results.contains(result->job_id())) {
      batch.duplicate_ids.push_back(result->job_id());
      continue;
    }
    batch.results[result->job_id()] = std::move(*result);
    if (on_result) on_result(static_cast<int>(batch.results.size()));
  }
  return batch;
}

}  // namespace orcs::test_support
