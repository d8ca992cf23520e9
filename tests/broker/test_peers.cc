#include "tests/broker/test_peers.h"

#include <iostream>

#include "proto/envelope.h"

namespace orcs::test_support {

using Clock = std::chrono::steady_clock;
using proto::kProtocolVersion;

std::function<void(std::string_view)> LogLines::Sink() {
  return [this](std::string_view line) {
    std::lock_guard lock(mutex_);
    lines_.emplace_back(line);
  };
}

std::vector<std::string> LogLines::lines() const {
  std::lock_guard lock(mutex_);
  return lines_;
}

int LogLines::Count(std::string_view needle) const {
  std::lock_guard lock(mutex_);
  int count = 0;
  for (const std::string& line : lines_) count += line.find(needle) != std::string::npos ? 1 : 0;
  return count;
}

broker::BrokerOptions TestBrokerOptions(LogLines* log) {
  broker::BrokerOptions options;
  options.bind_address = "127.0.0.1";
  options.client_port = 0;
  options.worker_port = 0;
  options.heartbeat_interval = kTestHeartbeat;
  options.liveness = kTestLiveness;
  if (log != nullptr) options.log = log->Sink();
  return options;
}

worker::WorkerConnectionOptions TestWorkerOptions(const std::string& endpoint, const std::string& name, int credit,
                                                  LogLines* log) {
  worker::WorkerConnectionOptions options;
  options.endpoint = endpoint;
  options.worker_id = name;
  options.credit = credit;
  options.heartbeat_interval = kTestHeartbeat;
  options.liveness = kTestLiveness;
  if (log != nullptr) options.log = log->Sink();
  return options;
}

runtime::BatchClientOptions TestClientOptions(const std::string& endpoint, LogLines* log) {
  runtime::BatchClientOptions options;
  options.endpoint = endpoint;
  options.heartbeat_interval = kTestHeartbeat;
  options.liveness = kTestLiveness;
  options.connect_timeout = std::chrono::milliseconds(3000);
  options.reconnect_timeout = std::chrono::milliseconds(8000);
  if (log != nullptr) options.log = log->Sink();
  return options;
}

bool WaitFor(const std::function<bool()>& condition, std::chrono::milliseconds limit) {
  const Clock::time_point deadline = Clock::now() + limit;
  while (!condition()) {
    if (Clock::now() >= deadline) return condition();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  return true;
}

int FreePort() {
  zmq::context_t context(1);
  zmq::socket_t socket(context, zmq::socket_type::router);
  socket.set(zmq::sockopt::linger, 0);
  socket.bind("tcp://127.0.0.1:*");
  const std::string endpoint = socket.get(zmq::sockopt::last_endpoint);
  return std::stoi(endpoint.substr(endpoint.rfind(':') + 1));
}

v1::Job MakeJob(const std::string& id, std::uint64_t seed) {
  v1::Job job;
  job.set_protocol_version(kProtocolVersion);
  job.set_job_id(id);
  job.set_seed(seed);
  job.set_genome_json("[" + std::to_string(seed) + "]");
  job.set_scenario_json("{}");
  return job;
}

double EchoFitness(const v1::Job& job) { return 2.0 * static_cast<double>(job.seed()) + 0.25; }

BrokerThread::BrokerThread(broker::BrokerOptions options)
    : broker_(std::make_unique<broker::Broker>(std::move(options))), thread_([this] { broker_->Run(); }) {}

BrokerThread::~BrokerThread() { Stop(); }

void BrokerThread::Stop() {
  if (!thread_.joinable()) return;
  broker_->Stop();
  thread_.join();
}

EchoWorker::EchoWorker(worker::WorkerConnectionOptions options, std::chrono::milliseconds job_time)
    : connection_(std::make_unique<worker::WorkerConnection>(std::move(options))), job_time_(job_time) {
  thread_ = std::thread([this] {
    while (!stop_.load()) {
      std::optional<v1::Job> job = connection_->NextJob(std::chrono::milliseconds(20));
      if (!job) continue;
      if (job_time_.count() > 0) std::this_thread::sleep_for(job_time_);  // the pretend work itself
      v1::Result result;
      result.set_job_id(job->job_id());
      result.set_batch_id(job->batch_id());
      result.set_status(v1::Result::OK);
      result.set_fitness(EchoFitness(*job));
      result.set_message("attempt=" + std::to_string(job->attempt()));
      result.mutable_timings()->set_run_seconds(std::chrono::duration<double>(job_time_).count());
      {
        std::lock_guard lock(mutex_);
        job_ids_.push_back(job->job_id());
      }
      connection_->SendResult(std::move(result));
      ++jobs_done_;
    }
  });
}

EchoWorker::~EchoWorker() {
  stop_.store(true);
  thread_.join();
  connection_.reset();
}

std::vector<std::string> EchoWorker::job_ids() const {
  std::lock_guard lock(mutex_);
  return job_ids_;
}

RawPeer::RawPeer(const std::string& endpoint, const std::optional<net::CurvePeerKeys>& curve)
    : context_(1), socket_(context_, zmq::socket_type::dealer) {
  socket_.set(zmq::sockopt::linger, 0);
  if (curve) net::MakeCurveClient(socket_, *curve);
  socket_.connect(endpoint);
}

void RawPeer::SendFrames(const std::vector<std::string>& frames) {
  for (std::size_t i = 0; i < frames.size(); ++i) {
    socket_.send(zmq::buffer(frames[i]), i + 1 < frames.size() ? zmq::send_flags::sndmore : zmq::send_flags::none);
  }
}

void RawPeer::Send(const google::protobuf::Message& message) { SendFrames({message.SerializeAsString()}); }

std::optional<std::string> RawPeer::Receive(std::chrono::milliseconds timeout) {
  zmq::pollitem_t item{socket_.handle(), 0, ZMQ_POLLIN, 0};
  if (zmq::poll(&item, 1, timeout) == 0) return std::nullopt;
  zmq::message_t message;
  if (!socket_.recv(message, zmq::recv_flags::dontwait)) return std::nullopt;
  std::string first = message.to_string();
  while (message.more() && socket_.recv(message, zmq::recv_flags::dontwait)) {
  }
  return first;
}

void RawPeer::Close() { socket_.close(); }

v1::WorkerToBroker ReadyMessage(const std::string& name, int credit) {
  v1::WorkerToBroker message;
  message.set_protocol_version(kProtocolVersion);
  message.mutable_ready()->set_worker_id(name);
  message.mutable_ready()->set_credit(static_cast<std::uint32_t>(credit));
  return message;
}

v1::WorkerToBroker WorkerHeartbeat() {
  v1::WorkerToBroker message;
  message.set_protocol_version(kProtocolVersion);
  message.mutable_heartbeat();
  return message;
}

v1::WorkerToBroker ResultMessage(const v1::Job& job, const std::string& name) {
  v1::WorkerToBroker message;
  message.set_protocol_version(kProtocolVersion);
  v1::Result& result = *message.mutable_result();
  result.set_protocol_version(kProtocolVersion);
  result.set_job_id(job.job_id());
  result.set_batch_id(job.batch_id());
  result.set_status(v1::Result::OK);
  result.set_fitness(EchoFitness(job));
  result.set_worker_id(name);
  result.set_lease(job.lease());  // the dispatch's token, as WorkerConnection returns it
  return message;
}

std::optional<v1::Job> AwaitJob(RawPeer& worker, std::chrono::milliseconds limit) {
  const Clock::time_point deadline = Clock::now() + limit;
  while (Clock::now() < deadline) {
    std::optional<v1::BrokerToWorker> message = worker.ReceiveEnvelope<v1::BrokerToWorker>(kTestHeartbeat);
    if (message && message->has_job()) return message->job();
    worker.Send(WorkerHeartbeat());
  }
  return std::nullopt;
}

std::optional<v1::BrokerToWorker> NextNonHeartbeat(RawPeer& worker, std::chrono::milliseconds limit) {
  const Clock::time_point deadline = Clock::now() + limit;
  while (Clock::now() < deadline) {
    std::optional<v1::BrokerToWorker> message = worker.ReceiveEnvelope<v1::BrokerToWorker>(
        std::chrono::ceil<std::chrono::milliseconds>(deadline - Clock::now()));
    if (message && !message->has_heartbeat()) return message;
  }
  return std::nullopt;
}

std::vector<v1::Result> Collect(runtime::BatchClient& client, std::size_t count, std::chrono::milliseconds limit) {
  std::vector<v1::Result> results;
  const Clock::time_point deadline = Clock::now() + limit;
  while (results.size() < count && Clock::now() < deadline) {
    std::optional<v1::Result> result = client.Next(std::chrono::milliseconds(100));
    if (result) results.push_back(std::move(*result));
  }
  return results;
}

}  // namespace orcs::test_support
