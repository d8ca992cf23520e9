// The broker's rules on their own: BrokerCore fed decoded messages and a made-up clock, its messages caught by a
// recording transport. No sockets, no threads, no sleeps — each test runs in microseconds. The same rules are
// exercised end to end, over real sockets, in broker_test.cc.
#include "broker/broker_core.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "proto/envelope.h"
#include "tests/broker/core_harness.h"
#include "tests/broker/recording_transport.h"

namespace orcs::test_support {
namespace {

using broker::BrokerCore;
using proto::kProtocolVersion;
using std::chrono::milliseconds;
using std::chrono::seconds;
using ::testing::HasSubstr;

class BrokerCoreTest : public ::testing::Test, protected Harness {};

TEST_F(BrokerCoreTest, SubmitIsAcceptedAndQueuedJobsFillTheWorkersCreditAndNoMore) {
  Submit("c", "b", {Job("j0"), Job("j1"), Job("j2")});
  const v1::BrokerToClient accepted = transport_.LastToClient("c");
  ASSERT_TRUE(accepted.has_accepted());
  EXPECT_EQ(accepted.accepted().job_count(), 3u);
  EXPECT_EQ(accepted.accepted().queued(), 3u);
  Ready("w", 2);
  Dispatch();
  const std::vector<v1::Job> jobs = transport_.Jobs("w");
  ASSERT_EQ(jobs.size(), 2u);
  EXPECT_EQ(jobs[0].job_id(), "j0");  // in submission order
  EXPECT_EQ(jobs[1].job_id(), "j1");
  EXPECT_NE(jobs[0].lease(), 0u);
  EXPECT_NE(jobs[0].lease(), jobs[1].lease());
  EXPECT_EQ(jobs[0].batch_id(), "b");
  EXPECT_EQ(Stats().queued, 1u);
  EXPECT_EQ(Stats().in_flight, 2u);
  EXPECT_EQ(Stats().jobs_dispatched, 2u);
}

TEST_F(BrokerCoreTest, JobsGoToTheLeastRecentlyServedWorkerFirst) {
  Submit("c", "b", {Job("j0"), Job("j1"), Job("j2"), Job("j3")});
  Ready("w1", 2);
  Ready("w2", 2);
  Dispatch();
  std::vector<std::string> order;
  for (const auto& [worker, message] : transport_.to_workers) order.push_back(worker + ":" + message.job().job_id());
  EXPECT_THAT(order, ::testing::ElementsAre("w1:j0", "w2:j1", "w1:j2", "w2:j3"));
}

TEST_F(BrokerCoreTest, AResultWithoutAStatusIsDeliveredAsInternalError) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  Answer("w", transport_.Jobs("w").at(0), v1::Result::STATUS_UNSPECIFIED);
  ASSERT_EQ(transport_.Results("c").size(), 1u);
  EXPECT_EQ(transport_.Results("c")[0].status(), v1::Result::INTERNAL_ERROR);
  EXPECT_EQ(transport_.Results("c")[0].message(), "the worker sent a result without a status");
}

TEST_F(BrokerCoreTest, AResultFromTheLeaseHolderReachesTheClientOnceAndFreesACredit) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  const v1::Job j0 = transport_.Jobs("w").at(0);
  Advance(seconds(2));
  Answer("w", j0);
  Answer("w", j0);  // a duplicate: the job is forgotten, so it is refused
  const std::vector<v1::Result> results = transport_.Results("c");
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].job_id(), "j0");
  EXPECT_EQ(results[0].worker_id(), "w-name");
  EXPECT_EQ(results[0].attempts(), 1u);
  EXPECT_EQ(Stats().results_delivered, 1u);
  EXPECT_EQ(Stats().results_refused, 1u);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 2u);  // the credit came back: j1 goes out
}

TEST_F(BrokerCoreTest, AResultWithoutTheLeaseTokenOrFromAnotherConnectionIsRefused) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Ready("other", 1);
  Dispatch();
  v1::Job job = transport_.Jobs("w").at(0);
  Answer("other", job);
  Answer("stranger", job);
  job.set_lease(job.lease() + 1);
  Answer("w", job);
  EXPECT_TRUE(transport_.Results("c").empty());
  EXPECT_EQ(Stats().results_refused, 3u);
  // The stranger never sent READY: it is told to start over.
  ASSERT_EQ(transport_.Disconnects("stranger").size(), 1u);
  EXPECT_THAT(transport_.Disconnects("stranger")[0], HasSubstr("unknown worker"));
}

TEST_F(BrokerCoreTest, ASecondReadyChangesTheCreditAndJobsHeldBeyondItStayHeld) {
  Submit("c", "b", {Job("j0"), Job("j1"), Job("j2"), Job("j3")});
  Ready("w", 1);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 1u);
  Ready("w", 3);  // more credit: two more jobs
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 3u);
  Ready("w", 1);  // less credit: the three stay held, and no new job until it holds fewer than one
  Answer("w", transport_.Jobs("w")[0]);
  Answer("w", transport_.Jobs("w")[1]);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 3u);
  Answer("w", transport_.Jobs("w")[2]);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 4u);
  EXPECT_TRUE(Logged("sent READY again; credit now 1"));
}

TEST_F(BrokerCoreTest, ReadyWithCreditOutsideItsBoundsIsDropped) {
  Ready("w", 0);
  Ready("v", 1025);
  EXPECT_EQ(Stats().workers, 0);
  EXPECT_EQ(Stats().messages_dropped, 2u);
}

TEST_F(BrokerCoreTest, AWorkerLostMidJobPutsItsJobBackAtTheFrontAndItsLateResultIsRefused) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  const v1::Job held = transport_.Jobs("w").at(0);
  Advance(seconds(4));
  ClientHeartbeat("c");  // the client stays; the worker says nothing
  Advance(seconds(1));   // silent for the liveness period: 5 heartbeats of 1 s
  Tick();
  EXPECT_EQ(Stats().workers_lost, 1u);
  EXPECT_EQ(Stats().jobs_requeued, 1u);
  EXPECT_EQ(Stats().in_flight, 0u);
  EXPECT_TRUE(Logged("worker w-name lost: silent for 5.0 s; 1 jobs back to the queue"));
  Ready("v", 1);
  Dispatch();
  ASSERT_EQ(transport_.Jobs("v").size(), 1u);
  EXPECT_EQ(transport_.Jobs("v")[0].job_id(), "j0");  // ahead of j1, which never left the queue
  EXPECT_EQ(transport_.Jobs("v")[0].attempt(), 1u);   // one worker lost on it
  Answer("w", held);                                   // the lost worker comes back late
  EXPECT_TRUE(transport_.Results("c").empty());
  EXPECT_EQ(Stats().results_refused, 1u);
}

TEST_F(BrokerCoreTest, AWorkerThatSaysGoodbyeGivesItsJobsBackWithoutALoss) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  v1::WorkerToBroker bye;
  bye.set_protocol_version(kProtocolVersion);
  bye.mutable_disconnect()->set_reason("done");
  core_.OnWorkerMessage("w", bye, now_);
  EXPECT_EQ(Stats().workers_lost, 0u);
  EXPECT_EQ(Stats().jobs_requeued, 1u);
  Ready("v", 1);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("v").at(0).attempt(), 0u);
}

TEST_F(BrokerCoreTest, ACrashedJobIsRetriedOnAWorkerItHasNotCrashedAndIsPoisonousAtTheThirdCrash) {
  Submit("c", "b", {Job("j0")});
  Ready("w1", 1);
  Ready("w2", 1);
  Ready("w3", 1);
  Dispatch();
  Answer("w1", transport_.Jobs("w1").at(0), v1::Result::CRASHED, "segfault");
  EXPECT_TRUE(transport_.Results("c").empty());  // retried, not answered
  EXPECT_EQ(Stats().crashes, 1u);
  EXPECT_EQ(Stats().jobs_requeued, 1u);
  Dispatch();  // w1 is ready again, and first in line, but the job crashed it
  EXPECT_EQ(transport_.Jobs("w1").size(), 1u);
  ASSERT_EQ(transport_.Jobs("w2").size(), 1u);
  Answer("w2", transport_.Jobs("w2").at(0), v1::Result::CRASHED, "abort");
  Dispatch();
  ASSERT_EQ(transport_.Jobs("w3").size(), 1u);
  Answer("w3", transport_.Jobs("w3").at(0), v1::Result::CRASHED, "killed");
  const std::vector<v1::Result> results = transport_.Results("c");
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].status(), v1::Result::CRASHED);
  EXPECT_EQ(results[0].message(), "poisonous: crashed 3 workers (w1-name, w2-name, w3-name); the last: killed");
  EXPECT_EQ(Stats().jobs_poisoned, 1u);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w1").size(), 1u);  // never retried
}

TEST_F(BrokerCoreTest, ACrashedJobWaitsWhileOnlyWorkersItCrashedAreReady) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w1", 1);
  Ready("w2", 1);
  Dispatch();  // j0 to w1, j1 to w2
  Answer("w1", transport_.Jobs("w1").at(0), v1::Result::CRASHED, "segfault");
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w1").size(), 1u);  // only w1 is free, and j0 crashed it: j0 waits for w2
  EXPECT_EQ(Stats().queued, 1u);
  Answer("w2", transport_.Jobs("w2").at(0));
  Dispatch();
  ASSERT_EQ(transport_.Jobs("w2").size(), 2u);
  EXPECT_EQ(transport_.Jobs("w2")[1].job_id(), "j0");
}

TEST_F(BrokerCoreTest, AWorkerHoldingAJobPastItsLeaseIsLostAndToldToStartOver) {
  Submit("c", "b", {Job("j0", 1.0)});
  Ready("w", 1);
  Dispatch();
  // The lease: 1 s × 1.5 + 2 s + the liveness period of 5 s = 8.5 s. The worker heartbeats all along.
  PassSecondsWithEveryoneAlive(8);
  EXPECT_EQ(Stats().leases_expired, 0u);
  PassSecondsWithEveryoneAlive(1);
  EXPECT_EQ(Stats().leases_expired, 1u);
  EXPECT_EQ(Stats().workers_lost, 1u);
  ASSERT_EQ(transport_.Disconnects("w").size(), 1u);
  EXPECT_THAT(transport_.Disconnects("w")[0],
              HasSubstr("held job b/j0 past its lease (time limit 1.0 s, leased for 8.5 s): connect again"));
  Ready("v", 1);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("v").size(), 1u);
}

// A worker runs its jobs one after another, so the lease of its second job starts where the first one's ends.
TEST_F(BrokerCoreTest, TheLeasesOfAWorkersJobsFollowOneAnother) {
  Submit("c", "b", {Job("j0", 1.0), Job("j1", 1.0)});
  Ready("w", 2);
  Dispatch();
  Advance(seconds(1));
  Answer("w", transport_.Jobs("w").at(0));
  // j1's lease: 8.5 s after j0's, which ended 8.5 s after dispatch — due 17 s after dispatch, not 8.5 s.
  PassSecondsWithEveryoneAlive(15);
  EXPECT_EQ(Stats().leases_expired, 0u);
  PassSecondsWithEveryoneAlive(1);
  EXPECT_EQ(Stats().leases_expired, 1u);
}

TEST_F(BrokerCoreTest, ABatchIsDoneWhenEveryJobIsAnsweredAndGoesWithItsClient) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 2);
  Dispatch();
  for (const v1::Job& job : transport_.Jobs("w")) Answer("w", job);
  EXPECT_EQ(transport_.Results("c").size(), 2u);
  EXPECT_EQ(Stats().jobs_held, 0u);  // finished jobs are forgotten at once
  EXPECT_EQ(Stats().jobs_held_peak, 2u);
  EXPECT_EQ(Stats().batches, 1);
  v1::ClientToBroker bye;
  bye.mutable_disconnect()->set_reason("finished");
  ClientSays("c", bye);
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().clients, 0);
  EXPECT_TRUE(Logged("client c-name left (finished)"));
}

TEST_F(BrokerCoreTest, ACancelledBatchsQueuedJobsAreNeverDispatched) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  v1::ClientToBroker cancel;
  cancel.mutable_cancel()->set_batch_id("b");
  ClientSays("c", cancel);
  Ready("w", 2);
  Dispatch();
  EXPECT_TRUE(transport_.Jobs("w").empty());
  EXPECT_EQ(Stats().queued, 0u);
  EXPECT_EQ(Stats().batches, 0);
}

TEST_F(BrokerCoreTest, ASubmitToAnotherClientsBatchIsAnsweredWithError) {
  Submit("c", "b", {Job("j0")});
  Submit("intruder", "b", {Job("j1")}, std::string(16, '\x07'));
  const v1::BrokerToClient reply = transport_.LastToClient("intruder");
  ASSERT_TRUE(reply.has_error());
  EXPECT_EQ(reply.error().message(), "batch 'b' belongs to another client");
  EXPECT_EQ(Stats().submits_rejected, 1u);
  EXPECT_EQ(Stats().queued, 1u);
}

TEST_F(BrokerCoreTest, AFailedSendOfAJobLosesTheWorkerButNotTheJob) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  transport_.gone.insert("w");
  Dispatch();
  EXPECT_EQ(Stats().workers_lost, 1u);
  EXPECT_EQ(Stats().jobs_dispatched, 0u);
  EXPECT_EQ(Stats().queued, 1u);
  Ready("v", 1);
  Dispatch();
  ASSERT_EQ(transport_.Jobs("v").size(), 1u);
  EXPECT_EQ(transport_.Jobs("v")[0].attempt(), 0u);  // it never reached w: no loss counted for the job
}

TEST_F(BrokerCoreTest, AFailedHeartbeatToAClientDropsItAndItsPendingJobs) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  transport_.gone.insert("c");
  Advance(seconds(1));
  Tick();
  EXPECT_EQ(Stats().clients, 0);
  EXPECT_EQ(Stats().clients_lost, 1u);
  EXPECT_EQ(Stats().queued, 0u);
  EXPECT_TRUE(Logged("client c-name lost (connection closed); dropped its 2 pending jobs"));
}

TEST_F(BrokerCoreTest, AResultThatCannotBeSentIsNotCountedAsDelivered) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  transport_.gone.insert("c");
  Answer("w", transport_.Jobs("w").at(0));
  EXPECT_EQ(Stats().results_delivered, 0u);
  EXPECT_EQ(Stats().jobs_held, 0u);
}

TEST_F(BrokerCoreTest, ASilentClientIsDroppedAfterItsLivenessPeriod) {
  Submit("c", "b", {Job("j0")});
  Advance(seconds(4));
  Tick();
  EXPECT_EQ(Stats().clients, 1);
  Advance(seconds(1));
  Tick();
  EXPECT_EQ(Stats().clients, 0);
  EXPECT_EQ(Stats().clients_lost, 1u);
}

// Peers at another pace than the broker (issue found with `orcs-broker --heartbeat 0.1` and clients left at
// 1 s: the broker dropped the client every 0.5 s, and the client submitted its batch again, for ever).
class BrokerCoreFastTest : public ::testing::Test, protected Harness {
 protected:
  BrokerCoreFastTest() : Harness(nullptr, false, milliseconds(100)) {}
};

TEST_F(BrokerCoreFastTest, AClientSlowerThanTheBrokerIsWaitedForAtItsOwnPace) {
  Declare(1000);
  Submit("c", "b", {Job("j0")});
  Advance(milliseconds(900));  // longer than the broker's own 0.5 s liveness, shorter than the client's 1 s beat
  Tick();
  EXPECT_EQ(Stats().clients, 1);
  ClientHeartbeat("c");
  Advance(milliseconds(4900));
  Tick();
  EXPECT_EQ(Stats().clients, 1);
  Advance(milliseconds(100));  // five of its heartbeats missed
  Tick();
  EXPECT_EQ(Stats().clients, 0);
  EXPECT_TRUE(Logged("lost (silent for 5.0 s)"));
}

TEST_F(BrokerCoreFastTest, APeerThatDoesNotSayItsPaceIsHeldToTheBrokers) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Advance(milliseconds(500));
  Tick();
  EXPECT_EQ(Stats().clients, 0);
  EXPECT_EQ(Stats().workers_lost, 1u);
}

TEST_F(BrokerCoreFastTest, AWorkersDeclaredPaceCountsUpToAMinute) {
  Declare(1000);
  Ready("w", 1);
  Declare(3'600'000);  // an hour: capped, or a dead worker would keep its jobs for five hours
  Ready("v", 1);
  Advance(milliseconds(4900));
  Tick();
  EXPECT_EQ(Stats().workers, 2);
  Advance(milliseconds(200));
  Tick();
  EXPECT_EQ(Stats().workers, 1);  // w: five of its 1 s heartbeats missed
  Advance(seconds(294));
  Tick();
  EXPECT_EQ(Stats().workers, 1);
  Advance(seconds(1));  // v: 5 × 60 s
  Tick();
  EXPECT_EQ(Stats().workers, 0);
}

TEST_F(BrokerCoreFastTest, TheBrokersHeartbeatsSayItsPace) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Advance(milliseconds(100));
  Tick();
  EXPECT_EQ(transport_.LastToClient("c").heartbeat().interval_ms(), 100u);
  EXPECT_EQ(transport_.LastToWorker("w").heartbeat().interval_ms(), 100u);
}

// ---------------------------------------------------------------------------------------------------------------
// Status (broker_core_status.cc)

const v1::WorkerStatus* FindWorker(const v1::Status& status, const std::string& name) {
  for (const v1::WorkerStatus& worker : status.worker_list()) {
    if (worker.worker_id() == name) return &worker;
  }
  return nullptr;
}

TEST_F(BrokerCoreTest, TheStatusFollowsWorkersJobsAndTheBatchAsTheyMove) {
  Submit("c", "b", {Job("j0"), Job("j1"), Job("j2"), Job("j3"), Job("j4")}, kToken, 6);
  Ready("w", 2, "node1");
  Ready("w2", 1);
  Dispatch();
  Advance(seconds(3));
  v1::Status status = AskStatus("asker");
  EXPECT_EQ(status.workers(), 2u);
  EXPECT_EQ(status.busy_workers(), 2u);
  EXPECT_EQ(status.clients(), 1u);  // the asker is not registered as a client
  EXPECT_EQ(status.queued(), 2u);
  EXPECT_EQ(status.running(), 3u);
  const v1::WorkerStatus* w = FindWorker(status, "w-name");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->host(), "node1");
  EXPECT_EQ(w->current_batch_id(), "b");
  EXPECT_EQ(w->current_job_id(), "j0");
  EXPECT_DOUBLE_EQ(w->current_seconds(), 3.0);
  EXPECT_EQ(w->holding(), 2u);
  EXPECT_EQ(w->credit(), 2u);
  EXPECT_DOUBLE_EQ(w->last_heard_seconds(), 3.0);
  ASSERT_EQ(status.batch_list_size(), 1);
  EXPECT_EQ(status.batch_list(0).batch_id(), "b");
  EXPECT_EQ(status.batch_list(0).client_id(), "c-name");
  EXPECT_EQ(status.batch_list(0).queued(), 2u);
  EXPECT_EQ(status.batch_list(0).running(), 3u);
  EXPECT_EQ(status.batch_list(0).expected(), 6u);
  EXPECT_DOUBLE_EQ(status.batch_list(0).seconds_left(), -1.0);  // nothing finished yet: no rate

  const std::vector<v1::Job> jobs = transport_.Jobs("w");
  Answer("w", jobs.at(0));
  Answer("w", jobs.at(1), v1::Result::TIMEOUT, "ran past its time limit");
  status = AskStatus("asker");
  EXPECT_EQ(status.done(), 1u);
  EXPECT_EQ(status.failed(), 1u);
  const v1::BatchStatus& batch = status.batch_list(0);
  EXPECT_EQ(batch.done(), 1u);
  EXPECT_EQ(batch.failed(), 1u);
  EXPECT_DOUBLE_EQ(batch.jobs_per_second(), 2.0);  // two in the first second
  EXPECT_DOUBLE_EQ(batch.seconds_left(), 2.0);     // (6 − 2) jobs at 2 jobs/s
  ASSERT_EQ(batch.recent_failures_size(), 1);
  EXPECT_EQ(batch.recent_failures(0).job_id(), "j2");  // w was given j0 and j2, w2 j1
  EXPECT_EQ(batch.recent_failures(0).status(), v1::Result::TIMEOUT);
  EXPECT_EQ(batch.recent_failures(0).message(), "ran past its time limit");
  EXPECT_EQ(batch.recent_failures(0).worker_id(), "w-name");
  w = FindWorker(status, "w-name");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->jobs_done(), 2u);
  ASSERT_EQ(w->recent_jobs_size(), 2);
  EXPECT_EQ(w->recent_jobs(0).job_id(), "j2");  // newest first
  EXPECT_EQ(w->recent_jobs(1).job_id(), "j0");
  EXPECT_DOUBLE_EQ(w->recent_jobs(1).seconds(), 3.0);
  EXPECT_FALSE(w->busy());
}

// A silent client's batch claimed back from a new connection: the job a worker runs is still that batch's (it was
// neither dropped nor revoked), and the status shows it running there, not queued again.
TEST_F(BrokerCoreTest, TheStatusShowsAReclaimedBatchsJobStillRunningOnItsWorker) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  PassSecondsWithTheClientSilent(5);
  ASSERT_EQ(Stats().clients, 0);  // the client went silent: its connection is forgotten, its batch waits for it
  Submit("c2", "b", {Job("j0")});
  const v1::Status status = AskStatus("asker");
  const v1::WorkerStatus* worker = FindWorker(status, "w-name");
  ASSERT_NE(worker, nullptr);
  EXPECT_EQ(worker->holding(), 1u);
  EXPECT_EQ(worker->current_job_id(), "j0");
  ASSERT_EQ(status.batch_list_size(), 1);
  EXPECT_EQ(status.batch_list(0).queued(), 0u);
  EXPECT_EQ(status.batch_list(0).running(), 1u);
  EXPECT_EQ(Stats().jobs_dispatched, 1u);  // not run twice
}

TEST_F(BrokerCoreTest, TheStatusForgetsALostWorkerAndCountsIt) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Ready("quiet", 1);
  Dispatch();
  PassSecondsWithEveryoneAlive(6);  // "quiet" never heartbeats
  const v1::Status status = AskStatus("asker");
  EXPECT_EQ(status.workers(), 1u);
  EXPECT_EQ(FindWorker(status, "quiet-name"), nullptr);
  EXPECT_EQ(status.workers_lost(), 1u);
  EXPECT_EQ(status.batch_list(0).queued() + status.batch_list(0).running(), 2u);
}

TEST_F(BrokerCoreTest, ACrashedJobCountsOnTheWorkerItCrashed) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  Answer("w", transport_.Jobs("w").at(0), v1::Result::CRASHED, "SIGSEGV");
  const v1::WorkerStatus* w = FindWorker(AskStatus("asker"), "w-name");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->crashes(), 1u);
  EXPECT_EQ(AskStatus("asker").crashes(), 1u);
}

class BrokerCoreCurveTest : public ::testing::Test, protected Harness {
 protected:
  BrokerCoreCurveTest() : Harness(nullptr, true) {}
};

TEST_F(BrokerCoreCurveTest, OnlyTheOwnersKeySeesABatchsNamesJobsAndFailures) {
  Submit("c", "b", {Job("j0"), Job("j1")}, kToken, 0, "owner-key");
  Ready("w", 1);
  Dispatch();
  Answer("w", transport_.Jobs("w").at(0), v1::Result::TIMEOUT, "secret detail");
  Dispatch();
  const v1::Status stranger = AskStatus("asker", "stranger-key");
  ASSERT_EQ(stranger.batch_list_size(), 1);
  EXPECT_TRUE(stranger.batch_list(0).hidden());
  EXPECT_EQ(stranger.batch_list(0).batch_id(), "");
  EXPECT_EQ(stranger.batch_list(0).client_id(), "");
  EXPECT_EQ(stranger.batch_list(0).recent_failures_size(), 0);
  EXPECT_EQ(stranger.batch_list(0).failed(), 1u);  // counts are everyone's
  EXPECT_EQ(stranger.batch_list(0).running(), 1u);
  EXPECT_EQ(stranger.worker_list(0).current_job_id(), "");
  EXPECT_TRUE(stranger.worker_list(0).busy());
  EXPECT_EQ(stranger.worker_list(0).recent_jobs(0).job_id(), "");
  EXPECT_EQ(stranger.worker_list(0).recent_jobs(0).status(), v1::Result::TIMEOUT);

  const v1::Status owner = AskStatus("asker2", "owner-key");
  EXPECT_FALSE(owner.batch_list(0).hidden());
  EXPECT_EQ(owner.batch_list(0).batch_id(), "b");
  EXPECT_EQ(owner.batch_list(0).recent_failures(0).message(), "secret detail");
  EXPECT_EQ(owner.worker_list(0).current_job_id(), "j1");
  EXPECT_EQ(owner.worker_list(0).recent_jobs(0).job_id(), "j0");
}

// ---------------------------------------------------------------------------------------------------------------
// Endings (issue 47): a batch that ends early frees its workers at once; a silent client gets a grace period.

namespace endings {

// The leases a REVOKE to `worker` named, over every REVOKE it got.
std::set<std::uint64_t> RevokedLeases(const RecordingTransport& transport, const std::string& worker) {
  std::set<std::uint64_t> leases;
  for (const auto& [peer, message] : transport.to_workers) {
    if (peer == worker && message.has_revoke()) leases.insert(message.revoke().leases().begin(),
                                                               message.revoke().leases().end());
  }
  return leases;
}

std::set<std::uint64_t> LeasesOf(const std::vector<v1::Job>& jobs) {
  std::set<std::uint64_t> leases;
  for (const v1::Job& job : jobs) leases.insert(job.lease());
  return leases;
}

}  // namespace endings

TEST_F(BrokerCoreTest, ACancelledBatchsRunningJobsAreRevokedAndTheirCreditServesTheNextBatchAtOnce) {
  Submit("c", "b", {Job("j0"), Job("j1"), Job("j2")});
  Ready("w", 2);
  Dispatch();
  const std::vector<v1::Job> held = transport_.Jobs("w");
  ASSERT_EQ(held.size(), 2u);
  v1::ClientToBroker cancel;
  cancel.mutable_cancel()->set_batch_id("b");
  ClientSays("c", cancel);
  EXPECT_EQ(endings::RevokedLeases(transport_, "w"), endings::LeasesOf(held));
  EXPECT_THAT(transport_.LastToWorker("w").revoke().reason(), HasSubstr("batch b cancelled by its client"));
  EXPECT_EQ(Stats().in_flight, 0u);
  EXPECT_EQ(Stats().leases_revoked, 2u);
  // Another user's batch gets the whole worker in the same turn, with no result of the old batch in between.
  Submit("d", "next", {Job("n0"), Job("n1")}, std::string(16, '\x07'));
  Dispatch();
  ASSERT_EQ(transport_.Jobs("w").size(), 4u);
  EXPECT_EQ(transport_.Jobs("w")[2].batch_id(), "next");
  EXPECT_EQ(transport_.Jobs("w")[3].batch_id(), "next");
  // The revoked jobs' results, should they still come, are refused and take no credit back twice.
  Answer("w", held[0]);
  EXPECT_EQ(Stats().results_refused, 1u);
  EXPECT_EQ(Stats().in_flight, 2u);
  EXPECT_TRUE(transport_.Results("c").empty());
}

TEST_F(BrokerCoreTest, AClientWhoseConnectionClosedHasItsRunningJobsRevokedAtTheNextHeartbeat) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 2);
  Dispatch();
  transport_.gone.insert("c");
  Advance(seconds(1));
  WorkerHeartbeat("w");
  Tick();
  EXPECT_EQ(endings::RevokedLeases(transport_, "w"), endings::LeasesOf(transport_.Jobs("w")));
  EXPECT_EQ(Stats().in_flight, 0u);
  EXPECT_EQ(Stats().batches, 0);
}

TEST_F(BrokerCoreTest, ASilentClientsBatchRunsOnThroughItsGraceAndIsClaimedBackWithTheResultsItMissed) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  PassSecondsWithTheClientSilent(5);  // the client is stopped (SIGSTOP): only the worker beats
  EXPECT_EQ(Stats().clients, 0);
  EXPECT_EQ(Stats().batches, 1);
  EXPECT_EQ(Stats().batches_orphaned, 1u);
  EXPECT_TRUE(endings::RevokedLeases(transport_, "w").empty());  // nothing is revoked within the grace
  EXPECT_TRUE(Logged("wait 60.0 s for it to come back"));
  Answer("w", transport_.Jobs("w").at(0));  // finishes while nobody owns the batch: held for its owner
  Dispatch();
  ASSERT_EQ(transport_.Jobs("w").size(), 2u);
  EXPECT_EQ(Stats().results_delivered, 0u);
  // The client wakes, is told the broker forgot it, connects again and submits what it has no result for.
  Submit("c-again", "b", {Job("j0"), Job("j1")});
  EXPECT_EQ(Stats().batches_reclaimed, 1u);
  ASSERT_EQ(transport_.Results("c-again").size(), 1u);
  EXPECT_EQ(transport_.Results("c-again")[0].job_id(), "j0");
  EXPECT_EQ(Stats().jobs_dispatched, 2u);  // j0 was not run again, j1 is still running
  Answer("w", transport_.Jobs("w").at(1));
  ASSERT_EQ(transport_.Results("c-again").size(), 2u);
  EXPECT_EQ(transport_.Results("c-again")[1].job_id(), "j1");
}

TEST_F(BrokerCoreTest, ASilentClientsBatchIsDroppedAfterItsGraceAndItsRunningJobsRevoked) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  PassSecondsWithTheClientSilent(5 + 59);
  EXPECT_EQ(Stats().batches, 1) << "dropped before its grace ended";
  PassSecondsWithTheClientSilent(1);
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().batches_unclaimed, 1u);
  EXPECT_EQ(endings::RevokedLeases(transport_, "w"), endings::LeasesOf(transport_.Jobs("w")));
  EXPECT_EQ(Stats().in_flight, 0u);
  EXPECT_EQ(Stats().queued, 0u);
}

TEST_F(BrokerCoreTest, AnOrphanedBatchsCancelFromItsFormerConnectionEndsItAtOnce) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 2);
  Dispatch();
  PassSecondsWithTheClientSilent(5);
  ASSERT_EQ(Stats().batches_orphaned, 1u);
  v1::ClientToBroker cancel;
  cancel.mutable_cancel()->set_batch_id("b");
  ClientSays("stranger", cancel);  // a CANCEL from another connection changes nothing
  EXPECT_EQ(Stats().batches, 1);
  ClientSays("c", cancel);
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(endings::RevokedLeases(transport_, "w"), endings::LeasesOf(transport_.Jobs("w")));
}

TEST_F(BrokerCoreTest, AnOrphanedBatchsGoodbyeFromItsFormerConnectionEndsItAtOnce) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  PassSecondsWithTheClientSilent(5);
  v1::ClientToBroker bye;
  bye.mutable_disconnect()->set_reason("interrupted");
  ClientSays("c", bye);
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().in_flight, 0u);
  EXPECT_TRUE(Logged("left (interrupted); dropped its batch b"));
}

// Found by the chaos soak: a client stopped just after its last result must not leave its empty batch behind.
TEST_F(BrokerCoreTest, AClientThatFallsSilentWithNothingPendingTakesItsBatchWithIt) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  Answer("w", transport_.Jobs("w").at(0));
  EXPECT_EQ(Stats().batches, 1);
  PassSecondsWithTheClientSilent(5);
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().batches_orphaned, 0u);
  EXPECT_TRUE(Logged("forgotten (silent for 5.0 s, nothing pending)"));
}

TEST_F(BrokerCoreTest, ASmallBatchBehindABigOneStartsAtOnce) {
  std::vector<v1::Job> big;
  for (int i = 0; i < 100; ++i) big.push_back(Job("big" + std::to_string(i)));
  Submit("c", "big", big);
  Submit("d", "small", {Job("s0"), Job("s1")}, std::string(16, '\x07'));
  Ready("w", 2);
  Dispatch();
  const std::vector<v1::Job> first = transport_.Jobs("w");
  ASSERT_EQ(first.size(), 2u);
  EXPECT_EQ(first[0].batch_id(), "big");
  EXPECT_EQ(first[1].batch_id(), "small");  // the batches take turns, not first come first served
  Answer("w", first[0]);
  Answer("w", first[1]);
  Dispatch();
  const std::vector<v1::Job> all = transport_.Jobs("w");
  ASSERT_EQ(all.size(), 4u);
  EXPECT_EQ(all[2].batch_id(), "big");
  EXPECT_EQ(all[3].job_id(), "s1");
}

TEST_F(BrokerCoreTest, AWorkerAskingForMoreCreditThanTheCapHoldsTheCapAndNoMore) {
  std::vector<v1::Job> jobs;
  for (int i = 0; i < 100; ++i) jobs.push_back(Job("j" + std::to_string(i)));
  Submit("c", "b", jobs);
  Ready("greedy", 1024);
  Ready("w", 2);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("greedy").size(), 16u);  // BrokerOptions::max_credit
  EXPECT_EQ(transport_.Jobs("w").size(), 2u);
  EXPECT_TRUE(Logged("joined with credit 16 (asked for 1024; --max-credit)"));
}

}  // namespace
}  // namespace orcs::test_support
