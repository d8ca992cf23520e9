// The broker's journal: the SQLite file on its own, and a broker started again on the journal of one that stopped
// with work pending (in-process on 127.0.0.1; tests/integration/broker_restart_test.cc kills a real orcs-broker
// with SIGKILL).
#include "broker/broker_journal.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <vector>

#include "broker/broker.h"
#include "proto/envelope.h"
#include "tests/broker/test_peers.h"
#include "tests/support/temp_dir.h"

namespace orcs::test_support {
namespace {

using broker::BrokerJournal;
using broker::JournalJob;
using std::chrono::milliseconds;
using ::testing::HasSubstr;

std::vector<JournalJob> AllJobs(BrokerJournal& journal) {
  std::vector<JournalJob> jobs;
  journal.ForEachJob([&](JournalJob&& job) { jobs.push_back(std::move(job)); });
  return jobs;
}

v1::Result OkResult(const std::string& job_id, double fitness) {
  v1::Result result;
  result.set_job_id(job_id);
  result.set_status(v1::Result::OK);
  result.set_fitness(fitness);
  return result;
}

TEST(BrokerJournal, KeepsJobsAndResultsAcrossReopeningInFlightFirstThenQueueOrder) {
  TempDir dir;
  const std::string path = dir.PathOf("journal.db");
  {
    BrokerJournal journal(path);
    journal.Begin();
    journal.AddBatch("b", "client-1", std::string(16, '\x01'), "");
    journal.SaveQueued("b", MakeJob("j0", 0), 1, 0, "");
    journal.SaveQueued("b", MakeJob("j1", 1), 2, 0, "");
    journal.SaveQueued("b", MakeJob("j2", 2), 3, 0, "");
    journal.SaveDispatched("b", "j2", 1);
    journal.SaveFinished("b", "j1", OkResult("j1", 2.25));
    journal.Commit();
    journal.Begin();  // never committed: lost, as a turn of a killed broker is
    journal.SaveFinished("b", "j0", OkResult("j0", 0.25));
  }
  BrokerJournal journal(path);
  ASSERT_EQ(journal.Batches().size(), 1u);
  EXPECT_EQ(journal.Batches()[0].client_id, "client-1");
  EXPECT_EQ(journal.Batches()[0].owner_token, std::string(16, '\x01'));
  const std::vector<JournalJob> jobs = AllJobs(journal);
  ASSERT_EQ(jobs.size(), 3u);
  EXPECT_EQ(jobs[0].job.job_id(), "j2");
  EXPECT_TRUE(jobs[0].dispatched);
  EXPECT_EQ(jobs[0].dispatches, 1);
  EXPECT_EQ(jobs[0].job.seed(), 2u) << "the job as accepted";
  EXPECT_EQ(jobs[1].job.job_id(), "j0");
  EXPECT_FALSE(jobs[1].finished) << "its result was in a transaction that never committed";
  EXPECT_EQ(jobs[2].job.job_id(), "j1");
  EXPECT_TRUE(jobs[2].finished);
  ASSERT_TRUE(journal.Result("b", "j1").has_value());
  EXPECT_EQ(journal.Result("b", "j1")->fitness(), 2.25);
  EXPECT_FALSE(journal.Result("b", "j0").has_value());

  journal.DropBatch("b");
  EXPECT_TRUE(journal.Batches().empty());
  EXPECT_TRUE(AllJobs(journal).empty());
}

TEST(BrokerJournal, AFileThatIsNoJournalIsRefusedNamingIt) {
  TempDir dir;
  const std::string path = dir.Write("notes.txt", std::string(4096, 'x'));
  try {
    BrokerJournal journal(path);
    FAIL() << "opened a text file as a journal";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr("journal " + path + ": "));
    EXPECT_THAT(error.what(), HasSubstr("not a database"));
  }
  EXPECT_THROW(BrokerJournal(dir.PathOf("no/such/folder/journal.db")), std::runtime_error);
}

// ---------------------------------------------------------------------------------------------------------------
// A broker started again on the journal

// The port of "tcp://127.0.0.1:5556".
int PortOf(const std::string& endpoint) { return std::stoi(endpoint.substr(endpoint.rfind(':') + 1)); }

const std::string kOwnerToken(16, '\x5a');

v1::ClientToBroker SubmitMessage(const std::vector<v1::Job>& jobs, const std::string& owner_token = kOwnerToken) {
  v1::ClientToBroker message;
  message.set_protocol_version(proto::kProtocolVersion);
  v1::Submit& submit = *message.mutable_submit();
  submit.set_batch_id("b");
  submit.set_client_id("c");
  submit.set_owner_token(owner_token);
  for (const v1::Job& job : jobs) *submit.add_jobs() = job;
  return message;
}

// The next RESULT a raw client receives, skipping ACCEPTED and heartbeats; nullopt after `limit`.
std::optional<v1::Result> AwaitResult(RawPeer& client, milliseconds limit = milliseconds(5000)) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (std::chrono::steady_clock::now() < deadline) {
    std::optional<v1::BrokerToClient> message = client.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(100));
    if (message && message->has_result()) return message->result();
  }
  return std::nullopt;
}

class BrokerRestartTest : public ::testing::Test {
 protected:
  broker::BrokerOptions Options(int client_port = 0, int worker_port = 0) {
    broker::BrokerOptions options = TestBrokerOptions(&log_);
    if (liveness_ > 0) options.liveness = liveness_;
    options.journal = dir_.PathOf("journal.db");
    options.client_port = client_port;
    options.worker_port = worker_port;
    return options;
  }
  // Stops the running broker and starts another on the same ports and journal.
  std::unique_ptr<BrokerThread> Restart(std::unique_ptr<BrokerThread> old) {
    const int client_port = PortOf(old->client_endpoint());
    const int worker_port = PortOf(old->worker_endpoint());
    old->Stop();
    old.reset();
    return std::make_unique<BrokerThread>(Options(client_port, worker_port));
  }

  TempDir dir_;
  LogLines log_;
  int liveness_ = 0;  ///< > 0: the brokers' liveness (a restored batch waits 2 × liveness heartbeats for its client)
};

TEST_F(BrokerRestartTest, QueuedAndInFlightJobsRunAgainAndAStoredResultReachesItsClientWithoutARerun) {
  auto broker = std::make_unique<BrokerThread>(Options());
  const std::vector<v1::Job> jobs = {MakeJob("j0", 0), MakeJob("j1", 1), MakeJob("j2", 2)};
  // The old peers stay open until the restart (a closed one would make the old broker drop or requeue their
  // work first), and then say nothing more: the client never reads j0's result, the worker never answers j1.
  RawPeer old_client(broker->client_endpoint());
  old_client.Send(SubmitMessage(jobs));
  RawPeer old_worker(broker->worker_endpoint());
  old_worker.Send(ReadyMessage("first", 1));
  std::optional<v1::Job> job = AwaitJob(old_worker);
  ASSERT_TRUE(job.has_value());
  ASSERT_EQ(job->job_id(), "j0");
  old_worker.Send(ResultMessage(*job, "first"));
  ASSERT_TRUE(WaitFor([&] { return broker->stats().jobs_dispatched == 2; }));  // j1 now in flight
  broker = Restart(std::move(broker));
  old_client.Close();
  old_worker.Close();
  ASSERT_TRUE(WaitFor([&] { return broker->stats().jobs_restored == 2; })) << "j1, in flight, and j2, queued";
  EXPECT_EQ(broker->stats().results_restored, 1u) << "j0";
  EXPECT_EQ(broker->stats().queued, 2u);
  EXPECT_EQ(log_.Count("restored 1 batches, 2 jobs queued again (1 of them were in flight), 1 results kept"), 1);

  // The client is back and asks for every job it has no result for: all three.
  RawPeer client(broker->client_endpoint());
  client.Send(SubmitMessage(jobs));
  std::optional<v1::Result> stored = AwaitResult(client);
  ASSERT_TRUE(stored.has_value());
  EXPECT_EQ(stored->job_id(), "j0");
  EXPECT_EQ(stored->fitness(), EchoFitness(jobs[0]));
  EXPECT_EQ(stored->worker_id(), "first");
  EXPECT_TRUE(WaitFor([&] { return broker->stats().results_resent == 1; }));

  // A new worker runs j1 (the one in flight first) and j2, and never j0.
  EchoWorker worker(TestWorkerOptions(broker->worker_endpoint(), "second", 1));
  std::set<std::string> ids;
  for (int i = 0; i < 2; ++i) {
    std::optional<v1::Result> result = AwaitResult(client);
    ASSERT_TRUE(result.has_value()) << i;
    EXPECT_EQ(result->status(), v1::Result::OK);
    ids.insert(result->job_id());
  }
  EXPECT_EQ(ids, (std::set<std::string>{"j1", "j2"}));
  EXPECT_EQ(worker.job_ids(), (std::vector<std::string>{"j1", "j2"}));
  EXPECT_FALSE(AwaitResult(client, milliseconds(300)).has_value()) << "nothing twice";
}

TEST_F(BrokerRestartTest, AResultFromAWorkerOfTheOldBrokerIsRefusedAndTheJobRunsAgain) {
  auto broker = std::make_unique<BrokerThread>(Options());
  RawPeer worker(broker->worker_endpoint());  // its socket reconnects by itself to the new broker
  RawPeer old_client(broker->client_endpoint());
  old_client.Send(SubmitMessage({MakeJob("j0", 5)}));
  worker.Send(ReadyMessage("slow", 1));
  const std::optional<v1::Job> job = AwaitJob(worker);
  ASSERT_TRUE(job.has_value());
  broker = Restart(std::move(broker));
  old_client.Close();
  RawPeer client(broker->client_endpoint());
  client.Send(SubmitMessage({MakeJob("j0", 5)}));
  ASSERT_TRUE(WaitFor([&] { return broker->stats().batches == 1 && broker->stats().clients == 1; }));
  worker.Send(ResultMessage(*job, "slow"));  // finished while the broker was away: no lease of the new broker's
  EXPECT_TRUE(WaitFor([&] { return broker->stats().results_refused == 1; }));
  EchoWorker next(TestWorkerOptions(broker->worker_endpoint(), "next", 1));
  std::optional<v1::Result> result = AwaitResult(client);
  ASSERT_TRUE(result.has_value()) << ::testing::PrintToString(log_.lines());
  EXPECT_EQ(result->fitness(), 10.25);
  EXPECT_EQ(result->worker_id(), "next");
  EXPECT_FALSE(AwaitResult(client, milliseconds(300)).has_value()) << "nothing twice";
}

// The journal keeps each batch's owner token: after a restart the batch goes to its owner only.
TEST_F(BrokerRestartTest, ARestoredBatchGoesOnlyToItsOwner) {
  liveness_ = 20;  // the owner claims its batch after the thief's try: 4 s, not 1 s, so that a busy machine makes it
  auto broker = std::make_unique<BrokerThread>(Options());
  RawPeer old_client(broker->client_endpoint());
  old_client.Send(SubmitMessage({MakeJob("j0", 3)}));
  ASSERT_TRUE(WaitFor([&] { return broker->stats().queued == 1; }));
  broker = Restart(std::move(broker));
  old_client.Close();
  ASSERT_TRUE(WaitFor([&] { return broker->stats().jobs_restored == 1; }));

  RawPeer thief(broker->client_endpoint());
  thief.Send(SubmitMessage({}, std::string(16, '\x00')));  // the batch id and client name, not the token
  std::optional<v1::BrokerToClient> refused;
  while (!refused) {
    refused = thief.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(5000));
    ASSERT_TRUE(refused.has_value());
    if (refused->has_heartbeat()) refused.reset();
  }
  ASSERT_TRUE(refused->has_error());
  EXPECT_EQ(refused->error().message(), "batch 'b' belongs to another client");

  RawPeer owner(broker->client_endpoint());
  owner.Send(SubmitMessage({}));
  // The owner's claim is in before a worker comes: a job of a restored batch that finishes while the batch is
  // unclaimed is kept in the journal and sent when its client submits it again, which this claim (no jobs) does not.
  ASSERT_TRUE(WaitFor([&] { return broker->stats().clients == 1; }));
  EchoWorker worker(TestWorkerOptions(broker->worker_endpoint(), "w", 1));
  std::optional<v1::Result> result = AwaitResult(owner);
  ASSERT_TRUE(result.has_value());
  EXPECT_EQ(result->job_id(), "j0");
  EXPECT_EQ(result->fitness(), 6.25);
  EXPECT_FALSE(AwaitResult(thief, milliseconds(300)).has_value());
}

TEST_F(BrokerRestartTest, ABatchWhoseClientDoesNotComeBackIsDroppedFromTheJournal) {
  auto broker = std::make_unique<BrokerThread>(Options());
  RawPeer old_client(broker->client_endpoint());
  old_client.Send(SubmitMessage({MakeJob("j0", 0)}));
  ASSERT_TRUE(WaitFor([&] { return broker->stats().queued == 1; }));
  broker = Restart(std::move(broker));
  old_client.Close();
  ASSERT_TRUE(WaitFor([&] { return broker->stats().jobs_restored == 1; }));
  EXPECT_EQ(broker->stats().batches, 1);
  // Two liveness periods (1 s with the test heartbeat) later, nobody has claimed it.
  ASSERT_TRUE(WaitFor([&] { return broker->stats().batches_unclaimed == 1; }, milliseconds(5000)));
  EXPECT_EQ(broker->stats().batches, 0);
  EXPECT_EQ(broker->stats().queued, 0u);
  broker->Stop();
  BrokerJournal journal(dir_.PathOf("journal.db"));
  EXPECT_TRUE(journal.Batches().empty());
  EXPECT_TRUE(AllJobs(journal).empty());
}

TEST_F(BrokerRestartTest, WithoutAJournalARestartedBrokerKnowsNothing) {
  broker::BrokerOptions options = TestBrokerOptions(&log_);
  auto broker = std::make_unique<BrokerThread>(options);
  {
    RawPeer client(broker->client_endpoint());
    client.Send(SubmitMessage({MakeJob("j0", 0)}));
    ASSERT_TRUE(WaitFor([&] { return broker->stats().queued == 1; }));
  }
  options.client_port = PortOf(broker->client_endpoint());
  options.worker_port = PortOf(broker->worker_endpoint());
  broker.reset();  // stops it and frees its ports
  broker = std::make_unique<BrokerThread>(options);
  RawPeer client(broker->client_endpoint());
  client.Send(SubmitMessage({}));  // an empty SUBMIT: answered once the broker runs, and opens batch "b" anew
  ASSERT_TRUE(WaitFor([&] { return broker->stats().batches == 1; }));
  EXPECT_EQ(broker->stats().queued, 0u);
  EXPECT_EQ(broker->stats().jobs_restored, 0u);
}

}  // namespace
}  // namespace orcs::test_support
