"""The Python client (clients/python/orcs_client) against a real orcs-broker and two real orcs-worker processes on
127.0.0.1: every result once with the bits of orcs-sim and of `orcs-batch submit` for the same jobs, a bad job's
status, no broker → a clean error in bounded time, a broker killed and restarted mid-batch; and its wire
behaviour (heartbeats, resubmission, duplicates, bad messages) against a scripted broker socket.

Run by CTest (tests/clients/python/CMakeLists.txt) with ORCS_BIN and ORCS_PYTHON_PATH set.
"""

import collections
import concurrent.futures
import json
import math
import os
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE_DIR = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
sys.path.insert(0, os.path.join(SOURCE_DIR, "clients", "python"))
sys.path.insert(0, HERE)

import zmq  # noqa: E402

from local_cluster import BIN, LocalCluster, unused_port  # noqa: E402
from orcs_client import (BatchClient, BrokerError, Job, Scenario, ScenarioError, broker_pb2,  # noqa: E402
                         result_pb2)

HEARTBEAT = 0.2  # seconds: the broker's, the workers' and the clients' interval (fast, so tests are short)

# Hip oscillators for a fifth of a second under two randomised parameter sets; a value file to resolve.
SCENARIO = {
    "name": "hips",
    "duration": 0.2,
    "value_files": ["hips.val"],
    "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
    "fitness": {"terms": [{"type": "distance", "body": "Middle/UpperBody", "axis": "z"}, {"type": "energy"}]},
    "randomisation": {"sets": 2, "default_motor_model": True},
    "genome": [20, 2, 0, 0, 20, 2, 3, 0],
}
GENOMES = [[20, 2, 0, 0, 20, 2, 3, 0], [27.5, 1.25, 0.3, 5, 27.5, 1.25, 3.3, -5], [10, 3, 0, 0, 10, 3, 1.5, 0]]
SEEDS = [1, 2, 3, 4]

cluster = None


def setUpModule():
    global cluster
    cluster = LocalCluster(workers=2, heartbeat=HEARTBEAT)


def tearDownModule():
    if cluster is not None:
        cluster.close()


def bits(value):
    """A double's exact bits as text, so that a mismatch shows both."""
    return float(value).hex()


class ScenarioFiles:
    """The test scenario and its value file in a temporary folder."""

    def __init__(self):
        self.folder = tempfile.TemporaryDirectory(prefix="orcs-python-client-")
        self.path = os.path.join(self.folder.name, "hips.json")
        with open(self.path, "w") as out:
            json.dump(SCENARIO, out)
        with open(os.path.join(self.folder.name, "hips.val"), "w") as out:
            out.write("#ORCS Values\n/AngularMotor/PID/Proportional=18\n")

    def write(self, name, text):
        path = os.path.join(self.folder.name, name)
        with open(path, "w") as out:
            out.write(text)
        return path


class RealBrokerTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.files = ScenarioFiles()
        cls.scenario = Scenario.load(cls.files.path)

    @classmethod
    def tearDownClass(cls):
        cls.files.folder.cleanup()

    def client(self, endpoint=None, **options):
        client = BatchClient(endpoint or cluster.clients, heartbeat=HEARTBEAT, **options)
        self.addCleanup(client.close)
        return client

    def test_every_result_once_with_the_bits_of_orcs_sim_and_orcs_batch(self):
        jobs = [self.scenario.job(genome, seed=seed, job_id="g%d-s%d" % (g, seed))
                for g, genome in enumerate(GENOMES) for seed in SEEDS]
        client = self.client()
        began = time.monotonic()
        batch = client.submit(jobs)
        arrived = list(batch.results(timeout=60))
        python_seconds = time.monotonic() - began

        counts = collections.Counter(result.job_id for result in arrived)
        self.assertEqual(set(counts), {job.job_id for job in jobs})
        self.assertEqual(set(counts.values()), {1}, "each job's result exactly once")
        self.assertEqual(batch.outstanding, 0)
        self.assertIsNone(batch.next(timeout=0.1), "nothing after the last result")
        self.assertEqual(client.stats()["results"], len(jobs))
        by_id = {result.job_id: result for result in arrived}
        for result in arrived:
            self.assertEqual(result.status, "ok", result.message)
            self.assertEqual(result.batch_id, batch.batch_id)
            self.assertTrue(math.isfinite(result.fitness))
            self.assertEqual(list(result.terms), ["distance", "energy"])
            self.assertEqual(len(result.proto.parameter_sets), 2)
            self.assertIn(result.worker_id, {"py-worker-0", "py-worker-1"})
        self.assertEqual({result.worker_id for result in arrived}, {"py-worker-0", "py-worker-1"},
                         "both workers served the batch")

        # The same jobs through the C++ client: `orcs-batch submit` on the same broker, the same bits.
        genomes = self.files.write("genomes.jsonl", "".join(json.dumps(g) + "\n" for g in GENOMES))
        out = os.path.join(self.files.folder.name, "cpp")
        began = time.monotonic()
        run = subprocess.run([os.path.join(BIN, "orcs-batch"), "submit", "--broker", cluster.clients, "--heartbeat",
                              str(HEARTBEAT), self.files.path, "--genomes", genomes, "--jobs", str(len(SEEDS)),
                              "--seed", str(SEEDS[0]), "--out", out, "--quiet"],
                             capture_output=True, text=True, timeout=120)
        cpp_seconds = time.monotonic() - began
        self.assertEqual(run.returncode, 0, run.stderr)
        with open(os.path.join(out, "results.jsonl")) as lines:
            cpp = [json.loads(line) for line in lines]
        self.assertEqual(len(cpp), len(jobs))
        for line in cpp:
            mine = by_id["g%d-s%d" % (line["genome_index"], line["seed"])]
            self.assertEqual(bits(mine.fitness), bits(line["fitness"]), line["id"])
            self.assertEqual({k: bits(v) for k, v in mine.terms.items()},
                             {k: bits(v) for k, v in line["terms"].items()}, line["id"])
            for mine_set, cpp_set in zip(mine.proto.parameter_sets, line["sets"]):
                self.assertEqual(bits(mine_set.fitness), bits(cpp_set["fitness"]), line["id"])
                self.assertEqual({d.path: bits(d.value) for d in mine_set.drawn},
                                 {k: bits(v) for k, v in cpp_set["drawn"].items()}, line["id"])
        print("\n%d jobs: Python client %.2f s (%.1f jobs/s); orcs-batch submit %.2f s (%.1f jobs/s, with its "
              "start and checks)" % (len(jobs), python_seconds, len(jobs) / python_seconds, cpp_seconds,
                                     len(jobs) / cpp_seconds), file=sys.stderr)

        # And one job replayed in-process by orcs-sim --scenario.
        sim = subprocess.run([os.path.join(BIN, "orcs-sim"), "--scenario", self.files.path, "--genome",
                              json.dumps(GENOMES[1]), "--seed", "3"], capture_output=True, text=True, timeout=120)
        self.assertEqual(sim.returncode, 0, sim.stderr)
        replay = json.loads(sim.stdout)
        self.assertEqual(bits(by_id["g1-s3"].fitness), bits(replay["fitness"]))
        self.assertEqual([bits(s.fitness) for s in by_id["g1-s3"].proto.parameter_sets],
                         [bits(s["fitness"]) for s in replay["sets"]])

    def test_a_bad_job_says_invalid_input_and_the_batch_goes_on(self):
        client = self.client()
        batch = client.submit([self.scenario.job([1, 2, 3], seed=1, job_id="short-genome"),
                               self.scenario.job(seed=1, overrides={"/No/Such/Path": 1.5}, job_id="bad-override"),
                               self.scenario.job(seed=1, job_id="good")])
        results = {result.job_id: result for result in batch.results(timeout=60)}
        self.assertEqual(results["short-genome"].status, "invalid_input")
        self.assertIsNone(results["short-genome"].fitness)
        self.assertIn("genome", results["short-genome"].message)
        self.assertEqual(results["bad-override"].status, "invalid_input")
        self.assertIn("/No/Such/Path", results["bad-override"].message)
        self.assertEqual(results["good"].status, "ok", results["good"].message)

    def test_a_client_slower_than_the_broker_is_not_taken_for_lost(self):
        # The broker beats every HEARTBEAT s and calls a peer silent for 5 of them (1 s) lost; this client beats
        # every 2.5 s and says so, and the broker waits for it at its pace through a batch of several seconds.
        def broker_log():
            with open(os.path.join(cluster.folder, "broker.log"), errors="replace") as log:
                return log.read()
        longer = Scenario.load(self.files.write("hips-2s.json", json.dumps(dict(SCENARIO, duration=2.0))))
        before = broker_log().count(" lost")
        client = BatchClient(cluster.clients, heartbeat=2.5)
        self.addCleanup(client.close)
        started = time.monotonic()
        batch = client.submit([longer.job(genome, seed=seed, job_id="slow-%d-%d" % (g, seed))
                               for g, genome in enumerate(GENOMES) for seed in SEEDS])
        results = list(batch.results(timeout=120))
        self.assertGreater(time.monotonic() - started, 1.0, "too short to tell")
        self.assertEqual(len(results), len(GENOMES) * len(SEEDS))
        self.assertTrue(all(r.status == "ok" for r in results), [r.message for r in results])
        self.assertEqual(broker_log().count(" lost"), before, broker_log()[-2000:])

    def test_no_broker_is_a_clean_error_in_bounded_time(self):
        endpoint = "tcp://127.0.0.1:%d" % unused_port()
        client = self.client(endpoint, connect_timeout=1.0)
        began = time.monotonic()
        with self.assertRaises(BrokerError) as raised:
            client.submit([self.scenario.job(seed=1)])
        elapsed = time.monotonic() - began
        self.assertEqual(str(raised.exception), "no broker answering at %s after 1 s" % endpoint)
        self.assertGreaterEqual(elapsed, 0.9)
        self.assertLess(elapsed, 4.0)
        with self.assertRaises(BrokerError):  # the client stays failed: make a new one
            client.submit([self.scenario.job(seed=2)])

    def test_bad_arguments_are_errors_before_anything_is_sent(self):
        with self.assertRaisesRegex(ValueError, "cannot connect to 'nonsense'"):
            BatchClient("nonsense")
        client = self.client()
        with self.assertRaisesRegex(ValueError, "job 1: job_id 'a' repeated"):
            client.submit([self.scenario.job(seed=1, job_id="a"), self.scenario.job(seed=2, job_id="a")])
        with self.assertRaisesRegex(ValueError, r"genome\[1\]: expected a finite number, found nan"):
            self.scenario.job([1.0, float("nan")])
        self.assertEqual(client.stats()["connections"], 0, "nothing was sent")

    def test_a_scenario_is_resolved_by_orcs_batch_with_its_files_inlined(self):
        scenario = Scenario.load(os.path.join(SOURCE_DIR, "scenarios", "examples", "pendulum_keyframes.json"))
        self.assertEqual(scenario.name, "pendulum-keyframes")
        with open(os.path.join(SOURCE_DIR, "scenarios", "examples", "pendulum_quarter.csv")) as record:
            self.assertEqual(scenario.data["controller"]["record"]["text"], record.read())
        with open(os.path.join(SOURCE_DIR, "scenarios", "environments", "pendulum.xml")) as xml:
            self.assertEqual(scenario.data["environment"]["xml"], xml.read())
        self.assertEqual(self.scenario.data["value_files"][0]["file"], "hips.val")

        missing = self.files.write("missing.json", json.dumps(dict(SCENARIO, value_files=["nowhere.val"])))
        with self.assertRaises(ScenarioError) as raised:
            Scenario.load(missing)
        self.assertIn("nowhere.val", str(raised.exception))
        self.assertNotIn("\n", str(raised.exception))
        typo = self.files.write("typo.json", json.dumps(dict(SCENARIO, duration=-1)))
        with self.assertRaisesRegex(ScenarioError, r"typo\.json.*duration"):
            Scenario.load(typo)


class BrokerRestartTest(unittest.TestCase):
    """A broker killed mid-batch and started again on the same ports: the client connects again, resubmits the
    jobs still without a result, and hands out every result once."""

    def test_every_result_once_across_a_broker_restart(self):
        restart = LocalCluster(workers=2, heartbeat=HEARTBEAT)
        self.addCleanup(restart.close)
        files = ScenarioFiles()
        self.addCleanup(files.folder.cleanup)
        scenario = Scenario.load(files.path)
        jobs = [scenario.job(GENOMES[0], seed=seed) for seed in range(1, 17)]
        logged = []
        with BatchClient(restart.clients, heartbeat=HEARTBEAT, log=logged.append) as client:
            batch = client.submit(jobs)
            arrived = [batch.next(timeout=60), batch.next(timeout=60)]
            self.assertNotIn(None, arrived)
            restart.kill_broker()
            restart.start_broker(restart.port(restart.clients), restart.port(restart.worker_endpoint))
            arrived += list(batch.results(timeout=60))
            stats = client.stats()
        self.assertEqual(batch.job_ids, tuple("job-%02d" % index for index in range(16)))  # numbered by submit
        counts = collections.Counter(result.job_id for result in arrived)
        self.assertEqual(set(counts), set(batch.job_ids))
        self.assertEqual(set(counts.values()), {1})
        self.assertTrue(all(result.ok for result in arrived))
        self.assertGreaterEqual(stats["connections"], 2, logged)
        self.assertGreaterEqual(stats["submit_messages"], 2)
        self.assertTrue(any("connecting again" in line for line in logged), logged)


class WireTest(unittest.TestCase):
    """The client's messages, seen by a scripted broker socket (a ROUTER, as orcs-broker's)."""

    def setUp(self):
        self.context = zmq.Context()
        self.router = self.context.socket(zmq.ROUTER)
        self.router.setsockopt(zmq.LINGER, 0)
        self.router.bind("tcp://127.0.0.1:0")
        self.endpoint = self.router.getsockopt(zmq.LAST_ENDPOINT).decode()
        self.addCleanup(self.context.term)
        self.addCleanup(self.router.close)

    def receive(self, want, timeout=5.0):
        """The next (peer, ClientToBroker) whose body is `want`, skipping others; fails after timeout seconds."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if not self.router.poll(int((deadline - time.monotonic()) * 1000) + 1):
                break
            peer, payload = self.router.recv_multipart()
            message = broker_pb2.ClientToBroker()
            message.ParseFromString(payload)
            self.assertEqual(message.protocol_version, 1)
            if message.WhichOneof("body") == want:
                return peer, message, time.monotonic()
        self.fail("no %s from the client within %g s" % (want, timeout))

    def send(self, peer, **body):
        message = broker_pb2.BrokerToClient(protocol_version=1, **body)
        self.router.send_multipart([peer, message.SerializeToString()])

    def result(self, batch_id, job_id, fitness):
        return result_pb2.Result(protocol_version=1, batch_id=batch_id, job_id=job_id, status=1, fitness=fitness)

    def test_heartbeats_resubmission_after_silence_and_duplicates(self):
        files = ScenarioFiles()
        self.addCleanup(files.folder.cleanup)
        scenario = Scenario.load(files.path)
        client = BatchClient(self.endpoint, heartbeat=0.1, liveness=6, log=lambda line: None)
        self.addCleanup(client.close)
        with concurrent.futures.ThreadPoolExecutor(1) as pool:
            submitting = pool.submit(client.submit, [scenario.job(seed=1, job_id="a"),
                                                     scenario.job(seed=2, job_id="b")])
            peer, submit, _ = self.receive("submit")
            self.assertEqual([job.job_id for job in submit.submit.jobs], ["a", "b"])
            self.assertEqual(submit.submit.client_id, client.client_id)
            for job in submit.submit.jobs:
                self.assertEqual(job.batch_id, submit.submit.batch_id)
                self.assertEqual(job.scenario_json, scenario.text)
            self.send(peer, accepted=broker_pb2.Accepted(batch_id=submit.submit.batch_id, job_count=2))
            batch = submitting.result(timeout=5)
        batch_id = batch.batch_id

        # Heartbeats every 0.1 s while jobs are outstanding, on the same connection as long as the broker answers.
        times = []
        for _ in range(6):
            heartbeat_peer, _, received = self.receive("heartbeat")
            self.assertEqual(heartbeat_peer, peer)
            self.send(peer, heartbeat=broker_pb2.Heartbeat())
            times.append(received)
        gaps = [later - earlier for earlier, later in zip(times, times[1:])]
        self.assertTrue(all(gap > 0.05 for gap in gaps), gaps)  # not more often than the interval
        self.assertLess(sorted(gaps)[len(gaps) // 2], 0.2, gaps)  # and about every interval (the median)

        # A message that is no protocol message is dropped; a result comes once, its duplicate is dropped.
        self.router.send_multipart([peer, b"\xff\xfe not protobuf"])
        self.send(peer, result=self.result(batch_id, "a", 0.5))
        self.send(peer, result=self.result(batch_id, "a", 0.5))
        first = batch.next(timeout=5)
        self.assertEqual((first.job_id, first.fitness), ("a", 0.5))

        # Silent for liveness × heartbeat (0.6 s): a new connection resubmits the job still without a result.
        deadline = time.monotonic() + 5
        while True:
            again_peer, again, _ = self.receive("submit", timeout=max(0.1, deadline - time.monotonic()))
            if again_peer != peer:
                break
        self.assertEqual([job.job_id for job in again.submit.jobs], ["b"])
        self.assertEqual(again.submit.batch_id, batch_id)
        self.send(again_peer, accepted=broker_pb2.Accepted(batch_id=batch_id, job_count=1))
        self.send(again_peer, result=self.result(batch_id, "b", 0.25))
        self.assertEqual([r.job_id for r in batch.results(timeout=5)], ["b"])
        stats = client.stats()
        self.assertEqual(stats["duplicates_dropped"], 1)
        self.assertEqual(stats["messages_dropped"], 1)
        self.assertEqual(stats["connections"], 2)
        self.assertEqual(stats["results"], 2)

        # Leaving: the client says DISCONNECT.
        client.close()
        self.receive("disconnect")

    def test_a_rejected_batch_is_an_error_naming_it(self):
        client = BatchClient(self.endpoint, heartbeat=0.1, log=lambda line: None)
        self.addCleanup(client.close)
        job = Job(job_id="x", scenario_json="{}", genome_json="[]")
        with concurrent.futures.ThreadPoolExecutor(1) as pool:
            submitting = pool.submit(client.submit, [job])
            peer, submit, _ = self.receive("submit")
            self.send(peer, error=broker_pb2.Error(batch_id=submit.submit.batch_id, message="job 0: too odd"))
            with self.assertRaises(BrokerError) as raised:
                submitting.result(timeout=5)
        self.assertEqual(str(raised.exception), "the broker at %s rejected batch %s: job 0: too odd"
                         % (self.endpoint, submit.submit.batch_id))


if __name__ == "__main__":
    unittest.main()
