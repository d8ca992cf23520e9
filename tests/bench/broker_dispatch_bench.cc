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
#include "broker/broker_core.h"
#include "clients/runtime/batch_client.h"
#include "net/curve_keys.h"
#include "net/status_client.h"
#include "proto/envelope.h"
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

// Asks the broker for its status `per_second` times a second on its own connection, as orcs-view's dashboard does
// once a second, until destroyed; counts the answers.
class StatusPoller {
 public:
  StatusPoller(const std::string& endpoint, const std::string& curve_keys, int per_second) {
    if (per_second <= 0) return;
    thread_ = std::thread([this, endpoint, curve_keys, per_second] {
      net::StatusClient client({endpoint, curve_keys, milliseconds(10000)});
      const auto period = std::chrono::microseconds(1000000 / per_second);
      auto next = std::chrono::steady_clock::now();
      while (!stop_.load()) {
        client.Fetch();
        answers_.fetch_add(1);
        next += period;
        std::this_thread::sleep_until(next);  // the pace of a polling page, not a wait for a condition
      }
    });
  }
  ~StatusPoller() {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
  }
  std::uint64_t answers() const { return answers_.load(); }

 private:
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> answers_{0};
  std::thread thread_;
};

// range(0): jobs per batch; range(1): each worker's credit; range(2): its short-job credit (WorkerConnectionOptions:
// the credit it asks for once its jobs prove short; ≤ credit keeps the credit fixed); range(3): 1 = every
// connection with CURVE (docs/security.md); range(4): 1 = a batch id of one character instead of the library's 128
// random bits (32 hex digits): ids that fit the standard library's small-string buffer, as the ids before issue 18
// did, so that the lease bookkeeping can be told apart from the cost of longer ids; range(5): status requests per
// second from a StatusPoller while the batch runs (issue 21: a dashboard must not slow dispatch; 0 = none).
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
    runtime::BatchClientOptions client_options;
    client_options.endpoint = broker.client_endpoint();
    client_options.curve_keys = curve_keys;
    if (state.range(4) != 0) client_options.batch_id = "b";
    runtime::BatchClient client(client_options);
    StatusPoller poller(broker.client_endpoint(), curve_keys, static_cast<int>(state.range(5)));

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
    state.counters["status_answers"] = static_cast<double>(poller.answers());
  }
  broker.Stop();
  broker_thread.join();
}
BENCHMARK(BM_BrokerDispatchEmptyJobs)
    ->Args({10000, 2, 16, 0, 0, 0})  // the defaults of WorkerConnectionOptions (and orcs-worker)
    ->Args({10000, 2, 16, 0, 0, 1})   // the same while a dashboard asks for the status once a second
    ->Args({10000, 2, 16, 0, 0, 10})  // ... and ten times a second
    ->Args({10000, 2, 16, 1, 0, 0})  // the same with CURVE
    ->Args({10000, 2, 2, 0, 0, 0})   // credit fixed at 2
    ->Args({10000, 8, 8, 0, 0, 0})
    ->Args({10000, 32, 32, 0, 0, 0})
    ->Args({10000, 2, 16, 0, 1, 0})  // short batch ids: the lease bookkeeping alone, against the build before it
    ->Args({10000, 2, 2, 0, 1, 0})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()  // the CPU column: every thread's CPU time (broker, client, workers, ZeroMQ's)
    ->UseRealTime();

// The broker thread's cost of one status, without sockets: BrokerCore::Status() of a busy broker — range(0)
// workers each holding 2 jobs, and 10 batches holding range(1) jobs each. The status is built from the workers and
// batches alone (their counts are kept as jobs move), so the jobs held should not change its cost.
// At one request a second (a dashboard) the fraction of the broker's thread it takes is this time over 1 s.
class NullTransport final : public broker::BrokerTransport {
 public:
  bool SendToWorker(const std::string&, const v1::BrokerToWorker&) override { return true; }
  bool SendToClient(const std::string&, const v1::BrokerToClient&) override { return true; }
};

void BM_BrokerCoreStatus(benchmark::State& state) {
  const int workers = static_cast<int>(state.range(0));
  const int jobs_per_batch = static_cast<int>(state.range(1));
  broker::BrokerOptions options;
  options.log = [](std::string_view) {};
  NullTransport transport;
  broker::BrokerCore core(options, transport, nullptr);
  auto now = std::chrono::steady_clock::now();
  for (int b = 0; b < 10; ++b) {
    v1::ClientToBroker submit;
    submit.set_protocol_version(proto::kProtocolVersion);
    submit.mutable_submit()->set_batch_id(std::string(32, static_cast<char>('a' + b)));
    submit.mutable_submit()->set_client_id("client-" + std::to_string(b));
    submit.mutable_submit()->set_owner_token(std::string(16, 'k'));
    for (int j = 0; j < jobs_per_batch; ++j) {
      v1::Job& job = *submit.mutable_submit()->add_jobs();
      job.set_protocol_version(proto::kProtocolVersion);
      job.set_job_id("job-" + std::to_string(j));
    }
    core.OnClientMessage("c" + std::to_string(b), "", submit, now);
  }
  for (int w = 0; w < workers; ++w) {
    v1::WorkerToBroker ready;
    ready.set_protocol_version(proto::kProtocolVersion);
    ready.mutable_ready()->set_worker_id("node" + std::to_string(w) + "-12345");
    ready.mutable_ready()->set_host("node" + std::to_string(w));
    ready.mutable_ready()->set_credit(2);
    core.OnWorkerMessage("w" + std::to_string(w), ready, now);
  }
  core.Dispatch(now);
  for (auto _ : state) {
    const v1::Status status = core.Status("", now);
    benchmark::DoNotOptimize(status.ByteSizeLong());
  }
  state.counters["bytes"] = static_cast<double>(core.Status("", now).ByteSizeLong());
}
BENCHMARK(BM_BrokerCoreStatus)->Args({2, 10000})->Args({64, 1000})->Args({512, 1000})->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace orcs

BENCHMARK_MAIN();
