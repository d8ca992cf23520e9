// orcs-view --broker ENDPOINT: the dashboard's source (docs/viewer.md, "Watching a broker"). One thread asks the
// broker for its status once per interval (net::StatusClient) — one request however many pages watch — keeps the
// newest answer for the pages' long polls and a bounded history of the totals for the throughput and queue charts.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <thread>

#include "net/status_client.h"

namespace orcs::viewer {

class BrokerWatch {
 public:
  /// One point of the charts: the broker's totals at one poll.
  struct Point {
    double time = 0;             ///< seconds since the watch started
    std::uint32_t workers = 0;   ///< registered workers
    std::uint32_t busy = 0;      ///< of them, holding a job
    std::uint64_t queued = 0;    ///< jobs waiting for a worker
    std::uint64_t running = 0;   ///< jobs held by workers
    std::uint64_t done = 0;      ///< jobs finished OK since the broker started
    std::uint64_t failed = 0;    ///< jobs finished otherwise
    double jobs_per_second = 0;  ///< over the broker's last minute
  };
  /// The newest poll.
  struct Snapshot {
    std::uint64_t serial = 0;  ///< counts polls, from 1; 0 = none yet
    double time = 0;           ///< seconds since the watch started
    std::string status_json;   ///< net::StatusJson of the answer; "" when the broker did not answer
    std::string error;         ///< why there is no answer ("no broker answering at ..."); "" when there is
  };
  /// The history keeps this many points (an hour at one poll a second).
  static constexpr std::size_t kHistoryPoints = 3600;

  /// Starts polling at once and then every `interval`.
  BrokerWatch(net::StatusClientOptions options, std::chrono::milliseconds interval);
  /// Stops the thread (within one poll's timeout).
  ~BrokerWatch();
  BrokerWatch(const BrokerWatch&) = delete;
  BrokerWatch& operator=(const BrokerWatch&) = delete;

  /// The newest snapshot once its serial is above `since`, waiting up to `wait` for one; the newest either way.
  Snapshot Wait(std::uint64_t since, std::chrono::milliseconds wait);
  /// The history, oldest first.
  std::deque<Point> History() const;
  const std::string& endpoint() const { return endpoint_; }

 private:
  void Poll(net::StatusClient& client);

  const std::string endpoint_;
  const std::chrono::milliseconds interval_;
  const std::chrono::steady_clock::time_point start_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  Snapshot latest_;          ///< guarded by mutex_
  std::deque<Point> history_;  ///< guarded by mutex_
  bool stopping_ = false;    ///< guarded by mutex_
  std::thread thread_;       ///< last: starts once everything above exists
};

}  // namespace orcs::viewer
