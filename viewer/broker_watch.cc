#include "viewer/broker_watch.h"

#include <exception>

namespace orcs::viewer {

BrokerWatch::BrokerWatch(net::StatusClientOptions options, std::chrono::milliseconds interval)
    : endpoint_(options.endpoint), interval_(interval), start_(std::chrono::steady_clock::now()) {
  auto client = std::make_shared<net::StatusClient>(std::move(options));  // checks the endpoint and keys now
  thread_ = std::thread([this, client] {
    std::unique_lock lock(mutex_);
    while (!stopping_) {
      lock.unlock();
      Poll(*client);
      lock.lock();
      changed_.wait_for(lock, interval_, [this] { return stopping_; });
    }
  });
}

BrokerWatch::~BrokerWatch() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void BrokerWatch::Poll(net::StatusClient& client) {
  Snapshot snapshot;
  Point point;
  bool answered = false;
  try {
    const v1::Status status = client.Fetch();
    snapshot.status_json = net::StatusJson(status);
    point = {0, status.workers(), status.busy_workers(), status.queued(), status.running(), status.done(),
             status.failed(), status.jobs_per_second()};
    answered = true;
  } catch (const std::exception& error) {  // no answer in time: say so, and ask again next time
    snapshot.error = error.what();
  }
  const double now = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::lock_guard lock(mutex_);
  snapshot.serial = latest_.serial + 1;
  snapshot.time = now;
  latest_ = std::move(snapshot);
  if (answered) {
    point.time = now;
    history_.push_back(point);
    if (history_.size() > kHistoryPoints) history_.pop_front();
  }
  changed_.notify_all();
}

BrokerWatch::Snapshot BrokerWatch::Wait(std::uint64_t since, std::chrono::milliseconds wait) {
  std::unique_lock lock(mutex_);
  changed_.wait_for(lock, wait, [&] { return latest_.serial > since || stopping_; });
  return latest_;
}

std::deque<BrokerWatch::Point> BrokerWatch::History() const {
  std::lock_guard lock(mutex_);
  return history_;
}

}  // namespace orcs::viewer
