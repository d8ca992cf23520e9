// Dispatch rate of the broker: empty jobs from one BatchClient through a real Broker to two echo workers (real
// WorkerConnections) and back, over TCP on 127.0.0.1, everything in this process on its own threads. An empty
// job carries only its ids; the echo worker answers at once. So the figure is the protocol's and the broker's
// overhead per job: serialising, three socket hops each way, the dispatch bookkeeping. docs/benchmarks.md;
// scripts/bench_batch.sh runs the default-settings case next to the same empty tasks through Dask.
#include <benchmark/benchmark.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "broker/broker.h"
#include "broker/client.h"
#include "net/curve_keys.h"
#include "worker/broker_connection.h"

namespace orcs {
namespace {

using std::chrono::milliseconds;

// A temporary CURVE key folder for one broker, one worker key and one client key (docs/security.md); removed at
// the end.
class CurveKeyFolder {
 public:
  CurveKeyFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "orcs-bench-keys-XXXXXX").string();
    if (::mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
    for (const char* name : {"broker", "worker", "client"}) {
      net::WriteCurveKeyPair(path_, name, net::GenerateCurveKeyPair());
    }
    std::filesystem::create_directory(path_ / "allowed_workers");
    std::filesystem::create_directory(path_ / "allowed_clients");
    std::filesystem::copy_file(path_ / "worker.pub", path_ / "allowed_workers/worker.pub");
    std::filesystem::copy_file(path_ / "client.pub", path_ / "allowed_clients/client.pub");
  }
  ~CurveKeyFolder() { std::filesystem::remove_all(path_); }
  std::string path() const { return path_.string(); }

 private:
  std::filesystem::path path_;
};

// A worker answering every job at once with status OK and nothing else.
class EchoWorker {
 public:
  EchoWorker(const std::string& endpoint, const std::string& name, int credit, int short_job_credit,
             const std::string& curve_keys) {
    worker::WorkerConnectionOptions options;
    options.curve_keys = curve_keys;
    options.endpoint = endpoint;
    options.worker_id = name;
    options.credit = credit;
    options.short_job_credit = short_job_credit;
    connection_ = std::make_unique<worker::WorkerConnection>(options);
    thread_ = std::thread([this] {
      while (!stop_.load()) {
        std::optional<v1::Job> job = connection_->NextJob(milliseconds(50));
        if (!job) continue;
        v1::Result result;
        result.set_job_id(job->job_id());
        result.set_batch_id(job->batch_id());
        result.set_status(v1::Result::OK);
        connection_->SendResult(std::move(result));
      }
    });
  }
  ~EchoWorker() {
    stop_.store(true);
    thread_.join();
  }

 private:
  std::unique_ptr<worker::WorkerConnection> connection_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

// range(0): jobs per batch; range(1): each worker's credit; range(2): its short-job credit (WorkerConnectionOptions:
// the credit it asks for once its jobs prove short; ≤ credit keeps the credit fixed); range(3): 1 = every
// connection with CURVE (docs/security.md); range(4): 1 = a batch id of one character instead of the library's 128
// random bits (32 hex digits): ids that fit the standard library's small-string buffer, as the ids before issue 18
// did, so that the lease bookkeeping can be told apart from the cost of longer ids.
void BM_BrokerDispatchEmptyJobs(benchmark::State& state) {
  const int jobs_per_batch = static_cast<int>(state.range(0));
  const int credit = static_cast<int>(state.range(1));
  const int short_job_credit = static_cast<int>(state.range(2));
  std::unique_ptr<CurveKeyFolder> keys;
  if (state.range(3) != 0) keys = std::make_unique<CurveKeyFolder>();
  const std::string curve_keys = keys ? keys->path() : "";
  broker::BrokerOptions broker_options;  // 127.0.0.1, ephemeral ports
  broker_options.curve_keys = curve_keys;
  broker_options.log = [](std::string_view) {};
  broker::Broker broker(broker_options);
  std::thread broker_thread([&] { broker.Run(); });
  {
    EchoWorker a(broker.worker_endpoint(), "a", credit, short_job_credit, curve_keys);
    EchoWorker b(broker.worker_endpoint(), "b", credit, short_job_credit, curve_keys);
    broker::BatchClientOptions client_options;
    client_options.endpoint = broker.client_endpoint();
    client_options.curve_keys = curve_keys;
    if (state.range(4) != 0) client_options.batch_id = "b";
    broker::BatchClient client(client_options);

    int batch = 0;
    for (auto _ : state) {
      state.PauseTiming();
      std::vector<v1::Job> jobs(static_cast<std::size_t>(jobs_per_batch));
      for (int i = 0; i < jobs_per_batch; ++i) jobs[i].set_job_id(std::to_string(batch) + "-" + std::to_string(i));
      ++batch;
      state.ResumeTiming();
      client.Submit(std::move(jobs));
      for (int received = 0; received < jobs_per_batch;) {
        std::optional<v1::Result> result = client.Next(milliseconds(10000));
        if (!result) throw std::runtime_error("no result for 10 s");
        ++received;
      }
    }
    state.SetItemsProcessed(state.iterations() * jobs_per_batch);
    const broker::BrokerStats stats = broker.stats();
    state.counters["requeued"] = static_cast<double>(stats.jobs_requeued);
  }
  broker.Stop();
  broker_thread.join();
}
BENCHMARK(BM_BrokerDispatchEmptyJobs)
    ->Args({10000, 2, 16, 0, 0})  // the defaults of WorkerConnectionOptions (and orcs-worker)
    ->Args({10000, 2, 16, 1, 0})  // the same with CURVE
    ->Args({10000, 2, 2, 0, 0})   // credit fixed at 2
    ->Args({10000, 8, 8, 0, 0})
    ->Args({10000, 32, 32, 0, 0})
    ->Args({10000, 2, 16, 0, 1})  // short batch ids: the lease bookkeeping alone, against the build before it
    ->Args({10000, 2, 2, 0, 1})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()  // the CPU column: every thread's CPU time (broker, client, workers, ZeroMQ's)
    ->UseRealTime();

}  // namespace
}  // namespace orcs

BENCHMARK_MAIN();
