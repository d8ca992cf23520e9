// The broker with CURVE (docs/security.md), on real sockets on 127.0.0.1 with ephemeral ports: allowed workers and
// clients complete a batch; a client or worker with an unknown key, without CURVE, or with a key of the other side
// gets nothing — its messages never reach the broker's handlers — and the broker counts and logs the refusal.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "broker/broker.h"
#include "net/curve_keys.h"
#include "proto/envelope.h"
#include "tests/broker/test_peers.h"
#include "tests/support/temp_dir.h"

namespace orcs::test_support {
namespace {

namespace fs = std::filesystem;
using runtime::BatchClient;
using runtime::BatchClientError;
using net::CurveKeyPair;
using std::chrono::milliseconds;
using ::testing::AllOf;
using ::testing::HasSubstr;

using Clock = std::chrono::steady_clock;

// How long a refused client tries before Submit() gives up; short, since no answer is coming.
constexpr milliseconds kRefusedConnectTimeout{1000};
// How long a test listens for what must not come, after the refusal it waits for has been seen.
constexpr milliseconds kQuietPeriod{300};

std::vector<v1::Job> MakeJobs(const std::string& prefix, int count) {
  std::vector<v1::Job> jobs;
  for (int i = 0; i < count; ++i) jobs.push_back(MakeJob(prefix + std::to_string(i), static_cast<std::uint64_t>(i)));
  return jobs;
}

void WritePair(const fs::path& dir, const std::string& name, const CurveKeyPair& pair) {
  net::WriteCurveKeyPair(dir, name, pair);
}

// The message of the BatchClientError `submit` ends with; fails the test when it ends without one.
std::string SubmitError(BatchClient& client) {
  try {
    client.Submit(MakeJobs("refused-", 2));
  } catch (const BatchClientError& error) {
    return error.what();
  }
  ADD_FAILURE() << "Submit succeeded";
  return "";
}

class CurveTest : public ::testing::Test {
 protected:
  // Four folders: the cluster's (broker, worker and client pairs; the worker's and the client's keys allowed),
  // bob's (another allowed client's pair and broker.pub),
  // a stranger's (its own worker and client pairs, the right broker.pub: it knows the broker, the broker does not
  // know it), and a swapped one (the allowed worker's pair as client.*, the allowed client's pair as worker.*).
  void SetUp() override {
    worker_pair_ = net::GenerateCurveKeyPair();
    client_pair_ = net::GenerateCurveKeyPair();
    WritePair(cluster(), "broker", net::GenerateCurveKeyPair());
    WritePair(cluster(), "worker", worker_pair_);
    WritePair(cluster(), "client", client_pair_);
    fs::create_directories(cluster() / "allowed_workers");
    fs::create_directories(cluster() / "allowed_clients");
    fs::copy_file(cluster() / "worker.pub", cluster() / "allowed_workers/worker.pub");
    fs::copy_file(cluster() / "client.pub", cluster() / "allowed_clients/client.pub");

    WritePair(bob(), "client", net::GenerateCurveKeyPair());
    fs::copy_file(cluster() / "broker.pub", bob() / "broker.pub");
    fs::copy_file(bob() / "client.pub", cluster() / "allowed_clients/bob.pub");

    stranger_client_ = net::GenerateCurveKeyPair();
    WritePair(stranger(), "worker", net::GenerateCurveKeyPair());
    WritePair(stranger(), "client", stranger_client_);
    fs::copy_file(cluster() / "broker.pub", stranger() / "broker.pub");

    WritePair(swapped(), "client", worker_pair_);
    WritePair(swapped(), "worker", client_pair_);
    fs::copy_file(cluster() / "broker.pub", swapped() / "broker.pub");
  }

  fs::path cluster() const { return dir_.path() / "cluster"; }
  fs::path stranger() const { return dir_.path() / "stranger"; }
  fs::path bob() const { return dir_.path() / "bob"; }
  fs::path swapped() const { return dir_.path() / "swapped"; }

  broker::BrokerOptions BrokerOptions() {
    broker::BrokerOptions options = TestBrokerOptions(&log_);
    options.curve_keys = cluster().string();
    return options;
  }
  worker::WorkerConnectionOptions WorkerOptions(BrokerThread& broker, const std::string& name,
                                                const fs::path& keys) {
    worker::WorkerConnectionOptions options = TestWorkerOptions(broker.worker_endpoint(), name, 2, &peer_log_);
    options.curve_keys = keys.string();
    return options;
  }
  runtime::BatchClientOptions ClientOptions(BrokerThread& broker, const fs::path& keys) {
    runtime::BatchClientOptions options = TestClientOptions(broker.client_endpoint(), &peer_log_);
    options.curve_keys = keys.string();
    options.connect_timeout = kRefusedConnectTimeout;
    return options;
  }

  TempDir dir_;
  LogLines log_;       ///< the broker's
  LogLines peer_log_;  ///< the workers' and clients'
  CurveKeyPair worker_pair_;
  CurveKeyPair client_pair_;
  CurveKeyPair stranger_client_;
};

TEST_F(CurveTest, AllowedWorkerAndClientCompleteABatch) {
  BrokerThread broker(BrokerOptions());
  EchoWorker worker(WorkerOptions(broker, "allowed", cluster()));
  ASSERT_TRUE(WaitFor([&] { return broker.stats().workers == 1; }));
  BatchClient client(ClientOptions(broker, cluster()));
  client.Submit(MakeJobs("job-", 20));
  const std::vector<v1::Result> results = Collect(client, 20);
  ASSERT_EQ(results.size(), 20u);
  std::set<std::string> ids;
  for (const v1::Result& result : results) {
    EXPECT_EQ(result.status(), v1::Result::OK);
    EXPECT_EQ(result.worker_id(), "allowed");
    EXPECT_EQ(result.fitness(), 2.0 * std::stod(result.job_id().substr(4)) + 0.25);
    ids.insert(result.job_id());
  }
  EXPECT_EQ(ids.size(), 20u);
  const broker::BrokerStats stats = broker.stats();
  EXPECT_EQ(stats.handshakes_refused, 0u);  // (handshakes_failed counts the connections' endpoint probes)
  EXPECT_EQ(log_.Count("CURVE on"), 1);
  EXPECT_EQ(log_.Count("1 worker keys and 2 client keys allowed"), 1);
}

TEST_F(CurveTest, ClientWithUnknownKeyCannotSubmit) {
  BrokerThread broker(BrokerOptions());
  EchoWorker worker(WorkerOptions(broker, "allowed", cluster()));
  ASSERT_TRUE(WaitFor([&] { return broker.stats().workers == 1; }));
  BatchClient client(ClientOptions(broker, stranger()));
  const Clock::time_point start = Clock::now();
  EXPECT_THAT(SubmitError(client), AllOf(HasSubstr("no broker answering"), HasSubstr("the key was refused")));
  EXPECT_LT(Clock::now() - start, kRefusedConnectTimeout + std::chrono::seconds(2));
  EXPECT_GE(client.stats().handshake_failures, 1u);
  ASSERT_TRUE(WaitFor([&] { return broker.stats().handshakes_refused >= 1; }));
  EXPECT_EQ(log_.Count("refused a client connection from 127.0.0.1: its CURVE key " + stranger_client_.public_key +
                       " is not allowed on the client socket"),
            1);
  const broker::BrokerStats stats = broker.stats();
  EXPECT_EQ(stats.jobs_accepted, 0u);
  EXPECT_EQ(stats.clients, 0);
  EXPECT_EQ(stats.messages_dropped, 0u);
  EXPECT_EQ(worker.jobs_done(), 0);
  EXPECT_EQ(peer_log_.Count("is client.pub in the broker's allowed_clients/"), 1);
}

// A client's HEARTBEAT from a connection the broker does not know is answered with DISCONNECT: the answer shows
// that a message reached the broker's handlers. With an allowed key it comes; with an unknown one nothing does.
TEST_F(CurveTest, ClientWithUnknownKeyReceivesNothing) {
  BrokerThread broker(BrokerOptions());
  v1::ClientToBroker heartbeat;
  heartbeat.set_protocol_version(proto::kProtocolVersion);
  heartbeat.mutable_heartbeat();

  RawPeer allowed(broker.client_endpoint(), net::LoadCurvePeerKeys(cluster(), "client"));
  allowed.Send(heartbeat);
  std::optional<v1::BrokerToClient> answer = allowed.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(5000));
  ASSERT_TRUE(answer.has_value());
  EXPECT_TRUE(answer->has_disconnect());

  RawPeer unknown(broker.client_endpoint(), net::LoadCurvePeerKeys(stranger(), "client"));
  unknown.Send(heartbeat);
  unknown.Send(v1::ClientToBroker());  // garbage would be counted as dropped, had it arrived
  ASSERT_TRUE(WaitFor([&] { return broker.stats().handshakes_refused >= 1; }));
  EXPECT_FALSE(unknown.Receive(kQuietPeriod).has_value());
  EXPECT_EQ(broker.stats().messages_dropped, 0u);
  EXPECT_EQ(broker.stats().clients, 0);
}

// The broker sees a peer without CURVE as a connection closed during its handshake (the peer notices the
// mismatch first and hangs up): counted in handshakes_failed, not logged (port scans look the same).
TEST_F(CurveTest, ClientWithoutCurveCannotSubmitOrReceive) {
  BrokerThread broker(BrokerOptions());
  v1::ClientToBroker heartbeat;
  heartbeat.set_protocol_version(proto::kProtocolVersion);
  heartbeat.mutable_heartbeat();
  RawPeer plain(broker.client_endpoint());
  plain.Send(heartbeat);
  ASSERT_TRUE(WaitFor([&] { return broker.stats().handshakes_failed >= 1; }));
  EXPECT_FALSE(plain.Receive(kQuietPeriod).has_value());
  EXPECT_EQ(broker.stats().clients, 0);
  EXPECT_EQ(broker.stats().handshakes_refused, 0u);  // it never got as far as showing a key

  runtime::BatchClientOptions options = ClientOptions(broker, cluster());
  options.curve_keys.clear();
  BatchClient client(options);
  const Clock::time_point start = Clock::now();
  EXPECT_THAT(SubmitError(client), HasSubstr("no broker answering"));
  EXPECT_LT(Clock::now() - start, kRefusedConnectTimeout + std::chrono::seconds(2));
  EXPECT_EQ(broker.stats().jobs_accepted, 0u);
  EXPECT_EQ(broker.stats().messages_dropped, 0u);
}

// The other way round: a CURVE client of a broker without CURVE is told that the handshake failed (as a mechanism
// mismatch, or as a connection closed during the handshake, depending on which side notices first).
TEST_F(CurveTest, CurveClientOfPlainBrokerSaysWhy) {
  BrokerThread broker(TestBrokerOptions(&log_));
  BatchClient client(ClientOptions(broker, cluster()));
  EXPECT_THAT(SubmitError(client), AllOf(HasSubstr("no broker answering"), HasSubstr("the CURVE handshake failed: ")));
  EXPECT_EQ(broker.stats().jobs_accepted, 0u);
}

TEST_F(CurveTest, WorkerWithUnknownKeyNeverGetsAJob) {
  BrokerThread broker(BrokerOptions());
  EchoWorker stranger_worker(WorkerOptions(broker, "stranger", stranger()));
  ASSERT_TRUE(WaitFor([&] {
    return broker.stats().handshakes_refused >= 1 && stranger_worker.connection().stats().handshake_failures >= 1;
  }));
  BatchClient client(ClientOptions(broker, cluster()));
  client.Submit(MakeJobs("job-", 4));
  EXPECT_FALSE(client.Next(kQuietPeriod).has_value());
  EXPECT_EQ(broker.stats().workers, 0);
  EXPECT_EQ(broker.stats().jobs_dispatched, 0u);
  EXPECT_GE(log_.Count("refused a worker connection from 127.0.0.1"), 1);
  EXPECT_EQ(peer_log_.Count("is worker.pub in the broker's allowed_workers/"), 1);

  EchoWorker allowed(WorkerOptions(broker, "allowed", cluster()));
  const std::vector<v1::Result> results = Collect(client, 4);
  ASSERT_EQ(results.size(), 4u);
  for (const v1::Result& result : results) EXPECT_EQ(result.worker_id(), "allowed");
  EXPECT_EQ(stranger_worker.jobs_done(), 0);
  EXPECT_EQ(stranger_worker.connection().stats().jobs_received, 0u);
}

TEST_F(CurveTest, WorkerKeyOnClientSocketAndClientKeyOnWorkerSocketAreRefused) {
  BrokerThread broker(BrokerOptions());
  BatchClient client(ClientOptions(broker, swapped()));  // speaks with the allowed worker's key
  EXPECT_THAT(SubmitError(client), HasSubstr("the key was refused"));
  EXPECT_EQ(log_.Count("its CURVE key " + worker_pair_.public_key + " is not allowed on the client socket (it is a "
                       "worker's key: " + (cluster() / "allowed_workers/worker.pub").string() + ")"),
            1);

  EchoWorker worker(WorkerOptions(broker, "client-key", swapped()));  // speaks with the allowed client's key
  ASSERT_TRUE(WaitFor([&] { return worker.connection().stats().handshake_failures >= 1; }));
  EXPECT_EQ(log_.Count("its CURVE key " + client_pair_.public_key + " is not allowed on the worker socket (it is a "
                       "client's key: " + (cluster() / "allowed_clients/client.pub").string() + ")"),
            1);
  EXPECT_EQ(broker.stats().workers, 0);
  EXPECT_EQ(broker.stats().jobs_accepted, 0u);
  EXPECT_GE(broker.stats().handshakes_refused, 2u);
}

// A batch id and a client id are names others can read in logs; a batch belongs to the owner token and, with CURVE,
// to the key that opened it, so another allowed client cannot take it over by naming it (which would move its
// results).
TEST_F(CurveTest, AnotherAllowedClientCannotTakeOverABatch) {
  BrokerThread broker(BrokerOptions());
  BatchClient alice(ClientOptions(broker, cluster()));
  alice.Submit(MakeJobs("job-", 2));  // no worker yet: the jobs wait

  RawPeer bob_peer(broker.client_endpoint(), net::LoadCurvePeerKeys(bob(), "client"));
  v1::ClientToBroker takeover;
  takeover.set_protocol_version(proto::kProtocolVersion);
  takeover.mutable_submit()->set_batch_id(alice.batch_id());
  takeover.mutable_submit()->set_client_id(alice.client_id());
  takeover.mutable_submit()->set_owner_token(std::string(16, 'x'));
  bob_peer.Send(takeover);
  std::optional<v1::BrokerToClient> answer = bob_peer.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(5000));
  ASSERT_TRUE(answer.has_value());
  ASSERT_TRUE(answer->has_error());
  EXPECT_EQ(answer->error().message(), "batch '" + alice.batch_id() + "' belongs to another client");

  EchoWorker worker(WorkerOptions(broker, "allowed", cluster()));
  EXPECT_EQ(Collect(alice, 2).size(), 2u);
  EXPECT_EQ(broker.stats().submits_rejected, 1u);
}

// The journal records each batch's key: a batch restored from it belongs to the key that opened it, even against
// an allowed client that has the owner token (stolen, say, from the owner's machine).
TEST_F(CurveTest, ABatchRestoredFromTheJournalStaysWithTheKeyThatOpenedIt) {
  broker::BrokerOptions options = BrokerOptions();
  options.journal = (dir_.path() / "journal.db").string();
  auto broker = std::make_unique<BrokerThread>(options);
  v1::ClientToBroker submit;
  submit.set_protocol_version(proto::kProtocolVersion);
  submit.mutable_submit()->set_batch_id("b");
  submit.mutable_submit()->set_client_id("c");
  submit.mutable_submit()->set_owner_token(std::string(16, 'o'));
  *submit.mutable_submit()->add_jobs() = MakeJob("j0", 3);
  {
    RawPeer alice(broker->client_endpoint(), net::LoadCurvePeerKeys(cluster(), "client"));
    alice.Send(submit);
    ASSERT_TRUE(WaitFor([&] { return broker->stats().jobs_accepted == 1; }));
    options.client_port = std::stoi(broker->client_endpoint().substr(broker->client_endpoint().rfind(':') + 1));
    options.worker_port = std::stoi(broker->worker_endpoint().substr(broker->worker_endpoint().rfind(':') + 1));
    broker->Stop();
  }
  broker.reset();  // frees the ports: Stop() alone leaves them to the context's teardown
  broker = std::make_unique<BrokerThread>(options);
  ASSERT_TRUE(WaitFor([&] { return broker->stats().jobs_restored == 1; }));

  RawPeer bob_peer(broker->client_endpoint(), net::LoadCurvePeerKeys(bob(), "client"));
  bob_peer.Send(submit);  // first after the restart, with the right token, but not alice's key
  std::optional<v1::BrokerToClient> answer = bob_peer.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(5000));
  ASSERT_TRUE(answer.has_value());
  ASSERT_TRUE(answer->has_error());
  EXPECT_EQ(answer->error().message(), "batch 'b' belongs to another client key");

  RawPeer alice(broker->client_endpoint(), net::LoadCurvePeerKeys(cluster(), "client"));
  alice.Send(submit);
  ASSERT_TRUE(WaitFor([&] { return broker->stats().clients == 1; }));
  EchoWorker worker(WorkerOptions(*broker, "allowed", cluster()));
  std::optional<v1::Result> result;
  ASSERT_TRUE(WaitFor([&] {
    std::optional<v1::BrokerToClient> message = alice.ReceiveEnvelope<v1::BrokerToClient>(milliseconds(50));
    if (message && message->has_result()) result = message->result();
    return result.has_value();
  }));
  EXPECT_EQ(result->job_id(), "j0");
  EXPECT_EQ(result->fitness(), EchoFitness(MakeJob("j0", 3)));
}

TEST_F(CurveTest, MissingKeysAreClearErrorsNamingTheFile) {
  broker::BrokerOptions options = BrokerOptions();
  options.curve_keys = stranger().string();  // no broker.key there
  try {
    broker::Broker broker(options);
    ADD_FAILURE() << "the broker started without its key";
  } catch (const net::CurveKeyError& error) {
    EXPECT_EQ(std::string(error.what()), (stranger() / "broker.key").string() + ": no such file");
  }
  fs::remove(stranger() / "broker.pub");
  worker::WorkerConnectionOptions worker_options = TestWorkerOptions("tcp://127.0.0.1:1", "w", 2);
  worker_options.curve_keys = stranger().string();
  EXPECT_THROW(worker::WorkerConnection connection(worker_options), net::CurveKeyError);
  runtime::BatchClientOptions client_options = TestClientOptions("tcp://127.0.0.1:1");
  client_options.curve_keys = (dir_.path() / "nowhere").string();
  try {
    BatchClient client(client_options);
    ADD_FAILURE() << "the client started without its key";
  } catch (const net::CurveKeyError& error) {
    EXPECT_EQ(std::string(error.what()), (dir_.path() / "nowhere/client.key").string() + ": no such file");
  }
}

}  // namespace
}  // namespace orcs::test_support
