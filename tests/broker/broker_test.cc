// The broker with real sockets on 127.0.0.1: real WorkerConnections and BatchClients, and raw sockets for peers
// that misbehave (go silent, crash, send garbage).
#include "broker/broker.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

#include "proto/envelope.h"
#include "tests/broker/test_peers.h"

namespace orcs::test_support {
namespace {

using runtime::BatchClient;
using runtime::BatchClientError;
using broker::BrokerStats;
using std::chrono::milliseconds;
using ::testing::HasSubstr;

std::vector<v1::Job> MakeJobs(const std::string& prefix, int count, std::uint64_t first_seed = 0) {
  std::vector<v1::Job> jobs;
  for (int i = 0; i < count; ++i) jobs.push_back(MakeJob(prefix + std::to_string(i), first_seed + i));
  return jobs;
}

// Checks that `results` answer exactly the jobs `prefix`0..count-1 of batch `batch_id`, once each, as EchoWorker
// answers them.
void ExpectEachJobOnce(const std::vector<v1::Result>& results, const std::string& prefix, int count,
                       const std::string& batch_id, std::uint64_t first_seed = 0) {
  ASSERT_EQ(results.size(), static_cast<std::size_t>(count));
  std::set<std::string> ids;
  for (const v1::Result& result : results) {
    EXPECT_EQ(result.batch_id(), batch_id);
    EXPECT_EQ(result.status(), v1::Result::OK) << result.message();
    EXPECT_TRUE(ids.insert(result.job_id()).second) << "twice: " << result.job_id();
    const std::uint64_t seed = std::stoull(result.job_id().substr(prefix.size())) + first_seed;
    EXPECT_EQ(result.fitness(), 2.0 * static_cast<double>(seed) + 0.25) << result.job_id();
  }
  for (int i = 0; i < count; ++i) EXPECT_EQ(ids.count(prefix + std::to_string(i)), 1u) << prefix << i;
}

bool WorkersRegistered(BrokerThread& broker, int count) {
  return WaitFor([&] { return broker.stats().workers == count; });
}

TEST(Broker, FortyJobsOnTwoWorkersComeBackOnceEach) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  EchoWorker a(TestWorkerOptions(broker.worker_endpoint(), "a", 2, &log));
  EchoWorker b(TestWorkerOptions(broker.worker_endpoint(), "b", 2, &log));
  ASSERT_TRUE(WorkersRegistered(broker, 2));

  BatchClient client(TestClientOptions(broker.client_endpoint(), &log));
  client.Submit(MakeJobs("job-", 40));
  const std::vector<v1::Result> results = Collect(client, 40);
  ExpectEachJobOnce(results, "job-", 40, client.batch_id());
  EXPECT_EQ(client.outstanding(), 0u);
  EXPECT_EQ(client.Next(milliseconds(0)), std::nullopt);  // nothing outstanding: answers at once
  EXPECT_EQ(a.jobs_done() + b.jobs_done(), 40);
  EXPECT_GT(a.jobs_done(), 0);  // fair dispatch: both got work
  EXPECT_GT(b.jobs_done(), 0);
  for (const v1::Result& result : results) {
    EXPECT_EQ(result.attempts(), 1u);
    EXPECT_THAT(result.worker_id(), ::testing::AnyOf("a", "b"));
  }
  // The broker publishes its counters after sending: wait for them to catch up before reading them.
  ASSERT_TRUE(WaitFor([&] { return broker.stats().results_delivered == 40; }));
  const BrokerStats stats = broker.stats();
  EXPECT_EQ(stats.jobs_accepted, 40u);
  EXPECT_EQ(stats.jobs_dispatched, 40u);
  EXPECT_EQ(stats.results_delivered, 40u);
  EXPECT_EQ(stats.results_refused, 0u);
  EXPECT_EQ(stats.messages_dropped, 0u);
  EXPECT_EQ(client.stats().duplicates_dropped, 0u);

  // With every result in, the client stops heartbeating and the broker forgets it: routine, not a loss.
  ASSERT_TRUE(WaitFor([&] { return broker.stats().clients == 0; }));
  EXPECT_EQ(broker.stats().clients_lost, 0u);
  EXPECT_EQ(log.Count("forgotten (silent for 0.5 s, nothing pending)"), 1);
}

TEST(Broker, DispatchFillsEachWorkersCreditInTurnAndNoMore) {
  BrokerThread broker(TestBrokerOptions());
  // Connections whose jobs nobody takes: they hold what the broker sends them.
  worker::WorkerConnection a(TestWorkerOptions(broker.worker_endpoint(), "a", 3));
  ASSERT_TRUE(WorkersRegistered(broker, 1));
  worker::WorkerConnection b(TestWorkerOptions(broker.worker_endpoint(), "b", 3));
  ASSERT_TRUE(WorkersRegistered(broker, 2));

  BatchClient client(TestClientOptions(broker.client_endpoint()));
  client.Submit(MakeJobs("job-", 10));
  ASSERT_TRUE(WaitFor([&] { return a.stats().jobs_received == 3 && b.stats().jobs_received == 3; }));
  ASSERT_TRUE(WaitFor([&] { return broker.stats().in_flight == 6; }));
  const BrokerStats stats = broker.stats();
  EXPECT_EQ(stats.in_flight, 6u);
  EXPECT_EQ(stats.queued, 4u);
  // First in, first out, alternating between the workers: a (least recently served) gets jobs 0, 2, 4.
  std::vector<std::string> got_a;
  std::vector<std::string> got_b;
  for (int i = 0; i < 3; ++i) {
    got_a.push_back(a.NextJob(milliseconds(1000)).value().job_id());
    got_b.push_back(b.NextJob(milliseconds(1000)).value().job_id());
  }
  EXPECT_THAT(got_a, ::testing::ElementsAre("job-0", "job-2", "job-4"));
  EXPECT_THAT(got_b, ::testing::ElementsAre("job-1", "job-3", "job-5"));
  EXPECT_EQ(a.NextJob(milliseconds(0)), std::nullopt);

  // Each result frees one credit, and the next queued job follows.
  v1::Result result;
  result.set_job_id("job-0");
  result.set_batch_id(client.batch_id());
  result.set_status(v1::Result::OK);
  a.SendResult(result);
  EXPECT_EQ(a.NextJob(milliseconds(5000)).value().job_id(), "job-6");
  EXPECT_EQ(client.Next(milliseconds(5000)).value().job_id(), "job-0");
}

TEST(Broker, SilentWorkersJobsGoToAnotherWorkerAndArriveOnce) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  RawPeer silent(broker.worker_endpoint());
  silent.Send(ReadyMessage("silent", 4));
  ASSERT_TRUE(WorkersRegistered(broker, 1));

  BatchClient client(TestClientOptions(broker.client_endpoint()));
  client.Submit(MakeJobs("job-", 12));
  std::vector<v1::Job> held;  // the silent worker takes its credit's worth and then says nothing at all
  while (held.size() < 4) {
    std::optional<v1::BrokerToWorker> message = silent.ReceiveEnvelope<v1::BrokerToWorker>(milliseconds(5000));
    ASSERT_TRUE(message.has_value());
    if (message->has_job()) held.push_back(message->job());
  }
  EchoWorker rescuer(TestWorkerOptions(broker.worker_endpoint(), "rescuer", 2, &log));
  const std::vector<v1::Result> results = Collect(client, 12);
  ExpectEachJobOnce(results, "job-", 12, client.batch_id());
  EXPECT_EQ(rescuer.jobs_done(), 12);
  ASSERT_TRUE(WaitFor([&] { return broker.stats().results_delivered == 12; }));
  const BrokerStats stats = broker.stats();
  EXPECT_EQ(stats.workers_lost, 1u);
  EXPECT_EQ(stats.jobs_requeued, 4u);
  EXPECT_EQ(log.Count("worker silent lost: silent for 0.5 s; 4 jobs back to the queue"), 1);
  for (const v1::Result& result : results) {
    const bool was_held =
        std::any_of(held.begin(), held.end(), [&](const v1::Job& job) { return job.job_id() == result.job_id(); });
    EXPECT_EQ(result.attempts(), was_held ? 2u : 1u) << result.job_id();
    EXPECT_EQ(result.message(), was_held ? "attempt=1" : "attempt=0") << result.job_id();
  }

  // The silent worker wakes up and answers: too late, its lease is gone; the client sees nothing more.
  silent.Send(ResultMessage(held[0], "silent"));
  std::optional<v1::BrokerToWorker> reply = NextNonHeartbeat(silent);
  ASSERT_TRUE(reply.has_value());
  EXPECT_TRUE(reply->has_disconnect());  // "unknown worker: connect again"
  ASSERT_TRUE(WaitFor([&] { return broker.stats().results_refused == 1; }));
  EXPECT_EQ(broker.stats().results_delivered, 12u);
  EXPECT_EQ(client.Next(milliseconds(200)), std::nullopt);
  EXPECT_EQ(client.stats().duplicates_dropped, 0u);
}

TEST(Broker, WorkerWhoseConnectionClosesLosesItsJobsAtTheNextHeartbeat) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  RawPeer crashing(broker.worker_endpoint());
  crashing.Send(ReadyMessage("crashing", 2));
  ASSERT_TRUE(WorkersRegistered(broker, 1));
  BatchClient client(TestClientOptions(broker.client_endpoint()));
  client.Submit(MakeJobs("job-", 6));
  ASSERT_TRUE(AwaitJob(crashing).has_value());
  crashing.Close();  // no DISCONNECT: the process died
  ASSERT_TRUE(WaitFor([&] { return broker.stats().workers_lost == 1; }));
  EXPECT_EQ(log.Count("worker crashing lost: connection closed"), 1);
  EchoWorker rescuer(TestWorkerOptions(broker.worker_endpoint(), "rescuer", 2, &log));
  ExpectEachJobOnce(Collect(client, 6), "job-", 6, client.batch_id());
}

TEST(Broker, WorkerThatSaysGoodbyeGivesItsJobsBackWithoutALoss) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  BatchClient client(TestClientOptions(broker.client_endpoint()));
  {
    worker::WorkerConnection leaving(TestWorkerOptions(broker.worker_endpoint(), "leaving", 3, &log));
    client.Submit(MakeJobs("job-", 5));
    ASSERT_TRUE(WaitFor([&] { return leaving.stats().jobs_received == 3; }));
  }  // DISCONNECT
  ASSERT_TRUE(WaitFor([&] { return broker.stats().workers == 0; }));
  EXPECT_EQ(broker.stats().workers_lost, 0u);
  EXPECT_EQ(broker.stats().queued, 5u);
  EchoWorker staying(TestWorkerOptions(broker.worker_endpoint(), "staying", 2, &log));
  const std::vector<v1::Result> results = Collect(client, 5);
  ExpectEachJobOnce(results, "job-", 5, client.batch_id());
  for (const v1::Result& result : results) EXPECT_EQ(result.message(), "attempt=0");  // no loss counted
  EXPECT_EQ(log.Count("worker leaving left (worker shutting down); 3 jobs back to the queue"), 1);
}

TEST(Broker, JobThatLosesThreeWorkersFailsWithWorkerLost) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  BatchClient client(TestClientOptions(broker.client_endpoint()));
  std::vector<std::unique_ptr<RawPeer>> victims;
  for (int i = 0; i < 3; ++i) {
    victims.push_back(std::make_unique<RawPeer>(broker.worker_endpoint()));
    victims.back()->Send(ReadyMessage("victim-" + std::to_string(i), 1));
    ASSERT_TRUE(WorkersRegistered(broker, 1));
    if (i == 0) client.Submit({MakeJob("deadly", 7)});
    // It heartbeats until the job comes (after the previous victim is declared lost), then falls silent.
    std::optional<v1::Job> job = AwaitJob(*victims.back());
    ASSERT_TRUE(job.has_value());
    EXPECT_EQ(job->job_id(), "deadly");
    EXPECT_EQ(job->attempt(), static_cast<std::uint32_t>(i));
  }
  std::optional<v1::Result> result = client.Next(milliseconds(10000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->job_id(), "deadly");
  EXPECT_EQ(result->batch_id(), client.batch_id());
  EXPECT_EQ(result->status(), v1::Result::WORKER_LOST);
  EXPECT_EQ(result->attempts(), 3u);
  EXPECT_EQ(result->worker_id(), "victim-2");
  EXPECT_EQ(result->message(),
            "lost 3 workers while running (victim-0, victim-1, victim-2); the last one: silent for 0.5 s");
  EXPECT_TRUE(WaitFor([&] { return broker.stats().workers_lost == 3; }));
  EXPECT_EQ(client.outstanding(), 0u);
}

// What a sandboxed worker sends when the job's simulation process died.
v1::WorkerToBroker CrashedMessage(const v1::Job& job, const std::string& name) {
  v1::WorkerToBroker message = ResultMessage(job, name);
  message.mutable_result()->set_status(v1::Result::CRASHED);
  message.mutable_result()->set_fitness(0.0);
  message.mutable_result()->set_message("the simulation process died of SIGSEGV (Segmentation fault)");
  return message;
}

TEST(Broker, ACrashedJobGoesBackToTheFrontOfTheQueueInsteadOfToTheClient) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  RawPeer worker(broker.worker_endpoint());
  worker.Send(ReadyMessage("crashy", 1));
  ASSERT_TRUE(WorkersRegistered(broker, 1));
  BatchClient client(TestClientOptions(broker.client_endpoint()));
  client.Submit({MakeJob("fragile", 3), MakeJob("other", 4)});

  std::optional<v1::Job> first = AwaitJob(worker);
  ASSERT_TRUE(first.has_value());
  ASSERT_EQ(first->job_id(), "fragile");
  worker.Send(CrashedMessage(*first, "crashy"));
  std::optional<v1::Job> again = AwaitJob(worker);  // before "other": a crashed job is requeued at the front
  ASSERT_TRUE(again.has_value());
  EXPECT_EQ(again->job_id(), "fragile");
  EXPECT_FALSE(client.Next(milliseconds(0)).has_value()) << "the crash itself never reaches the client";
  worker.Send(ResultMessage(*again, "crashy"));

  std::optional<v1::Result> result = client.Next(milliseconds(10000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->job_id(), "fragile");
  EXPECT_EQ(result->status(), v1::Result::OK);
  EXPECT_EQ(result->attempts(), 2u);
  EXPECT_TRUE(WaitFor([&] { return broker.stats().crashes == 1; }));
  EXPECT_EQ(broker.stats().jobs_requeued, 1u);
  EXPECT_EQ(broker.stats().jobs_poisoned, 0u);
  EXPECT_EQ(log.Count("job " + client.batch_id() + "/fragile crashed worker crashy (the simulation process died of "
                      "SIGSEGV (Segmentation fault)); back to the front of the queue, crash 1 of 3"),
            1);
}

TEST(Broker, AJobThatCrashesThreeWorkersIsPoisonousAndNeverRetried) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  std::vector<std::unique_ptr<RawPeer>> workers;
  for (int i = 0; i < 3; ++i) {
    workers.push_back(std::make_unique<RawPeer>(broker.worker_endpoint()));
    workers.back()->Send(ReadyMessage("c" + std::to_string(i), 1));
    ASSERT_TRUE(WorkersRegistered(broker, i + 1));
  }
  BatchClient client(TestClientOptions(broker.client_endpoint()));
  client.Submit({MakeJob("poison", 9)});
  // The least recently served worker goes first: c0, then c1, then c2.
  for (int i = 0; i < 3; ++i) {
    std::optional<v1::Job> job = AwaitJob(*workers[i]);
    ASSERT_TRUE(job.has_value()) << "c" << i;
    EXPECT_EQ(job->job_id(), "poison");
    workers[i]->Send(CrashedMessage(*job, "c" + std::to_string(i)));
  }
  std::optional<v1::Result> result = client.Next(milliseconds(10000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->job_id(), "poison");
  EXPECT_EQ(result->status(), v1::Result::CRASHED);
  EXPECT_EQ(result->message(),
            "poisonous: crashed 3 workers (c0, c1, c2); the last: the simulation process died of SIGSEGV "
            "(Segmentation fault)");
  EXPECT_EQ(result->worker_id(), "c2");
  EXPECT_EQ(result->attempts(), 3u);
  EXPECT_TRUE(WaitFor([&] { return broker.stats().jobs_poisoned == 1; }));
  const BrokerStats stats = broker.stats();
  EXPECT_EQ(stats.crashes, 3u);
  EXPECT_EQ(stats.queued, 0u) << "never retried";
  EXPECT_EQ(stats.in_flight, 0u);
  EXPECT_EQ(stats.jobs_dispatched, 3u);
  EXPECT_EQ(log.Count("job " + client.batch_id() + "/poison poisonous: crashed 3 workers (c0, c1, c2); not retried"),
            1);
  EXPECT_EQ(client.outstanding(), 0u);
}

TEST(Broker, MaxCrashesOfOneFinishesAJobAtItsFirstCrash) {
  broker::BrokerOptions options = TestBrokerOptions();
  options.max_crashes = 1;
  BrokerThread broker(options);
  RawPeer worker(broker.worker_endpoint());
  worker.Send(ReadyMessage("only", 1));
  ASSERT_TRUE(WorkersRegistered(broker, 1));
  BatchClient client(TestClientOptions(broker.client_endpoint()));
  client.Submit({MakeJob("once", 1)});
  std::optional<v1::Job> job = AwaitJob(worker);
  ASSERT_TRUE(job.has_value());
  worker.Send(CrashedMessage(*job, "only"));
  std::optional<v1::Result> result = client.Next(milliseconds(10000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->status(), v1::Result::CRASHED);
  EXPECT_THAT(result->message(), HasSubstr("poisonous: crashed 1 workers (only)"));
  options.max_crashes = 0;
  EXPECT_THROW(broker::Broker{options}, std::invalid_argument);
}

TEST(Broker, LateResultFromALostWorkerIsRefusedAndTheJobRunsElsewhere) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  RawPeer slow(broker.worker_endpoint());
  slow.Send(ReadyMessage("slow", 1));
  ASSERT_TRUE(WorkersRegistered(broker, 1));
  BatchClient client(TestClientOptions(broker.client_endpoint()));
  client.Submit({MakeJob("job-0", 21)});
  std::optional<v1::Job> job = AwaitJob(slow);
  ASSERT_TRUE(job.has_value());
  EXPECT_NE(job->lease(), 0u) << "every dispatch is a lease with a token";
  ASSERT_TRUE(WaitFor([&] { return broker.stats().workers_lost == 1; }));  // silent: lost, its lease revoked
  EXPECT_EQ(broker.stats().queued, 1u);

  slow.Send(ResultMessage(*job, "slow"));  // it was only slow; but the job is no longer its to answer
  std::optional<v1::BrokerToWorker> reply = NextNonHeartbeat(slow);
  ASSERT_TRUE(reply.has_value());
  EXPECT_TRUE(reply->has_disconnect());
  ASSERT_TRUE(WaitFor([&] { return broker.stats().results_refused == 1; }));
  EXPECT_EQ(client.Next(milliseconds(0)), std::nullopt);
  EXPECT_EQ(log.Count("refused a result from a connection that never sent READY to this broker (a worker from "
                      "before a restart, or one whose jobs went elsewhere): job " +
                      client.batch_id() + "/job-0"),
            1);

  // A worker arriving now runs the job under a new lease, and its result is the one the client gets.
  EchoWorker next(TestWorkerOptions(broker.worker_endpoint(), "next", 2));
  std::optional<v1::Result> result = client.Next(milliseconds(5000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->fitness(), 42.25);
  EXPECT_EQ(result->worker_id(), "next");
  EXPECT_EQ(result->attempts(), 2u);
  EXPECT_EQ(next.jobs_done(), 1);
}

// A peer on the worker port forges results: without READY, for jobs queued but never dispatched, and — once
// registered — for a job leased to another worker and for its own job without the lease's token. None reaches the
// client; every job is answered once, by the worker that ran it.
TEST(Broker, ForgedResultsAreRefusedAndCounted) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  BatchClient client(TestClientOptions(broker.client_endpoint(), &log));
  client.Submit(MakeJobs("job-", 3));
  ASSERT_TRUE(WaitFor([&] { return broker.stats().queued == 3; }));

  RawPeer forger(broker.worker_endpoint());
  const auto forged = [&](const std::string& job_id, std::uint64_t lease) {
    v1::Job job = MakeJob(job_id, 0);
    job.set_batch_id(client.batch_id());
    job.set_lease(lease);
    v1::WorkerToBroker message = ResultMessage(job, "forger");
    message.mutable_result()->set_fitness(1e9);
    return message;
  };
  for (int i = 0; i < 3; ++i) forger.Send(forged("job-" + std::to_string(i), 0));
  ASSERT_TRUE(WaitFor([&] { return broker.stats().results_refused == 3; }));
  EXPECT_EQ(broker.stats().queued, 3u) << "nothing moved";

  // Registered, the forger draws job-0; an honest worker then takes the other two.
  forger.Send(ReadyMessage("forger", 1));
  std::optional<v1::Job> own = AwaitJob(forger);
  ASSERT_TRUE(own.has_value());
  EchoWorker honest(TestWorkerOptions(broker.worker_endpoint(), "honest", 2));
  forger.Send(forged(own->job_id(), own->lease() + 1));  // its own job, a wrong token
  forger.Send(forged("job-2", own->lease()));            // another worker's job
  ASSERT_TRUE(WaitFor([&] { return broker.stats().results_refused == 5; }));
  forger.Send(ResultMessage(*own, "forger"));  // the real answer to its lease is accepted

  const std::vector<v1::Result> results = Collect(client, 3);
  ExpectEachJobOnce(results, "job-", 3, client.batch_id());
  for (const v1::Result& result : results) EXPECT_NE(result.fitness(), 1e9);
  EXPECT_EQ(client.Next(milliseconds(200)), std::nullopt);
  EXPECT_EQ(broker.stats().results_refused, 5u);
  EXPECT_EQ(log.Count("refused a result"), 1) << "one line per peer: a flood of forgeries makes one line";
}

// A worker that heartbeats but never answers holds its job only until the lease's deadline: then it is lost, the
// job runs elsewhere, and the worker is told to start over.
TEST(Broker, AJobHeldPastItsLeaseGoesToAnotherWorker) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  RawPeer staller(broker.worker_endpoint());
  staller.Send(ReadyMessage("staller", 1));
  ASSERT_TRUE(WorkersRegistered(broker, 1));
  BatchClient client(TestClientOptions(broker.client_endpoint()));
  v1::Job job = MakeJob("job-0", 5);
  job.set_time_limit_seconds(0.2);  // lease: 1.5 × 0.2 s + 2 s + 0.5 s (liveness) = 2.8 s
  client.Submit({job});
  const auto taken = std::chrono::steady_clock::now();
  std::optional<v1::Job> held = AwaitJob(staller);
  ASSERT_TRUE(held.has_value());
  // It keeps heartbeating (so it is never "silent") until the broker gives up on its lease.
  std::optional<v1::BrokerToWorker> disconnect;
  while (!disconnect && std::chrono::steady_clock::now() - taken < std::chrono::seconds(10)) {
    std::optional<v1::BrokerToWorker> message = staller.ReceiveEnvelope<v1::BrokerToWorker>(kTestHeartbeat);
    if (message && message->has_disconnect()) disconnect = message;
    staller.Send(WorkerHeartbeat());
  }
  ASSERT_TRUE(disconnect.has_value()) << "the lease never expired";
  const double held_for = std::chrono::duration<double>(std::chrono::steady_clock::now() - taken).count();
  EXPECT_GE(held_for, 2.8 - 0.2);
  EXPECT_THAT(disconnect->disconnect().reason(), HasSubstr("held job " + client.batch_id() + "/job-0 past its lease"));
  // The stats are a snapshot the broker publishes after its loop pass, which may be after the DISCONNECT arrived.
  EXPECT_TRUE(WaitFor([&] { return broker.stats().leases_expired == 1u; }));
  EXPECT_EQ(log.Count("worker staller lost: held job " + client.batch_id() + "/job-0 past its lease (time limit 0.2 s, "
                      "leased for 2.8 s); 1 jobs back to the queue"),
            1);

  EchoWorker rescuer(TestWorkerOptions(broker.worker_endpoint(), "rescuer", 1));
  std::optional<v1::Result> result = client.Next(milliseconds(5000));
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->worker_id(), "rescuer");
  EXPECT_EQ(result->status(), v1::Result::OK);
  staller.Send(ResultMessage(*held, "staller"));  // too late: refused
  ASSERT_TRUE(WaitFor([&] { return broker.stats().results_refused == 1; }));
  EXPECT_EQ(client.Next(milliseconds(200)), std::nullopt);
}

// Ids a peer chooses are written to the log escaped, and bounded: no peer forges a log line or floods the log.
TEST(Broker, PeerChosenIdsCannotForgeOrFloodLogLines) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  RawPeer liar(broker.worker_endpoint());
  liar.Send(ReadyMessage("w1 joined\norcs-broker: worker admin joined with credit 1", 1));
  ASSERT_TRUE(WorkersRegistered(broker, 1));
  RawPeer flood(broker.worker_endpoint());
  flood.Send(ReadyMessage(std::string(1 << 20, 'x'), 1));
  ASSERT_TRUE(WaitFor([&] { return broker.stats().messages_dropped == 1; }));
  EXPECT_EQ(broker.stats().workers, 1) << "a 1 MB worker id is refused";
  for (const std::string& line : log.lines()) {
    EXPECT_EQ(line.find('\n'), std::string::npos) << line;
    EXPECT_LE(line.size(), 2100u);
  }
  EXPECT_EQ(log.Count("worker w1 joined\\x0aorcs-broker: worker admin joined with credit 1 joined with credit 1"), 1);
  EXPECT_EQ(log.Count("READY with a worker_id of 1048576 bytes (at most 128)"), 1);
}

TEST(Broker, TwoClientsWithInterleavedBatchesGetOnlyTheirOwnResults) {
  BrokerThread broker(TestBrokerOptions());
  EchoWorker a(TestWorkerOptions(broker.worker_endpoint(), "a", 2));
  EchoWorker b(TestWorkerOptions(broker.worker_endpoint(), "b", 2));
  BatchClient first(TestClientOptions(broker.client_endpoint()));
  BatchClient second(TestClientOptions(broker.client_endpoint()));
  ASSERT_NE(first.batch_id(), second.batch_id());
  // The same job ids in both batches, with different seeds: only the batch tells them apart.
  std::vector<v1::Job> first_jobs = MakeJobs("job-", 20, 0);
  std::vector<v1::Job> second_jobs = MakeJobs("job-", 20, 1000);
  for (int part = 0; part < 4; ++part) {
    first.Submit({first_jobs.begin() + part * 5, first_jobs.begin() + part * 5 + 5});
    second.Submit({second_jobs.begin() + part * 5, second_jobs.begin() + part * 5 + 5});
  }
  ExpectEachJobOnce(Collect(first, 20), "job-", 20, first.batch_id(), 0);
  ExpectEachJobOnce(Collect(second, 20), "job-", 20, second.batch_id(), 1000);
  EXPECT_TRUE(WaitFor([&] { return broker.stats().results_delivered == 40; }));
}

TEST(Broker, ClientThatLeavesTakesItsQueuedJobsWithIt) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  {
    BatchClient client(TestClientOptions(broker.client_endpoint()));
    client.Submit(MakeJobs("job-", 30));
    EXPECT_TRUE(WaitFor([&] { return broker.stats().queued == 30; }));
  }  // DISCONNECT
  ASSERT_TRUE(WaitFor([&] { return broker.stats().clients == 0; }));
  EXPECT_EQ(broker.stats().queued, 0u);
  EXPECT_EQ(broker.stats().batches, 0);
  EXPECT_EQ(log.Count("dropped its 30 pending jobs"), 1);
  EchoWorker idle(TestWorkerOptions(broker.worker_endpoint(), "idle", 2));
  ASSERT_TRUE(WorkersRegistered(broker, 1));
  EXPECT_EQ(broker.stats().jobs_dispatched, 0u);
}

// A silent client's batch waits for it through the grace period (docs/protocol.md, "Endings"), then goes with its
// jobs.
TEST(Broker, SilentClientIsDroppedWithItsJobsAfterTheGrace) {
  LogLines log;
  broker::BrokerOptions options = TestBrokerOptions(&log);
  options.client_grace = milliseconds(300);
  BrokerThread broker(options);
  RawPeer client(broker.client_endpoint());
  v1::ClientToBroker submit;
  submit.set_protocol_version(proto::kProtocolVersion);
  submit.mutable_submit()->set_batch_id("quiet-batch");
  submit.mutable_submit()->set_client_id("quiet");
  submit.mutable_submit()->set_owner_token(std::string(16, 'q'));
  for (int i = 0; i < 3; ++i) *submit.mutable_submit()->add_jobs() = MakeJob("job-" + std::to_string(i), i);
  client.Send(submit);
  std::optional<v1::BrokerToClient> answer = client.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(5000));
  ASSERT_TRUE(answer && answer->has_accepted());
  EXPECT_EQ(answer->accepted().job_count(), 3u);
  EXPECT_EQ(answer->accepted().queued(), 3u);
  ASSERT_TRUE(WaitFor([&] { return broker.stats().clients_lost == 1; }));  // it never heartbeats
  EXPECT_EQ(log.Count("client quiet lost (silent for 0.5 s); its 1 batches (3 pending jobs) wait 0.3 s"), 1);
  ASSERT_TRUE(WaitFor([&] { return broker.stats().batches == 0; }));
  EXPECT_EQ(broker.stats().queued, 0u);
  EXPECT_EQ(broker.stats().batches_unclaimed, 1u);
}

TEST(Broker, RejectsAMalformedSubmitWithAnErrorAndQueuesNothing) {
  BrokerThread broker(TestBrokerOptions());
  RawPeer client(broker.client_endpoint());
  const auto submit_with = [&](const std::function<void(v1::Submit&)>& spoil) {
    v1::ClientToBroker message;
    message.set_protocol_version(proto::kProtocolVersion);
    v1::Submit& submit = *message.mutable_submit();
    submit.set_batch_id("b");
    submit.set_client_id("c");
    submit.set_owner_token(std::string(16, 't'));
    *submit.add_jobs() = MakeJob("job-0", 0);
    *submit.add_jobs() = MakeJob("job-1", 1);
    spoil(submit);
    client.Send(message);
    std::optional<v1::BrokerToClient> answer = client.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(5000));
    return answer && answer->has_error() ? answer->error().message() : std::string("(no ERROR)");
  };
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.mutable_jobs(1)->clear_job_id(); }), "job 1: empty job_id");
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.mutable_jobs(1)->set_job_id("job-0"); }),
            "job 1 (id 'job-0'): job_id repeated within the SUBMIT");
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.mutable_jobs(0)->set_batch_id("other"); }),
            "job 0 (id 'job-0'): batch_id 'other' differs from the SUBMIT's 'b'");
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.mutable_jobs(0)->set_protocol_version(2); }),
            "job 0 (id 'job-0'): protocol_version 2 (expected 1)");
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.clear_batch_id(); }), "empty batch_id");
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.clear_client_id(); }), "empty client_id");
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.set_client_id(std::string(129, 'c')); }),
            "client_id longer than 128 bytes");
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.set_batch_id(std::string(129, 'b')); }), "batch_id longer than 128 bytes");
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.mutable_jobs(0)->set_job_id(std::string(257, 'j')); }),
            "job 0: job_id longer than 256 bytes");
  EXPECT_EQ(submit_with([](v1::Submit& s) { s.clear_owner_token(); }),
            "owner_token of 0 bytes (expected 16–64 random bytes; a client library from before leases and owner "
            "tokens?)");
  // The broker publishes its stats after it has answered: wait for the tenth rejection to show.
  EXPECT_TRUE(WaitFor([&] { return broker.stats().submits_rejected == 10u; }));
  EXPECT_EQ(broker.stats().queued, 0u);
  EXPECT_EQ(broker.stats().batches, 0);
  EXPECT_EQ(broker.stats().messages_dropped, 0u);
}

TEST(Broker, BatchOfAnotherClientCannotBeJoined) {
  BrokerThread broker(TestBrokerOptions());
  runtime::BatchClientOptions options = TestClientOptions(broker.client_endpoint());
  options.batch_id = "shared-name";
  BatchClient owner(options);
  owner.Submit({MakeJob("job-0", 0)});
  BatchClient intruder(options);
  try {
    intruder.Submit({MakeJob("job-1", 1)});
    FAIL() << "expected a BatchClientError";
  } catch (const BatchClientError& error) {
    EXPECT_THAT(error.what(), HasSubstr("rejected batch shared-name: batch 'shared-name' belongs to another client"));
  }
  EXPECT_THROW(intruder.Next(milliseconds(0)), BatchClientError);  // errors stay
  EXPECT_TRUE(WaitFor([&] { return broker.stats().queued == 1; }));
}

// Knowing a batch's id and its client's name is not enough: an empty SUBMIT naming them from another connection
// is refused, and the owner keeps its batch and its results.
TEST(Broker, AnEmptySubmitNamingAnotherClientsBatchCannotTakeItOver) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  BatchClient owner(TestClientOptions(broker.client_endpoint(), &log));
  owner.Submit(MakeJobs("job-", 4));
  EXPECT_EQ(owner.batch_id().size(), 32u) << "128 random bits as hex";
  EXPECT_EQ(owner.batch_id().find_first_not_of("0123456789abcdef"), std::string::npos);
  ASSERT_TRUE(WaitFor([&] { return broker.stats().queued == 4; }));

  RawPeer thief(broker.client_endpoint());
  v1::ClientToBroker message;
  message.set_protocol_version(proto::kProtocolVersion);
  v1::Submit& submit = *message.mutable_submit();
  submit.set_batch_id(owner.batch_id());  // read from the broker's log
  submit.set_client_id(owner.client_id());
  submit.set_owner_token(std::string(16, '\0'));
  thief.Send(message);
  std::optional<v1::BrokerToClient> answer = thief.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(5000));
  ASSERT_TRUE(answer.has_value());
  ASSERT_TRUE(answer->has_error());
  EXPECT_EQ(answer->error().message(), "batch '" + owner.batch_id() + "' belongs to another client");

  EchoWorker worker(TestWorkerOptions(broker.worker_endpoint(), "w", 2));
  ExpectEachJobOnce(Collect(owner, 4), "job-", 4, owner.batch_id());
  std::optional<v1::BrokerToClient> stolen = thief.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(200));
  EXPECT_FALSE(stolen.has_value() && stolen->has_result()) << "the thief received a result";
  EXPECT_EQ(broker.stats().submits_rejected, 1u);
}

TEST(Broker, GarbageWrongVersionsAndTruncatedMessagesAreDroppedAndTheBrokerKeepsServing) {
  LogLines log;
  BrokerThread broker(TestBrokerOptions(&log));
  RawPeer bad_worker(broker.worker_endpoint());
  RawPeer bad_client(broker.client_endpoint());

  std::mt19937 bytes(12345);  // seeded: the same garbage every run
  std::string garbage(200, '\0');
  for (char& c : garbage) c = static_cast<char>(bytes() & 0xff);
  v1::WorkerToBroker wrong_version = ReadyMessage("impostor", 2);
  wrong_version.set_protocol_version(7);
  const std::string ready = ReadyMessage("truncated", 2).SerializeAsString();
  v1::WorkerToBroker no_body;
  no_body.set_protocol_version(proto::kProtocolVersion);
  v1::WorkerToBroker old_result = ResultMessage(MakeJob("job-x", 1), "old");
  old_result.mutable_result()->set_protocol_version(0);

  int sent = 0;
  for (const std::vector<std::string>& frames : std::vector<std::vector<std::string>>{
           {garbage},
           {""},
           {"a", "b", "c"},
           {wrong_version.SerializeAsString()},
           {ready.substr(0, ready.size() - 3)},
           {no_body.SerializeAsString()},
           {ReadyMessage("greedy", 0).SerializeAsString()},
           {old_result.SerializeAsString()},
       }) {
    bad_worker.SendFrames(frames);
    ++sent;
  }
  v1::ClientToBroker wrong_client;
  wrong_client.set_protocol_version(99);
  wrong_client.mutable_heartbeat();
  v1::ClientToBroker submit;
  submit.set_protocol_version(proto::kProtocolVersion);
  submit.mutable_submit()->set_batch_id("b");
  submit.mutable_submit()->set_client_id("c");
  *submit.mutable_submit()->add_jobs() = MakeJob("job-0", 0);
  const std::string submit_bytes = submit.SerializeAsString();
  for (const std::string& frame : {garbage, wrong_client.SerializeAsString(), submit_bytes.substr(0, 20)}) {
    bad_client.SendFrames({frame});
    ++sent;
  }
  ASSERT_TRUE(WaitFor([&] { return broker.stats().messages_dropped == static_cast<std::uint64_t>(sent); }));
  EXPECT_EQ(broker.stats().workers, 0);  // none of it registered anybody
  EXPECT_EQ(broker.stats().batches, 0);
  EXPECT_EQ(log.Count("dropped a message from worker"), 1);  // logged once per peer
  EXPECT_EQ(log.Count("dropped a message from client"), 1);
  EXPECT_EQ(bad_client.Receive(milliseconds(100)), std::nullopt);  // and never answered

  EchoWorker worker(TestWorkerOptions(broker.worker_endpoint(), "good", 2));
  BatchClient client(TestClientOptions(broker.client_endpoint()));
  client.Submit(MakeJobs("job-", 5));
  ExpectEachJobOnce(Collect(client, 5), "job-", 5, client.batch_id());
}

TEST(Broker, StopSaysGoodbyeToWorkersWhichConnectAgain) {
  LogLines log;
  auto broker = std::make_unique<BrokerThread>(TestBrokerOptions(&log));
  worker::WorkerConnection connection(TestWorkerOptions(broker->worker_endpoint(), "w", 2, &log));
  ASSERT_TRUE(WaitFor([&] { return connection.stats().broker_answering; }));
  broker->Stop();
  ASSERT_TRUE(WaitFor([&] { return connection.stats().connections >= 2; }));
  EXPECT_EQ(log.Count("said goodbye (broker shutting down); connecting again"), 1);
  EXPECT_EQ(log.Count("stopped: told 1 workers and 0 clients"), 1);
}

TEST(Broker, BadOptionsAndBusyPortsAreReportedAtConstruction) {
  broker::BrokerOptions options = TestBrokerOptions();
  options.liveness = 1;
  EXPECT_THROW(broker::Broker{options}, std::invalid_argument);
  BrokerThread first(TestBrokerOptions());
  options = TestBrokerOptions();
  const std::string endpoint = first.client_endpoint();
  options.client_port = std::stoi(endpoint.substr(endpoint.rfind(':') + 1));
  try {
    broker::Broker second(options);
    FAIL() << "expected the port to be busy";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr("cannot bind the client socket to " + endpoint + ": Address already in use"));
  }
}

}  // namespace
}  // namespace orcs::test_support
