// The broker's state tables (docs/protocol.md, "The broker's state machine"), walked row by row: one test per row,
// named after it — StateTableJob.J04_... is row J04 of table J. Each test puts BrokerCore in the row's state, sends
// the row's event, and checks the next state and the actions from outside: what the core sent, its counters and
// its status. No sockets, no threads, no sleeps: a recording transport and a made-up clock, as in
// broker_core_test.cc.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <chrono>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "broker/broker_core.h"
#include "broker/broker_journal.h"
#include "proto/envelope.h"
#include "tests/broker/core_harness.h"
#include "tests/broker/recording_transport.h"
#include "tests/support/temp_dir.h"

namespace orcs::test_support {
namespace {

using broker::BrokerCore;
using proto::kProtocolVersion;
using std::chrono::seconds;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::IsEmpty;

class StateTableJob : public ::testing::Test, protected Harness {};
class StateTableWorker : public ::testing::Test, protected Harness {};
class StateTableClient : public ::testing::Test, protected Harness {};
class StateTableBatch : public ::testing::Test, protected Harness {};

// A journal written by one core and read back by another (a restarted broker).
class StateTableJournal : public ::testing::Test {
 protected:
  TempDir dir_;
  const std::string path_ = dir_.PathOf("journal.db");
};

// ---------------------------------------------------------------------------------------------------------------
// Table J: a job

TEST_F(StateTableJob, J01_None_Submit_QueuedAtTheBack) {
  Submit("c", "b", {Job("j0")});
  Submit("c", "b", {Job("j1")});
  const v1::BrokerToClient accepted = transport_.LastToClient("c");
  ASSERT_TRUE(accepted.has_accepted());
  EXPECT_EQ(accepted.accepted().job_count(), 1u);
  EXPECT_EQ(accepted.accepted().queued(), 2u);
  EXPECT_EQ(Stats().jobs_accepted, 2u);
  EXPECT_EQ(BatchEntry("b")->queued(), 2u);
  Ready("w", 2);
  Dispatch();
  EXPECT_THAT(transport_.JobIds("w"), ElementsAre("j0", "j1"));  // j1 went behind j0
}

TEST_F(StateTableJob, J02_None_SubmitWithAResultKept_ResultSentAgain) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  Pass(5, {"w"}, {});  // the client falls silent: its batch is orphaned
  AnswerNth("w", 0);   // the result is kept in the batch (no journal)
  ASSERT_THAT(transport_.Results("c"), IsEmpty());
  Submit("c2", "b", {Job("j0")});
  ASSERT_EQ(transport_.Results("c2").size(), 1u);
  EXPECT_EQ(transport_.Results("c2")[0].job_id(), "j0");
  EXPECT_EQ(transport_.Results("c2")[0].fitness(), 1.5);
  EXPECT_EQ(Stats().results_resent, 1u);
  EXPECT_EQ(Stats().jobs_accepted, 1u);  // not accepted again
  EXPECT_EQ(Stats().queued, 0u);
  EXPECT_EQ(Stats().jobs_held, 0u);
}

TEST_F(StateTableJob, J03_QueuedOrRunning_SubmitAgain_Unchanged) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();  // j0 running on w, j1 queued
  Submit("c", "b", {Job("j0"), Job("j1")});
  EXPECT_EQ(transport_.LastToClient("c").accepted().job_count(), 2u);
  EXPECT_EQ(Stats().jobs_accepted, 2u);
  EXPECT_EQ(Stats().queued, 1u);
  EXPECT_EQ(Stats().in_flight, 1u);
  AnswerNth("w", 0);  // j0's lease still holds
  EXPECT_EQ(transport_.Results("c").size(), 1u);
  Dispatch();
  Dispatch();
  EXPECT_THAT(transport_.JobIds("w"), ElementsAre("j0", "j1"));  // j1 queued once
}

TEST_F(StateTableJob, J04_Queued_Dispatch_RunningOnW) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  const std::vector<v1::Job> sent = transport_.Jobs("w");
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].job_id(), "j0");
  EXPECT_EQ(sent[0].batch_id(), "b");
  EXPECT_NE(sent[0].lease(), 0u);
  EXPECT_EQ(sent[0].attempt(), 0u);
  EXPECT_EQ(BatchEntry("b")->queued(), 0u);
  EXPECT_EQ(BatchEntry("b")->running(), 1u);
  EXPECT_EQ(WorkerEntry("w-name")->current_job_id(), "j0");
  EXPECT_EQ(Stats().jobs_dispatched, 1u);
}

TEST_F(StateTableJob, J05_Queued_DispatchSendFails_QueuedAtTheFrontWithoutALoss) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  transport_.gone.insert("w");
  Dispatch();
  EXPECT_EQ(Stats().jobs_dispatched, 0u);
  EXPECT_EQ(Stats().queued, 2u);
  EXPECT_EQ(Stats().workers_lost, 1u);
  Ready("v", 1);
  Dispatch();
  ASSERT_EQ(transport_.Jobs("v").size(), 1u);
  EXPECT_EQ(transport_.Jobs("v")[0].job_id(), "j0");
  EXPECT_EQ(transport_.Jobs("v")[0].attempt(), 0u);
}

TEST_F(StateTableJob, J06_QueuedAfterACrash_DispatchWithOnlyWorkersItCrashedFree_Waits) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w1", 1);
  Ready("w2", 1);
  Dispatch();  // j0 to w1, j1 to w2
  AnswerNth("w1", 0, v1::Result::CRASHED, "segfault");
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w1").size(), 1u);  // w1 is free, but j0 crashed it and w2 has not had it
  EXPECT_EQ(Stats().queued, 1u);
  AnswerNth("w2", 0);
  Dispatch();
  EXPECT_THAT(transport_.JobIds("w2"), ElementsAre("j1", "j0"));
}

TEST_F(StateTableJob, J07_RunningOnW_Result_FinishedAndForgotten) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Advance(seconds(2));
  Ready("w", 2);
  Dispatch();
  AnswerNth("w", 0);
  AnswerNth("w", 1, v1::Result::STATUS_UNSPECIFIED);
  const std::vector<v1::Result> results = transport_.Results("c");
  ASSERT_EQ(results.size(), 2u);
  EXPECT_EQ(results[0].status(), v1::Result::OK);
  EXPECT_EQ(results[0].attempts(), 1u);
  EXPECT_EQ(results[0].worker_id(), "w-name");
  EXPECT_DOUBLE_EQ(results[0].timings().queued_seconds(), 2.0);
  EXPECT_EQ(results[1].status(), v1::Result::INTERNAL_ERROR);
  EXPECT_EQ(Stats().results_delivered, 2u);
  EXPECT_EQ(Stats().jobs_held, 0u);  // forgotten
  EXPECT_EQ(BatchEntry("b")->done(), 1u);
  EXPECT_EQ(BatchEntry("b")->failed(), 1u);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 0u);
}

TEST_F(StateTableJournal, J08_RunningOnWInABatchNobodyOwns_Result_KeptForItsOwner) {
  broker::BrokerJournal journal(path_);
  Harness broker(&journal);
  broker.Submit("c", "b", {Job("j0")});
  broker.Ready("w", 1);
  broker.Dispatch();
  broker.Pass(5, {"w"}, {});  // the client falls silent: its batch is orphaned
  broker.AnswerNth("w", 0);
  EXPECT_THAT(broker.transport_.Results("c"), IsEmpty());
  EXPECT_EQ(broker.Stats().results_delivered, 0u);
  EXPECT_EQ(broker.Stats().jobs_held, 0u);
  const std::optional<v1::Result> stored = journal.Result("b", "j0");
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->status(), v1::Result::OK);
}

TEST_F(StateTableJob, J09_RunningOnW_CrashedBelowTheLimit_QueuedAtTheFront) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  AnswerNth("w", 0, v1::Result::CRASHED, "segfault");
  EXPECT_THAT(transport_.Results("c"), IsEmpty());
  EXPECT_EQ(Stats().crashes, 1u);
  EXPECT_EQ(Stats().jobs_requeued, 1u);
  EXPECT_EQ(Stats().queued, 2u);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 0u);
  EXPECT_TRUE(Logged("crash 1 of 3"));
  Ready("v", 1);
  Dispatch();
  ASSERT_EQ(transport_.Jobs("v").size(), 1u);
  EXPECT_EQ(transport_.Jobs("v")[0].job_id(), "j0");  // ahead of j1, and not on w, which it crashed
  EXPECT_EQ(transport_.Jobs("v")[0].attempt(), 0u);   // a crash is no loss
  EXPECT_THAT(transport_.JobIds("w"), ElementsAre("j0", "j1"));
}

TEST_F(StateTableJob, J10_RunningOnW_CrashedAtTheLimit_FinishedPoisonous) {
  Submit("c", "b", {Job("j0")});
  for (const std::string worker : {"w1", "w2", "w3"}) {
    Ready(worker, 1);
    Dispatch();
    ASSERT_EQ(transport_.Jobs(worker).size(), 1u);
    AnswerNth(worker, 0, v1::Result::CRASHED, "died " + worker);
  }
  const std::vector<v1::Result> results = transport_.Results("c");
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].status(), v1::Result::CRASHED);
  EXPECT_EQ(results[0].message(), "poisonous: crashed 3 workers (w1-name, w2-name, w3-name); the last: died w3");
  EXPECT_EQ(Stats().jobs_poisoned, 1u);
  EXPECT_EQ(Stats().jobs_held, 0u);
}

TEST_F(StateTableJob, J11_RunningOnW_ResultNotAnsweringItsLease_Refused) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Ready("other", 1);
  Dispatch();
  v1::Job job = transport_.Jobs("w").at(0);
  Answer("other", job);  // another connection
  v1::Job stale = job;
  stale.set_lease(job.lease() + 1);
  Answer("w", stale);  // another token
  stale.set_lease(0);
  Answer("w", stale);                            // no token
  Answer("other", job, v1::Result::CRASHED);  // a crash not under the lease counts none
  EXPECT_THAT(transport_.Results("c"), IsEmpty());
  EXPECT_EQ(Stats().results_refused, 4u);
  EXPECT_EQ(Stats().crashes, 0u);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 1u);  // still running on w
  Answer("w", job);
  EXPECT_EQ(transport_.Results("c").size(), 1u);
}

TEST_F(StateTableJob, J12_RunningOnW_WorkerLostBelowTheLimit_QueuedAtTheFrontWithOneMoreLoss) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  Pass(5, {}, {"c"});  // w says nothing for its liveness period
  EXPECT_EQ(Stats().jobs_requeued, 1u);
  EXPECT_EQ(Stats().queued, 2u);
  Ready("v", 1);
  Dispatch();
  ASSERT_EQ(transport_.Jobs("v").size(), 1u);
  EXPECT_EQ(transport_.Jobs("v")[0].job_id(), "j0");
  EXPECT_EQ(transport_.Jobs("v")[0].attempt(), 1u);
}

TEST_F(StateTableJob, J13_RunningOnW_WorkerLostAtTheLimit_FinishedWorkerLost) {
  Submit("c", "b", {Job("j0")});
  for (const std::string worker : {"w1", "w2", "w3"}) {
    Ready(worker, 1);
    Dispatch();
    ASSERT_EQ(transport_.Jobs(worker).size(), 1u);
    transport_.gone.insert(worker);
    Advance(seconds(1));
    Tick();
  }
  const std::vector<v1::Result> results = transport_.Results("c");
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].status(), v1::Result::WORKER_LOST);
  EXPECT_EQ(results[0].message(),
            "lost 3 workers while running (w1-name, w2-name, w3-name); the last one: connection closed");
  EXPECT_EQ(results[0].worker_id(), "w3-name");
  EXPECT_EQ(results[0].attempts(), 3u);
  EXPECT_EQ(Stats().workers_lost, 3u);
  EXPECT_EQ(Stats().jobs_requeued, 2u);
  EXPECT_EQ(Stats().jobs_held, 0u);
}

TEST_F(StateTableJob, J14_RunningOnW_WorkerDisconnect_QueuedAtTheFrontWithoutALoss) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  WorkerDisconnect("w", "done");
  EXPECT_EQ(Stats().jobs_requeued, 1u);
  EXPECT_EQ(Stats().queued, 2u);
  Ready("v", 1);
  Dispatch();
  ASSERT_EQ(transport_.Jobs("v").size(), 1u);
  EXPECT_EQ(transport_.Jobs("v")[0].job_id(), "j0");
  EXPECT_EQ(transport_.Jobs("v")[0].attempt(), 0u);
}

TEST_F(StateTableJob, J15_Queued_BatchEnds_Forgotten) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Cancel("c", "b");
  EXPECT_EQ(Stats().queued, 0u);
  EXPECT_EQ(Stats().jobs_held, 0u);
  Ready("w", 2);
  Dispatch();
  EXPECT_THAT(transport_.Jobs("w"), IsEmpty());
  EXPECT_THAT(transport_.Results("c"), IsEmpty());
}

TEST_F(StateTableJob, J16_RunningOnW_BatchEnds_RevokedAndForgotten) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  const v1::Job job = transport_.Jobs("w").at(0);
  Cancel("c", "b");
  const std::vector<v1::Revoke> revokes = transport_.Revokes("w");
  ASSERT_EQ(revokes.size(), 1u);
  EXPECT_THAT(revokes[0].leases(), ElementsAre(job.lease()));
  EXPECT_EQ(revokes[0].reason(), "batch b cancelled by its client");
  EXPECT_EQ(Stats().leases_revoked, 1u);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 0u);
  Answer("w", job);
  EXPECT_THAT(transport_.Results("c"), IsEmpty());
  EXPECT_EQ(Stats().results_refused, 1u);
}

TEST_F(StateTableJob, J17_Forgotten_LateResult_Refused) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  AnswerNth("w", 0);
  AnswerNth("w", 0);
  EXPECT_EQ(transport_.Results("c").size(), 1u);
  EXPECT_EQ(Stats().results_refused, 1u);
  EXPECT_TRUE(Logged("refused a result for a job the broker does not know"));
}

TEST_F(StateTableJournal, J18_InTheJournal_Restore_Queued) {
  {
    broker::BrokerJournal journal(path_);
    Harness before(&journal);
    before.Submit("c", "b", {Job("j0"), Job("j1"), Job("j2")});
    before.Ready("w", 2);
    before.Dispatch();  // j0 and j1 in flight
    before.AnswerNth("w", 0);
  }
  broker::BrokerJournal journal(path_);
  Harness after(&journal);
  after.core_.Restore(after.now_);
  EXPECT_EQ(after.Stats().batches, 1);
  EXPECT_EQ(after.Stats().jobs_restored, 2u);
  EXPECT_EQ(after.Stats().results_restored, 1u);
  EXPECT_EQ(after.Stats().queued, 2u);
  after.Submit("c2", "b", {Job("j0"), Job("j1"), Job("j2")});  // its client is back, on a new connection
  ASSERT_EQ(after.transport_.Results("c2").size(), 1u);  // j0's stored result at once (row J02)
  EXPECT_EQ(after.transport_.Results("c2")[0].job_id(), "j0");
  EXPECT_EQ(after.Stats().results_resent, 1u);
  EXPECT_EQ(after.Stats().jobs_accepted, 0u);  // j1 and j2 were pending already
  after.Ready("v", 2);
  after.Dispatch();
  EXPECT_THAT(after.transport_.JobIds("v"), ElementsAre("j1", "j2"));  // in flight first
  EXPECT_EQ(after.transport_.Jobs("v")[0].attempt(), 0u);
}

// ---------------------------------------------------------------------------------------------------------------
// Table W: a worker as the broker sees it

TEST_F(StateTableWorker, W01_Unknown_Ready_Registered) {
  Ready("w", 20);
  ASSERT_TRUE(WorkerEntry("w-name").has_value());
  EXPECT_EQ(WorkerEntry("w-name")->credit(), 16u);  // --max-credit
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 0u);
  EXPECT_TRUE(Logged("worker w-name joined with credit 16 (asked for 20; --max-credit)"));
  std::vector<v1::Job> jobs;
  for (int i = 0; i < 20; ++i) jobs.push_back(Job("j" + std::to_string(i)));
  Submit("c", "b", jobs);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 16u);
}

TEST_F(StateTableWorker, W02_Any_ReadyOutOfBounds_Dropped) {
  Ready("w", 0);
  Ready("v", 1025);
  ReadyAs("u", std::string(broker::kMaxIdBytes + 1, 'u'), 1);
  EXPECT_EQ(Stats().workers, 0);
  Ready("x", 2);
  Ready("x", 0);
  EXPECT_EQ(WorkerEntry("x-name")->credit(), 2u);
  EXPECT_EQ(Stats().messages_dropped, 4u);
}

TEST_F(StateTableWorker, W03_Registered_ReadyAgain_CreditReplaced) {
  Submit("c", "b", {Job("j0"), Job("j1"), Job("j2"), Job("j3")});
  Ready("w", 1);
  Dispatch();
  Ready("w", 3);
  EXPECT_EQ(WorkerEntry("w-name")->credit(), 3u);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 1u);  // its job stays its own
  EXPECT_TRUE(Logged("worker w-name sent READY again; credit now 3"));
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 3u);
  Ready("w", 1);  // full: nothing more until it holds fewer than 1
  AnswerNth("w", 0);
  AnswerNth("w", 1);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 3u);
  AnswerNth("w", 2);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 4u);
}

// Pins a flaw (reported with issue 52, item 5): a worker still on the ready list when it lowers its credit to what
// it holds or less stays on the list and gets one more JOB than its new credit allows.
TEST_F(StateTableWorker, W04_RegisteredFree_ReadyAgainWithCreditAtMostItsHolding_Full) {
  Submit("c", "b", {Job("j0"), Job("j1"), Job("j2")});
  Ready("w", 2);
  Dispatch();
  ASSERT_EQ(transport_.Jobs("w").size(), 2u);
  AnswerNth("w", 0);  // holding 1 of 2: on the ready list
  Ready("w", 1);      // holding 1 of 1: full, off the list
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 2u) << "no JOB beyond the new credit";
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 1u);
  EXPECT_EQ(WorkerEntry("w-name")->credit(), 1u);
  AnswerNth("w", 1);  // holding 0 of 1: free again, j2 goes to it
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 3u);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 1u);
}

TEST_F(StateTableWorker, W05_RegisteredFree_Dispatch_HoldsOneMore) {
  Submit("c", "b", {Job("j0"), Job("j1"), Job("j2")});
  Ready("w", 2);
  Dispatch();
  EXPECT_EQ(transport_.Jobs("w").size(), 2u);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 2u);
  Dispatch();  // full
  EXPECT_EQ(transport_.Jobs("w").size(), 2u);
  EXPECT_EQ(Stats().queued, 1u);
}

TEST_F(StateTableWorker, W06_RegisteredFree_DispatchSendFails_Lost) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  transport_.gone.insert("w");
  Dispatch();
  EXPECT_EQ(Stats().workers, 0);
  EXPECT_EQ(Stats().workers_lost, 1u);
  EXPECT_TRUE(Logged("worker w-name lost: connection closed"));
}

TEST_F(StateTableWorker, W07_Registered_ResultForItsLease_OneCreditBack) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  AnswerNth("w", 0);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 0u);
  EXPECT_EQ(WorkerEntry("w-name")->jobs_done(), 1u);
  Dispatch();
  EXPECT_THAT(transport_.JobIds("w"), ElementsAre("j0", "j1"));
}

TEST_F(StateTableWorker, W08_Registered_RefusedResult_Unchanged) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Ready("v", 1);
  Dispatch();  // j0 to w
  Answer("v", transport_.Jobs("w").at(0));
  EXPECT_EQ(Stats().results_refused, 1u);
  EXPECT_EQ(Stats().workers, 2);
  EXPECT_THAT(transport_.Disconnects("v"), IsEmpty());
  EXPECT_EQ(WorkerEntry("v-name")->holding(), 0u);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 1u);
}

TEST_F(StateTableWorker, W09_Unknown_Result_RefusedAndToldToReconnect) {
  Submit("c", "b", {Job("j0")});
  v1::Job forged = Job("j0");
  forged.set_batch_id("b");
  Answer("stranger", forged);
  EXPECT_EQ(Stats().results_refused, 1u);
  EXPECT_EQ(Stats().workers, 0);
  EXPECT_THAT(transport_.Disconnects("stranger"), ElementsAre("unknown worker: connect again and send READY"));
  EXPECT_EQ(Stats().queued, 1u);
}

TEST_F(StateTableWorker, W10_Registered_Heartbeat_LivenessRenewed) {
  Ready("w", 1);
  Advance(seconds(4));
  WorkerHeartbeat("w");
  Advance(seconds(4));
  Tick();
  EXPECT_EQ(Stats().workers, 1);  // 8 s after READY, 4 s after its heartbeat
  WorkerHeartbeat("w", 2000);     // a pace of 2 s: 10 s of silence allowed
  Advance(seconds(9));
  Tick();
  EXPECT_EQ(Stats().workers, 1);
  Advance(seconds(1));
  Tick();
  EXPECT_EQ(Stats().workers, 0);
}

TEST_F(StateTableWorker, W11_Unknown_Heartbeat_ToldToReconnect) {
  WorkerHeartbeat("stranger");
  EXPECT_EQ(Stats().workers, 0);
  EXPECT_THAT(transport_.Disconnects("stranger"), ElementsAre("unknown worker: connect again and send READY"));
}

TEST_F(StateTableWorker, W12_Registered_Disconnect_Gone) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  WorkerDisconnect("w", "done");
  EXPECT_EQ(Stats().workers, 0);
  EXPECT_EQ(Stats().workers_lost, 0u);
  EXPECT_EQ(Stats().in_flight, 0u);
  EXPECT_EQ(Stats().queued, 1u);
  EXPECT_TRUE(Logged("worker w-name left (done); 1 jobs back to the queue"));
}

TEST_F(StateTableWorker, W13_Unknown_Disconnect_Nothing) {
  WorkerDisconnect("stranger", "bye");
  EXPECT_TRUE(transport_.to_workers.empty());
  EXPECT_EQ(Stats().workers_lost, 0u);
  EXPECT_EQ(Stats().messages_dropped, 0u);
}

TEST_F(StateTableWorker, W14_Registered_SilentForItsLiveness_Lost) {
  Ready("w", 1);
  Advance(seconds(4));
  Tick();
  EXPECT_EQ(Stats().workers, 1);
  Advance(seconds(1));
  Tick();
  EXPECT_EQ(Stats().workers, 0);
  EXPECT_EQ(Stats().workers_lost, 1u);
  EXPECT_TRUE(Logged("worker w-name lost: silent for 5.0 s"));
  EXPECT_THAT(transport_.Disconnects("w"), IsEmpty());
}

TEST_F(StateTableWorker, W15_Registered_HeartbeatSendFails_Lost) {
  Ready("w", 1);
  transport_.gone.insert("w");
  Advance(seconds(1));
  Tick();
  EXPECT_EQ(Stats().workers, 0);
  EXPECT_EQ(Stats().workers_lost, 1u);
  EXPECT_TRUE(Logged("worker w-name lost: connection closed"));
}

TEST_F(StateTableWorker, W16_Registered_HeldJobPastItsLease_LostAndToldToReconnect) {
  Submit("c", "b", {Job("j0", 1.0)});
  Ready("w", 1);
  Dispatch();
  // The lease: 1 s × 1.5 + 2 s + the liveness period of 5 s = 8.5 s. The worker heartbeats all along.
  Pass(8, {"w"}, {"c"});
  EXPECT_EQ(Stats().workers, 1);
  Pass(1, {"w"}, {"c"});
  EXPECT_EQ(Stats().workers, 0);
  EXPECT_EQ(Stats().leases_expired, 1u);
  EXPECT_EQ(Stats().workers_lost, 1u);
  EXPECT_EQ(Stats().queued, 1u);
  EXPECT_THAT(transport_.Disconnects("w"),
              ElementsAre("held job b/j0 past its lease (time limit 1.0 s, leased for 8.5 s): connect again and send "
                          "READY"));
}

TEST_F(StateTableWorker, W17_Registered_BatchOfItsJobsEnds_RevokedAndCreditFree) {
  Submit("c", "b1", {Job("j0"), Job("j1")});
  Submit("d", "b2", {Job("k0"), Job("k1")});
  Ready("w", 2);
  Dispatch();  // the batches take turns: j0, k0
  ASSERT_THAT(transport_.JobIds("w"), ElementsAre("j0", "k0"));
  Cancel("c", "b1");
  ASSERT_EQ(transport_.Revokes("w").size(), 1u);
  EXPECT_THAT(transport_.Revokes("w")[0].leases(), ElementsAre(transport_.Jobs("w")[0].lease()));
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 1u);
  Dispatch();
  EXPECT_THAT(transport_.JobIds("w"), ElementsAre("j0", "k0", "k1"));
}

TEST_F(StateTableWorker, W18_Registered_Tick_Heartbeat) {
  Ready("w", 1);
  Advance(seconds(1));
  Tick();
  const v1::BrokerToWorker last = transport_.LastToWorker("w");
  ASSERT_TRUE(last.has_heartbeat());
  EXPECT_EQ(last.heartbeat().interval_ms(), 1000u);
}

TEST_F(StateTableWorker, W19_Registered_BrokerStops_Disconnect) {
  Ready("w", 1);
  core_.SayGoodbye();
  EXPECT_THAT(transport_.Disconnects("w"), ElementsAre("broker shutting down"));
}

// ---------------------------------------------------------------------------------------------------------------
// Table C: a client connection

TEST_F(StateTableClient, C01_Unknown_Submit_Registered) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  const v1::BrokerToClient accepted = transport_.LastToClient("c");
  ASSERT_TRUE(accepted.has_accepted());
  EXPECT_EQ(accepted.accepted().batch_id(), "b");
  EXPECT_EQ(accepted.accepted().job_count(), 2u);
  EXPECT_EQ(accepted.accepted().queued(), 2u);
  EXPECT_EQ(Stats().clients, 1);
  EXPECT_EQ(BatchEntry("b")->client_id(), "c-name");
}

TEST_F(StateTableClient, C02_Any_SubmitWithAProblem_Error) {
  Submit("c", "b", {Job("j0")});
  Submit("x", "", {Job("j1")});
  EXPECT_EQ(transport_.LastToClient("x").error().message(), "empty batch_id");
  Submit("x", "b2", {Job("j1"), Job("j1")});
  EXPECT_THAT(transport_.LastToClient("x").error().message(), HasSubstr("job_id repeated within the SUBMIT"));
  Submit("x", "b", {Job("j1")}, std::string(16, '\x07'));
  EXPECT_EQ(transport_.LastToClient("x").error().message(), "batch 'b' belongs to another client");
  EXPECT_EQ(Stats().clients, 1);  // x registered nothing
  SubmitAs("c", "someone-else", "b3", {Job("j1")});
  EXPECT_EQ(transport_.LastToClient("c").error().message(), "this connection submitted as client 'c-name' before");
  EXPECT_EQ(Stats().submits_rejected, 4u);
  EXPECT_EQ(Stats().queued, 1u);
  EXPECT_EQ(Stats().batches, 1);
}

TEST_F(StateTableClient, C03_Registered_Heartbeat_LivenessRenewed) {
  Submit("c", "b", {Job("j0")});
  Advance(seconds(4));
  ClientHeartbeat("c");
  Advance(seconds(4));
  Tick();
  EXPECT_EQ(Stats().clients, 1);
  Advance(seconds(1));
  Tick();
  EXPECT_EQ(Stats().clients, 0);
}

TEST_F(StateTableClient, C04_Unknown_Heartbeat_ToldToReconnect) {
  ClientHeartbeat("x");
  EXPECT_EQ(Stats().clients, 0);
  const v1::BrokerToClient reply = transport_.LastToClient("x");
  ASSERT_TRUE(reply.has_disconnect());
  EXPECT_EQ(reply.disconnect().reason(), "unknown client: connect again and submit the outstanding jobs");
}

TEST_F(StateTableClient, C05_Any_StatusRequest_AnsweredRegistersNothing) {
  v1::ClientToBroker request;
  request.mutable_status_request();
  ClientSays("x", request);
  EXPECT_TRUE(transport_.LastToClient("x").has_status());
  EXPECT_EQ(Stats().clients, 0);
  Advance(seconds(1));
  Tick();
  EXPECT_TRUE(transport_.LastToClient("x").has_status());  // no heartbeat to a status connection
}

TEST_F(StateTableClient, C06_Registered_Disconnect_ForgottenWithItsBatches) {
  Submit("c", "b1", {Job("j0")});
  Submit("c", "b2", {Job("k0")});
  ClientDisconnect("c", "bye");
  EXPECT_EQ(Stats().clients, 0);
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().queued, 0u);
  EXPECT_EQ(Stats().clients_lost, 0u);
  EXPECT_TRUE(Logged("client c-name left (bye); dropped its 2 pending jobs"));
}

TEST_F(StateTableClient, C07_UnknownFormerOwner_Disconnect_OrphanedBatchesDropped) {
  Submit("c", "b", {Job("j0")});
  Submit("d", "other", {Job("k0")});
  Pass(5, {}, {"d"});  // c falls silent: forgotten, b orphaned
  ASSERT_EQ(Stats().batches_orphaned, 1u);
  ClientDisconnect("c", "interrupted");
  EXPECT_EQ(Stats().batches, 1);  // d's stays
  EXPECT_FALSE(BatchEntry("b").has_value());
  EXPECT_EQ(Stats().clients, 1);
  EXPECT_TRUE(Logged("client c-name left (interrupted); dropped its batch b"));
}

TEST_F(StateTableClient, C08_Registered_HeartbeatSendFails_LostWithItsBatches) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  transport_.gone.insert("c");
  Advance(seconds(1));
  Tick();
  EXPECT_EQ(Stats().clients, 0);
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().clients_lost, 1u);
  EXPECT_TRUE(Logged("client c-name lost (connection closed); dropped its 2 pending jobs"));
}

TEST_F(StateTableClient, C09_Registered_SilentForItsLiveness_ForgottenItsBatchesOrphaned) {
  Submit("c", "done", {Job("j0")});
  Submit("c", "pending", {Job("k0")});
  Ready("w", 1);
  Dispatch();
  ASSERT_THAT(transport_.JobIds("w"), ElementsAre("j0"));
  AnswerNth("w", 0);  // "done" has nothing pending now; "pending" has k0 queued
  Pass(5, {"w"}, {});
  EXPECT_EQ(Stats().clients, 0);
  EXPECT_EQ(Stats().clients_lost, 1u);
  EXPECT_EQ(Stats().batches_orphaned, 1u);
  EXPECT_FALSE(BatchEntry("done").has_value());
  EXPECT_TRUE(BatchEntry("pending").has_value());
  EXPECT_TRUE(Logged("its 1 batches (1 pending jobs) wait 60.0 s for it to come back"));
}

TEST_F(StateTableClient, C10_Registered_Tick_Heartbeat) {
  Submit("c", "b", {Job("j0")});
  Advance(seconds(1));
  Tick();
  const v1::BrokerToClient last = transport_.LastToClient("c");
  ASSERT_TRUE(last.has_heartbeat());
  EXPECT_EQ(last.heartbeat().interval_ms(), 1000u);
}

TEST_F(StateTableClient, C11_Registered_BrokerStops_Disconnect) {
  Submit("c", "b", {Job("j0")});
  core_.SayGoodbye();
  const v1::BrokerToClient last = transport_.LastToClient("c");
  ASSERT_TRUE(last.has_disconnect());
  EXPECT_EQ(last.disconnect().reason(), "broker shutting down");
}

// ---------------------------------------------------------------------------------------------------------------
// Table B: a batch

TEST_F(StateTableBatch, B01_None_Submit_OwnedByC) {
  Submit("c", "b", {Job("j0")});
  ASSERT_TRUE(BatchEntry("b").has_value());
  EXPECT_EQ(BatchEntry("b")->client_id(), "c-name");
  EXPECT_TRUE(Logged("client c-name opened batch b"));
  Ready("w", 1);
  Dispatch();
  AnswerNth("w", 0);
  EXPECT_EQ(transport_.Results("c").size(), 1u);
}

TEST_F(StateTableBatch, B02_OwnedByC_SubmitFromC_MoreJobs) {
  Submit("c", "b", {Job("j0")});
  Submit("c", "b", {Job("j1")});
  EXPECT_EQ(Stats().batches, 1);
  EXPECT_EQ(BatchEntry("b")->queued(), 2u);
  EXPECT_EQ(Stats().jobs_accepted, 2u);
}

TEST_F(StateTableBatch, B03_OwnedByC_SubmitFromAnotherConnection_MovedToIt) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  Submit("c2", "b", {Job("j0")});  // the client reconnected
  EXPECT_TRUE(Logged("batch b of client c2-name moved to its new connection"));
  AnswerNth("w", 0);
  EXPECT_THAT(transport_.Results("c"), IsEmpty());
  EXPECT_EQ(transport_.Results("c2").size(), 1u);
  ClientDisconnect("c", "old connection closing");  // no longer its batch
  EXPECT_EQ(Stats().batches, 1);
}

TEST_F(StateTableBatch, B04_OrphanedOrUnclaimed_SubmitWithItsToken_Reclaimed) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  Pass(5, {"w"}, {});
  ASSERT_EQ(Stats().batches_orphaned, 1u);
  Submit("c2", "b", {Job("j1")});
  EXPECT_EQ(Stats().batches_reclaimed, 1u);
  EXPECT_EQ(BatchEntry("b")->client_id(), "c2-name");
  Pass(60, {"w"}, {"c2"});  // past the grace: it is owned again, so it stays
  EXPECT_EQ(Stats().batches, 1);
  AnswerNth("w", 0);
  EXPECT_EQ(transport_.Results("c2").size(), 1u);
}

TEST_F(StateTableBatch, B05_Any_SubmitWithAnotherToken_Error) {
  Submit("c", "b", {Job("j0")});
  Submit("intruder", "b", {Job("j1")}, std::string(16, '\x07'));
  ASSERT_TRUE(transport_.LastToClient("intruder").has_error());
  EXPECT_EQ(BatchEntry("b")->client_id(), "c-name");
  EXPECT_EQ(BatchEntry("b")->queued(), 1u);
  Ready("w", 1);
  Dispatch();
  AnswerNth("w", 0);
  EXPECT_EQ(transport_.Results("c").size(), 1u);
}

TEST_F(StateTableBatch, B06_OwnedByC_CancelFromC_Dropped) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  Cancel("c", "b");
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().queued, 0u);
  EXPECT_EQ(transport_.Revokes("w").size(), 1u);
  EXPECT_EQ(Stats().clients, 1);  // the client stays
  EXPECT_TRUE(Logged("client c-name cancelled batch b"));
}

TEST_F(StateTableBatch, B07_Orphaned_CancelFromItsFormerConnection_Dropped) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  Pass(5, {"w"}, {});
  ASSERT_EQ(Stats().batches_orphaned, 1u);
  Cancel("c", "b");
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(transport_.Revokes("w").size(), 1u);
}

TEST_F(StateTableBatch, B08_OwnedOrOrphaned_CancelFromAnotherConnection_Unchanged) {
  Submit("c", "b", {Job("j0")});
  Cancel("x", "b");
  EXPECT_EQ(Stats().batches, 1);
  EXPECT_EQ(Stats().queued, 1u);
  Pass(5, {}, {});  // orphaned
  ASSERT_EQ(Stats().batches_orphaned, 1u);
  Cancel("x", "b");
  EXPECT_EQ(Stats().batches, 1);
}

TEST_F(StateTableBatch, B09_OwnedByC_ClientLeavesOrItsConnectionCloses_Dropped) {
  Submit("c", "b", {Job("j0")});
  Submit("d", "e", {Job("k0")});
  Ready("w", 2);
  Dispatch();
  ClientDisconnect("c", "bye");
  transport_.gone.insert("d");
  Advance(seconds(1));
  Tick();
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().leases_revoked, 2u);
  EXPECT_EQ(WorkerEntry("w-name")->holding(), 0u);
}

TEST_F(StateTableBatch, B10_OwnedByC_ClientSilentWithJobsPending_Orphaned) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  Pass(5, {"w"}, {});
  EXPECT_EQ(Stats().batches_orphaned, 1u);
  EXPECT_TRUE(BatchEntry("b").has_value());
  EXPECT_THAT(transport_.Revokes("w"), IsEmpty());  // its jobs run on
  AnswerNth("w", 0);
  Dispatch();
  EXPECT_THAT(transport_.JobIds("w"), ElementsAre("j0", "j1"));
}

TEST_F(StateTableBatch, B11_OwnedByC_ClientSilentWithNothingPending_Dropped) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  AnswerNth("w", 0);
  Pass(5, {"w"}, {});
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().batches_orphaned, 0u);
  EXPECT_EQ(Stats().clients_lost, 0u);
  EXPECT_TRUE(Logged("client c-name forgotten (silent for 5.0 s, nothing pending)"));
}

TEST_F(StateTableBatch, B12_OrphanedOrUnclaimed_ClaimDeadlinePasses_Dropped) {
  Submit("c", "b", {Job("j0"), Job("j1")});
  Ready("w", 1);
  Dispatch();
  Pass(5 + 59, {"w"}, {});  // forgotten after 5 s; its grace is 60 s
  EXPECT_EQ(Stats().batches, 1);
  Pass(1, {"w"}, {});
  EXPECT_EQ(Stats().batches, 0);
  EXPECT_EQ(Stats().batches_unclaimed, 1u);
  EXPECT_EQ(transport_.Revokes("w").size(), 1u);
  EXPECT_EQ(Stats().queued, 0u);
}

TEST_F(StateTableJournal, B13_InTheJournal_Restore_Unclaimed) {
  {
    broker::BrokerJournal journal(path_);
    Harness before(&journal);
    before.Submit("c", "b", {Job("j0")});
  }
  broker::BrokerJournal journal(path_);
  Harness after(&journal);
  after.core_.Restore(after.now_);
  ASSERT_TRUE(after.BatchEntry("b").has_value());
  EXPECT_EQ(after.BatchEntry("b")->client_id(), "c-name");
  EXPECT_EQ(after.Stats().clients, 0);
  after.Advance(seconds(9));  // unclaimed for two liveness periods (10 s): dropped
  after.Tick();
  EXPECT_EQ(after.Stats().batches, 1);
  after.Advance(seconds(1));
  after.Tick();
  EXPECT_EQ(after.Stats().batches, 0);
  EXPECT_EQ(after.Stats().batches_unclaimed, 1u);
  EXPECT_EQ(after.Stats().queued, 0u);
}

TEST_F(StateTableBatch, B14_OwnedByC_LastJobFinishes_StaysOwned) {
  Submit("c", "b", {Job("j0")});
  Ready("w", 1);
  Dispatch();
  AnswerNth("w", 0);
  ASSERT_TRUE(BatchEntry("b").has_value());
  EXPECT_EQ(BatchEntry("b")->done(), 1u);
  Submit("c", "b", {Job("j1")});  // more jobs may come
  EXPECT_EQ(BatchEntry("b")->queued(), 1u);
}

}  // namespace
}  // namespace orcs::test_support
