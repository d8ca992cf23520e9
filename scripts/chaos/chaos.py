#!/usr/bin/env python3
"""The chaos soak (issue 47): real brokers, workers and clients under a seeded schedule of faults, with the
invariants checked throughout. scripts/chaos.sh is the entry; docs/reliability.md, "Chaos soak", describes it.

What runs:
- loopback: a standing `orcs-broker --journal` on 127.0.0.1, three `orcs-worker`s, two users with
  `orcs-batch submit` (alice: short jobs, bob: longer ones) and one hand-made client (carol, below) that submits
  and then CANCELs;
- network namespaces (when they can be made): a head node with an `orcs-broker --bind '*' --curve-keys` (no
  journal), two worker nodes joined to it by veth pairs (10.200.1.0/24 and 10.200.2.0/24, addresses only inside
  the namespaces), one `orcs-worker --curve-keys` on each, and a user (dave) with `orcs-batch submit --curve-keys`
  on the second node.

The faults come from a schedule drawn from the seed alone (printed at the start; the same seed gives the same
schedule): SIGKILL and restart of workers, brokers and clients (a killed client is resumed with --resume),
SIGSTOP/SIGCONT of each, Ctrl-C (SIGINT to a client's process group; most are resumed), CANCELs, and a worker
node's link down for a while. What a fault hits is the schedule's, when it hits it is the schedule's; what the
programs are doing at that moment is not, so a replay repeats the faults, not every interleaving.

Invariants, checked throughout:
- every job of every batch that was not cancelled gets exactly one result, with the bits (fitness, and every
  parameter set's fitness, drawn values and terms) of an undisturbed run of the same job (computed once per job
  spec with `orcs-batch run` before the faults start);
- a cancelled or interrupted batch's results that did arrive are each once and have the same bits;
- no worker stays held by a batch that ended (it holds jobs, but none of a live batch) for more than 2 s, read
  from `orcs-broker status --json` twice a second;
- every batch finishes or is cancelled within its deadline;
- a Ctrl-C'd client exits within 5 s;
- the broker's resident memory stays flat.
Exit 0 when every invariant held, 1 when one was violated, 2 when the soak could not be set up.
"""

import argparse
import collections
import json
import os
import random
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import wire  # noqa: E402

HEARTBEAT = 0.25          # every program's heartbeat interval, s (liveness 5: a silent peer is lost after 1.25 s)
STATUS_PERIOD = 0.5       # how often each broker's status is read, s
WEDGE_LIMIT = 2.0         # the longest a worker may stay held by an ended batch, s
CTRL_C_LIMIT = 5.0        # the longest a client may take to exit after Ctrl-C, s
CLIENT_GRACE = 3.0        # --client-grace of the brokers (when the broker has the option)
# A batch may stay live this long after its client ended: the broker notices a silent client after liveness × H
# and keeps its batch for the grace period; then the batch must go (an ended client never comes back for it).
BATCH_OUTLIVES_LIMIT = CLIENT_GRACE + 5 * HEARTBEAT + WEDGE_LIMIT
MAX_WORKER_LOSSES = 50    # high, so that a job hit by several kills in a row is re-run, not failed WORKER_LOST

# Fault kinds and their weights in the schedule.
KINDS = [("worker_kill", 3), ("worker_stop", 2), ("broker_kill", 1), ("broker_stop", 1), ("client_kill", 2),
         ("client_stop", 2), ("client_int", 3), ("link_down", 2)]
DURATION = {  # seconds: how long a stop or a link-down lasts, or how long until a killed program is started again
    "worker_kill": (0.0, 2.0), "worker_stop": (0.5, 4.0), "broker_kill": (0.3, 2.0), "broker_stop": (0.5, 3.0),
    "client_kill": (0.0, 3.0), "client_stop": (0.5, 8.0), "client_int": (0.0, 3.0), "link_down": (1.0, 6.0)}

# The job specs: shipped scenarios cut short. (file under scenarios/, changes to its fields, seeds in the pool)
SPECS = {
    "swing": ("examples/swing_oscillator.json", {"duration": 0.2, "randomisation.sets": 2}),
    "stand": ("examples/stand_network.json", {"duration": 0.3, "randomisation.sets": 1, "log": []}),
}


def now():
    return time.monotonic()


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def fhex(value):
    return None if value is None else float(value).hex()


def canonical_line(line):
    """The bits of a results.jsonl line that an undisturbed run must reproduce."""
    sets = tuple((s["index"], fhex(s.get("fitness")), s.get("status"),
                  tuple(sorted((k, fhex(v)) for k, v in s.get("drawn", {}).items())),
                  tuple(sorted((k, fhex(v)) for k, v in s.get("terms", {}).items())))
                 for s in line.get("sets", []))
    return (line["status"], fhex(line.get("fitness")), sets)


class Soak:
    def __init__(self, args):
        self.args = args
        self.bin = os.path.abspath(args.bin)
        self.t0 = now()
        self.work = tempfile.mkdtemp(prefix="orcs-chaos.")
        self.logdir = os.path.join(self.work, "logs")
        os.makedirs(self.logdir)
        self.logfile = open(os.path.join(self.work, "chaos.log"), "w")
        self.procs = []          # every process started, for the cleanup
        self.pending = []        # (time, description, callable): SIGCONTs, restarts, link-ups, resumes
        self.violations = []
        self.faults = collections.Counter()
        self.skipped = collections.Counter()
        self.not_applicable = collections.Counter()  # faults on namespaces that could not be made
        self.ended_batches = {}  # broker batch id -> when its client's batch ended (finished, cancelled, given up)
        self.counts = collections.Counter()
        self.netns = []          # namespaces made (removed at the end)
        self.prefix = args.netns_prefix or "ochaos%d" % os.getpid()
        self.lock = threading.Lock()
        self.stop_polling = threading.Event()
        self.soaking = True      # faults and new batches only while True
        _, self.result_pb2, _, self.broker_pb2 = wire.load(self.bin, self.work)[0:4]
        self.revoke_in_schema = wire.has_field(self.broker_pb2.BrokerToWorker, "revoke")
        help_text = subprocess.run([self.exe("orcs-broker"), "--help"], capture_output=True, text=True).stdout
        self.broker_has_grace = "--client-grace" in help_text

    # --- little helpers ---------------------------------------------------------------------------------------
    def t(self):
        return now() - self.t0

    def log(self, message):
        line = "[%7.2f] %s" % (self.t(), message)
        with self.lock:
            print(line, file=self.logfile, flush=True)
            if self.args.verbose:
                print(line, flush=True)

    def say(self, message):
        print("chaos: " + message, flush=True)
        self.log(message)

    def violate(self, message):
        with self.lock:
            self.violations.append("[%.1f s] %s" % (self.t(), message))
        self.say("VIOLATION: " + message)

    def exe(self, name):
        return os.path.join(self.bin, name)

    def later(self, delay, what, action):
        self.pending.append((now() + delay, what, action))

    def start(self, name, argv, ns=None):
        log = open(os.path.join(self.logdir, "%s.log" % name), "ab")
        full = (["ip", "netns", "exec", ns] if ns else []) + argv
        proc = subprocess.Popen(full, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True)
        log.close()
        proc.chaos_name = name
        self.procs.append(proc)
        if os.environ.get("CHAOS_PIDFILE"):
            with open(os.environ["CHAOS_PIDFILE"], "a") as f:
                print(proc.pid, file=f)
        self.log("started %s (pid %d): %s" % (name, proc.pid, " ".join(argv)))
        return proc

    @staticmethod
    def alive(proc):
        return proc is not None and proc.poll() is None

    def signal(self, proc, sig, group=False):
        if not self.alive(proc):
            return False
        try:
            if group:
                os.killpg(proc.pid, sig)  # its own process group: start_new_session above
            else:
                os.kill(proc.pid, sig)
            return True
        except ProcessLookupError:
            return False

    # --- set-up ------------------------------------------------------------------------------------------------
    def make_specs(self):
        """Scenario files for each spec (shipped scenarios cut short), their resolved text, and the reference
        results of an undisturbed run of every seed in the pool."""
        self.specs = {}
        for name, (relative, changes) in SPECS.items():
            source = os.path.join(wire.SOURCE_DIR, "scenarios", relative)
            with open(source) as f:
                scenario = json.load(f)
            for key, value in changes.items():
                node = scenario
                *parents, last = key.split(".")
                for p in parents:
                    node = node[p]
                if last == "log" and value == []:
                    node.pop("log", None)
                else:
                    node[last] = value
            scenario["comment"] = "chaos soak: %s cut short (%s)" % (relative, json.dumps(changes))
            path = os.path.join(self.work, "%s.json" % name)
            with open(path, "w") as f:
                json.dump(scenario, f)
            resolved = subprocess.run([self.exe("orcs-batch"), "resolve", path], capture_output=True, text=True,
                                      check=True).stdout.strip()
            sim = scenario["duration"] * scenario.get("randomisation", {}).get("sets", 1)
            self.specs[name] = {"path": path, "resolved": resolved, "genome": json.dumps(scenario.get("genome", [])),
                                "time_limit": 30.0 + 10.0 * sim, "ref": {}}
        if self.args.reference == "run":
            self.reference()

    def reference(self):
        """Every seed of the pool run once, undisturbed: by `orcs-batch run` (its own broker and workers), or with
        --reference quiet by `orcs-batch submit` to the loopback broker before the first fault."""
        pool = self.args.pool
        for name, spec in self.specs.items():
            out = os.path.join(self.work, "reference", name)
            started = now()
            where = ["run", spec["path"], "--workers", "2"] if self.args.reference == "run" else \
                ["submit", spec["path"], "--broker", self.brokers[0].endpoint]
            run = subprocess.run([self.exe("orcs-batch")] + where + ["--jobs", str(pool), "--seed", "1", "--out", out,
                                                                     "--quiet"], capture_output=True, text=True,
                                 timeout=600)
            if run.returncode != 0:
                raise RuntimeError("the reference run of %s failed (exit %d): %s" % (name, run.returncode,
                                                                                  run.stderr[-2000:]))
            with open(os.path.join(out, "results.jsonl")) as f:
                for line in f:
                    row = json.loads(line)
                    spec["ref"][row["seed"]] = canonical_line(row)
            if len(spec["ref"]) != pool:
                raise RuntimeError("the reference run of %s gave %d results for %d seeds" % (name, len(spec["ref"]),
                                                                                            pool))
            self.say("reference: %d jobs of %s (%s) in %.1f s" % (pool, name, os.path.basename(spec["path"]),
                                                                  now() - started))

    def make_netns(self):
        """Three namespaces: head (the broker) and two worker nodes, each joined to the head by a veth pair."""
        if self.args.no_netns:
            self.netns_reason = "--no-netns"
            return False
        if os.geteuid() != 0 or shutil.which("ip") is None:
            self.netns_reason = "needs root and iproute2"
            return False
        head = self.prefix + "-head"
        nodes = [self.prefix + "-n1", self.prefix + "-n2"]
        try:
            for ns in [head] + nodes:
                subprocess.run(["ip", "netns", "add", ns], check=True, capture_output=True)
                self.netns.append(ns)
                subprocess.run(["ip", "-n", ns, "link", "set", "lo", "up"], check=True, capture_output=True)
            for i, ns in enumerate(nodes, 1):
                h, n = "vh%d" % i, "vn%d" % i
                for cmd in (["ip", "link", "add", h, "netns", head, "type", "veth", "peer", "name", n, "netns", ns],
                            ["ip", "-n", head, "addr", "add", "10.200.%d.1/24" % i, "dev", h],
                            ["ip", "-n", ns, "addr", "add", "10.200.%d.2/24" % i, "dev", n],
                            ["ip", "-n", head, "link", "set", h, "up"],
                            ["ip", "-n", ns, "link", "set", n, "up"]):
                    subprocess.run(cmd, check=True, capture_output=True)
        except subprocess.CalledProcessError as error:
            self.netns_reason = "cannot make network namespaces: %s" % (error.stderr or b"").decode().strip()
            self.remove_netns()
            return False
        self.head_ns, self.node_ns = head, nodes
        keys = os.path.join(self.work, "keys")
        subprocess.run([self.exe("orcs-keys"), "generate", keys, "broker", "worker", "client"], check=True,
                       capture_output=True)
        for role in ("workers", "clients"):
            os.makedirs(os.path.join(keys, "allowed_" + role))
            shutil.copy(os.path.join(keys, role[:-1] + ".pub"), os.path.join(keys, "allowed_" + role))
        self.keys = keys
        return True

    def remove_netns(self):
        for ns in self.netns:
            subprocess.run(["ip", "netns", "del", ns], capture_output=True)
        self.netns = []

    # --- the cluster -------------------------------------------------------------------------------------------
    def build(self):
        self.brokers = []
        cport, wport = free_port(), free_port()
        while wport == cport:
            wport = free_port()
        common = ["--heartbeat", str(HEARTBEAT), "--max-worker-losses", str(MAX_WORKER_LOSSES)]
        if self.broker_has_grace:
            common += ["--client-grace", str(CLIENT_GRACE)]
        loop = Broker(self, "loop-broker", None,
                      [self.exe("orcs-broker"), "--client-port", str(cport), "--worker-port", str(wport),
                       "--journal", os.path.join(self.work, "journal.sqlite")] + common,
                      "tcp://127.0.0.1:%d" % cport, [])
        self.brokers.append(loop)
        self.workers = [Worker(self, "loop-w%d" % i, None, "tcp://127.0.0.1:%d" % wport, loop) for i in range(3)]
        self.users = [BatchUser(self, "alice", None, loop, "swing", (6, 20), None),
                      BatchUser(self, "bob", None, loop, "stand", (3, 10), None),
                      CancelUser(self, "carol", loop, "swing", (8, 20))]
        self.nodes = []
        self.use_netns = self.make_netns()
        if self.use_netns:
            curve = ["--curve-keys", self.keys]
            ns_broker = Broker(self, "ns-broker", self.head_ns,
                               [self.exe("orcs-broker"), "--bind", "*", "--client-port", "5555", "--worker-port",
                                "5556"] + common + curve, "tcp://10.200.2.1:5555", curve)
            self.brokers.append(ns_broker)
            self.workers += [Worker(self, "ns-w%d" % i, ns, "tcp://10.200.%d.1:5556" % i, ns_broker, curve)
                             for i, ns in enumerate(self.node_ns, 1)]
            self.users.append(BatchUser(self, "dave", self.node_ns[1], ns_broker, "swing", (6, 16), curve))
            self.nodes = [(ns, "vn%d" % i) for i, ns in enumerate(self.node_ns, 1)]
        else:
            self.say("network namespaces skipped (%s): the loopback part runs alone" % self.netns_reason)
        for b in self.brokers:
            b.launch()
        for b in self.brokers:
            if not b.wait_ready(15):
                raise RuntimeError("%s did not answer a status request within 15 s (log: %s)" %
                                   (b.name, os.path.join(self.logdir, b.name + ".log")))
        for w in self.workers:
            w.launch()

    # --- the schedule ------------------------------------------------------------------------------------------
    def make_schedule(self):
        """The faults, from the seed alone: (time s, kind, target draw, duration s, a draw in [0, 1))."""
        rng = random.Random("chaos-schedule-%d" % self.args.seed)
        kinds = [k for k, _ in KINDS]
        weights = [w for _, w in KINDS]
        events, t = [], self.args.warmup
        end = self.args.minutes * 60.0
        while len(events) < 100000:
            t += rng.expovariate(1.0 / self.args.fault_interval)
            if t >= end:
                break
            kind = rng.choices(kinds, weights)[0]
            low, high = DURATION[kind]
            events.append((round(t, 2), kind, rng.randrange(1 << 30), round(rng.uniform(low, high), 2),
                           round(rng.random(), 3)))
        return events

    def targets(self, kind):
        if kind.startswith("worker"):
            return self.workers_all
        if kind.startswith("broker"):
            return self.brokers_all
        if kind.startswith("client"):
            return self.batch_users_all
        return self.nodes_all

    def inject(self, event):
        _, kind, draw, duration, p = event
        candidates = self.targets(kind)
        target = candidates[draw % len(candidates)]
        if target is None:  # a netns target while the namespaces could not be made
            self.not_applicable[kind] += 1
            return
        done = getattr(self, "fault_" + kind)(target, duration, p)
        if done:
            self.faults[kind] += 1
            self.log("FAULT %s on %s (%.2f s)" % (kind, getattr(target, "name", target), duration))
        else:
            self.skipped[kind] += 1
            self.log("fault %s on %s skipped: not running, or already stopped or down" % (
                kind, getattr(target, "name", target)))

    def fault_worker_kill(self, w, duration, p):
        return w.kill(duration)

    def fault_worker_stop(self, w, duration, p):
        return w.pause(duration)

    def fault_broker_kill(self, b, duration, p):
        return b.kill(duration)

    def fault_broker_stop(self, b, duration, p):
        return b.pause(duration)

    def fault_client_kill(self, u, duration, p):
        return u.kill(duration)

    def fault_client_stop(self, u, duration, p):
        return u.pause(duration)

    def fault_client_int(self, u, duration, p):
        return u.interrupt(duration, resume=p >= 0.2)

    def fault_link_down(self, node, duration, p):
        ns, dev = node
        if node in self.links_down:
            return False
        subprocess.run(["ip", "-n", ns, "link", "set", dev, "down"], check=True)
        self.links_down.add(node)
        self.link_changed[ns] = now()

        def up():
            subprocess.run(["ip", "-n", ns, "link", "set", dev, "up"], check=True)
            self.links_down.discard(node)
            self.link_changed[ns] = now()
        self.later(duration, "link %s up" % ns, up)
        return True

    # --- the run -----------------------------------------------------------------------------------------------
    def run(self):
        schedule = self.make_schedule()
        self.make_specs()
        self.build()
        if self.args.reference == "quiet":
            self.reference()
        self.links_down = set()
        self.link_changed = {}   # namespace -> when its link last went down or up
        # Every target list has a fixed shape whatever the machine allows, so that a seed picks the same targets
        # everywhere (a netns target is None, and skipped, where namespaces cannot be made).
        self.workers_all = self.workers[:3] + (self.workers[3:] if self.use_netns else [None, None])
        self.brokers_all = self.brokers[:1] + (self.brokers[1:] if self.use_netns else [None])
        self.batch_users_all = [u for u in self.users if isinstance(u, BatchUser) and u.ns is None] + \
            ([u for u in self.users if isinstance(u, BatchUser) and u.ns is not None] or [None])
        self.nodes_all = self.nodes or [None, None]
        self.say("seed %d, %.1f minutes, a fault every %.1f s on average: %d faults scheduled; work folder %s" %
                 (self.args.seed, self.args.minutes, self.args.fault_interval, len(schedule), self.work))
        self.say("brokers: %s; workers: %s; users: %s; REVOKE in the schema: %s; --client-grace: %s" % (
            ", ".join(b.name for b in self.brokers), ", ".join(w.name for w in self.workers),
            ", ".join(u.name for u in self.users), "yes" if self.revoke_in_schema else "no",
            CLIENT_GRACE if self.broker_has_grace else "not an option of this orcs-broker"))
        with open(os.path.join(self.work, "schedule.txt"), "w") as f:
            for e in schedule:
                print("%8.2f %-12s target#%-10d %5.2f s p=%.3f" % e, file=f)
        if self.args.print_schedule:
            for e in schedule:
                print("chaos: schedule %8.2f %-12s target#%d %.2f s p=%.3f" % e)
        else:
            print("chaos: schedule (replay with --seed %d): %s" % (self.args.seed, "; ".join(
                "%.1f %s#%d" % (e[0], e[1], e[2] % len(self.targets(e[1]))) for e in schedule)), flush=True)
        pollers = [threading.Thread(target=b.poll_loop, daemon=True) for b in self.brokers]
        for p in pollers:
            p.start()
        self.soak_start = now()
        end = self.soak_start + self.args.minutes * 60.0
        queue = list(schedule)
        last_progress = now()
        while now() < end:
            self.step(queue)
            if now() - last_progress > 30:
                last_progress = now()
                self.progress()
            time.sleep(0.05)
        self.soak_seconds = now() - self.soak_start
        self.say("%.1f minutes soaked; no more faults: everything back up, the batches under way drain" %
                 (self.soak_seconds / 60))
        self.soaking = False
        for when, what, action in sorted(self.pending, key=lambda x: x[0]):
            self.log("at once: " + what)
            action()
        self.pending = []
        for u in self.users:
            u.drain()
        drain_end = now() + self.args.drain
        while now() < drain_end and not all(u.finished() for u in self.users):
            self.step([])
            time.sleep(0.05)
        for u in self.users:
            if not u.finished():
                u.give_up("still under way %.0f s after the faults stopped" % self.args.drain)
        self.settle()
        self.log("batch ids of ended clients tracked: %d" % len(self.ended_batches))
        self.stop_polling.set()
        for p in pollers:
            p.join(10)

    def step(self, queue):
        t = now() - self.soak_start
        while queue and queue[0][0] <= t:
            self.inject(queue.pop(0))
        due = [x for x in self.pending if x[0] <= now()]
        self.pending = [x for x in self.pending if x[0] > now()]
        for _, what, action in due:
            self.log(what)
            action()
        for u in self.users:
            u.tick()
        for w in self.workers:
            w.tick()

    def settle(self):
        """After the last batch: every broker idle within WEDGE_LIMIT + a poll, every worker free."""
        deadline = now() + WEDGE_LIMIT + 3 * STATUS_PERIOD + 2
        while now() < deadline:
            if all(b.idle() for b in self.brokers):
                break
            time.sleep(0.2)
        for b in self.brokers:
            snap = b.last_status
            if snap is None:
                self.violate("%s: no status after the soak" % b.name)
                continue
            held = [(w.get("worker_id"), w.get("holding")) for w in b.workers_of(snap) if w.get("holding")]
            batches = [{k: x.get(k) for k in ("batch_id", "client_id", "queued", "running", "done", "failed",
                                              "expected", "age_seconds")} for x in b.batches_of(snap)]
            with open(os.path.join(self.work, "%s-final-status.json" % b.name), "w") as f:
                json.dump(snap, f, indent=1)
            if held or batches:
                self.violate("%s after the last batch ended: workers still held %s, live batches %s" %
                             (b.name, held, batches))

    def progress(self):
        self.say("%.0f s: %d faults, %d batches done, %d results checked, %d violations" % (
            now() - self.soak_start, sum(self.faults.values()), self.counts["batches_finished"],
            self.counts["results_checked"], len(self.violations)))

    def check_results(self, who, spec, rows, expected_seeds, complete):
        """rows: (seed, job id, canonical bits). Counts lost, duplicated and wrong results."""
        ref = self.specs[spec]["ref"]
        seen = collections.Counter(seed for seed, _, _ in rows)
        ids = collections.Counter(job for _, job, _ in rows)
        self.counts["results_checked"] += len(rows)
        for seed, count in seen.items():
            if count > 1:
                self.counts["duplicated"] += count - 1
                self.violate("%s: job with seed %d delivered %d times" % (who, seed, count))
            if seed not in expected_seeds:
                self.violate("%s: a result for seed %d, which the batch does not have" % (who, seed))
        for job, count in ids.items():
            if count > 1 and not any(c > 1 for c in seen.values()):
                self.counts["duplicated"] += count - 1
                self.violate("%s: job id %s delivered %d times" % (who, job, count))
        for seed, job, bits in rows:
            if bits != ref.get(seed):
                self.counts["wrong"] += 1
                self.violate("%s: %s (seed %d) differs from the undisturbed run: %s, expected %s" %
                             (who, job, seed, str(bits)[:300], str(ref.get(seed))[:300]))
        if complete:
            missing = [s for s in expected_seeds if s not in seen]
            if missing:
                self.counts["lost"] += len(missing)
                self.violate("%s: %d jobs without a result (seeds %s)" % (who, len(missing), missing[:10]))

    def cleanup(self):
        self.stop_polling.set()
        for proc in self.procs:
            if self.alive(proc):
                try:
                    os.killpg(proc.pid, signal.SIGCONT)
                    os.killpg(proc.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
        for proc in self.procs:
            try:
                proc.wait(5)
            except subprocess.TimeoutExpired:
                pass
        self.remove_netns()

    def summary(self):
        minutes = getattr(self, "soak_seconds", 0.0) / 60
        kinds = [k for k, _ in KINDS] + ["cancel"]
        lines = ["", "chaos soak summary (seed %d)" % self.args.seed,
                 "  minutes soaked:   %.1f (+ drain)" % minutes,
                 "  network namespaces: %s" % ("yes (CURVE broker on a head node, 2 worker nodes)"
                                               if getattr(self, "use_netns", False) else
                                               "no (%s)" % getattr(self, "netns_reason", "?")),
                 "  faults injected:  %d (%s)" % (sum(self.faults.values()), ", ".join(
                     "%s %d" % (k, self.faults[k]) for k in kinds)),
                 "  faults skipped:   %d (target not running, or already stopped or down: %s)" % (sum(self.skipped.values()),
                                                                                 ", ".join("%s %d" % kv for kv in
                                                                                           sorted(self.skipped.items()))),
                 "  not applicable:   %d (netns targets without namespaces)" % sum(self.not_applicable.values()),
                 "  client retries:   %d (orcs-batch found no broker while it was down or cut off: exit 2, run "
                 "again)" % self.counts["client_retries"],
                 "  batches:          %d finished, %d cancelled or interrupted, %d unfinished" % (
                     self.counts["batches_finished"], self.counts["batches_cancelled"],
                     self.counts["batches_unfinished"]),
                 "  jobs:             %d submitted, %d results checked" % (self.counts["jobs_submitted"],
                                                                         self.counts["results_checked"]),
                 "  lost:             %d" % self.counts["lost"],
                 "  duplicated:       %d" % self.counts["duplicated"],
                 "  wrong bits:       %d" % self.counts["wrong"],
                 "  batches outliving their client: %d (still live %.1f s after it ended)" % (
                     self.counts["batches_outlived"], BATCH_OUTLIVES_LIMIT),
                 "  wedged seconds:   %.1f (the longest a worker stayed held by an ended batch; limit %.0f s)" % (
                     max([b.wedged_max for b in getattr(self, "brokers", [])] or [0.0]), WEDGE_LIMIT)]
        for b in getattr(self, "brokers", []):
            lines.append("  %s RSS:   %s" % (b.name, b.rss_text()))
        lines.append("  violations:       %d" % len(self.violations))
        for v in self.violations[:25]:
            lines.append("    " + v)
        if len(self.violations) > 25:
            lines.append("    ... %d more in %s" % (len(self.violations) - 25, os.path.join(self.work, "chaos.log")))
        lines.append("  replay: scripts/chaos.sh --minutes %g --seed %d%s" % (
            self.args.minutes, self.args.seed,
            "" if self.args.fault_interval == 3.0 else " --fault-interval %g" % self.args.fault_interval))
        text = "\n".join(lines)
        print(text, flush=True)
        self.log(text)


class Broker:
    def __init__(self, soak, name, ns, argv, client_endpoint, curve):
        self.soak, self.name, self.ns, self.argv = soak, name, ns, argv
        self.endpoint = client_endpoint
        status_endpoint = "tcp://127.0.0.1:%s" % (5555 if ns else client_endpoint.rsplit(":", 1)[1])
        self.status_cmd = (["ip", "netns", "exec", ns] if ns else []) + [
            soak.exe("orcs-broker"), "status", "--broker", status_endpoint, "--json", "--timeout", "2"] + curve
        self.proc = None
        self.stopped = False
        self.down = False
        self.last_down = -1e9
        self.incarnations = []   # per process: [pid, start time, [(t, rss kB)]]
        self.last_status = None
        self.flagged = {}        # worker id -> first time seen held by an ended batch
        self.wedged_max = 0.0
        self.wedge_reported = set()
        self.outlived_reported = set()

    def launch(self):
        self.proc = self.soak.start(self.name, self.argv, self.ns)
        self.incarnations.append([self.proc.pid, now(), []])
        self.down = False

    def wait_ready(self, seconds):
        deadline = now() + seconds
        while now() < deadline and self.soak.alive(self.proc):
            if self.read_status() is not None:
                return True
            time.sleep(0.2)
        return False

    def kill(self, duration):
        if self.down or not self.soak.alive(self.proc):
            return False
        if self.stopped:
            return False
        self.soak.signal(self.proc, signal.SIGKILL)
        self.proc.wait()
        self.down = True
        self.last_down = now()
        self.soak.later(duration, "restart " + self.name, self.restart)
        return True

    def restart(self):
        self.last_down = now()
        self.launch()

    def pause(self, duration):
        if self.down or self.stopped or not self.soak.alive(self.proc):
            return False
        self.soak.signal(self.proc, signal.SIGSTOP)
        self.stopped = True
        self.last_down = now()

        def resume():
            self.soak.signal(self.proc, signal.SIGCONT)
            self.stopped = False
            self.last_down = now()
        self.soak.later(duration, "SIGCONT " + self.name, resume)
        return True

    def recently_down(self, seconds=6.0):
        return self.down or self.stopped or now() - self.last_down < seconds

    def read_status(self):
        try:
            out = subprocess.run(self.status_cmd, capture_output=True, text=True, timeout=4)
        except subprocess.TimeoutExpired:
            return None
        if out.returncode != 0:
            return None
        try:
            return json.loads(out.stdout)
        except ValueError:
            return None

    @staticmethod
    def workers_of(snap):
        return snap.get("worker_list", snap.get("workerList", []))

    @staticmethod
    def batches_of(snap):
        return snap.get("batch_list", snap.get("batchList", []))

    def idle(self):
        snap = self.last_status
        if snap is None:
            return False
        return not self.batches_of(snap) and not any(w.get("holding") for w in self.workers_of(snap))

    def poll_loop(self):
        while not self.soak.stop_polling.is_set():
            started = now()
            if self.soak.alive(self.proc) and not self.stopped:
                rss = self.rss()
                if rss is not None:
                    self.incarnations[-1][2].append((now(), rss))
                snap = self.read_status()
                if snap is not None:
                    self.last_status = snap
                    self.check_wedged(snap, started)
            self.soak.stop_polling.wait(max(0.0, STATUS_PERIOD - (now() - started)))

    def rss(self):
        try:
            with open("/proc/%d/status" % self.proc.pid) as f:
                for line in f:
                    if line.startswith("VmRSS:"):
                        return int(line.split()[1])
        except OSError:
            return None
        return None

    def check_wedged(self, snap, at):
        """A worker is held by an ended batch when it holds jobs but the broker finds none of them in a live
        batch: its current batch is empty or not among the live ones. (Without CURVE, and with CURVE to the key
        that owns every batch here, a live batch's id is shown.) Also counted: jobs held by workers beyond the
        live batches' running jobs."""
        live = {b.get("batch_id") for b in self.batches_of(snap)}
        for bid in live:
            ended = self.soak.ended_batches.get(bid)
            if ended is not None and at - ended > BATCH_OUTLIVES_LIMIT and bid not in self.outlived_reported:
                self.outlived_reported.add(bid)
                self.soak.counts["batches_outlived"] += 1
                self.soak.violate("%s: batch %s is still live %.1f s after its client ended (limit %.2f s: "
                                  "liveness, grace and 2 s)" % (self.name, bid, at - ended, BATCH_OUTLIVES_LIMIT))
        running = sum(b.get("running", 0) for b in self.batches_of(snap))
        workers = self.workers_of(snap)
        held = sum(w.get("holding", 0) for w in workers)
        flagged_now = set()
        for w in workers:
            if w.get("holding", 0) > 0 and (not w.get("current_batch_id") or w.get("current_batch_id") not in live):
                flagged_now.add(w.get("worker_id"))
        if held > running and not flagged_now:
            flagged_now.add("(%d jobs beyond the live batches')" % (held - running))
        for wid in list(self.flagged):
            if wid not in flagged_now:
                del self.flagged[wid]
        for wid in flagged_now:
            first = self.flagged.setdefault(wid, at)
            wedged = at - first
            self.wedged_max = max(self.wedged_max, wedged)
            if wedged > WEDGE_LIMIT and (wid, first) not in self.wedge_reported:
                self.wedge_reported.add((wid, first))
                w = next((w for w in workers if w.get("worker_id") == wid), None)
                if w is None:  # held > running without a worker to name
                    self.soak.violate("%s: %s held for ended batches for more than %.0f s (%d live batches)" % (
                        self.name, wid, WEDGE_LIMIT, len(live)))
                    continue
                self.soak.violate("%s: worker %s held by an ended batch for more than %.0f s (holding %s of %s, "
                                  "current batch '%s', %d live batches)" % (
                                      self.name, wid, WEDGE_LIMIT, w.get("holding"), w.get("credit"),
                                      w.get("current_batch_id", ""), len(live)))

    def rss_text(self):
        """Start and end of the run, and the longest-lived process (the one whose flatness says most)."""
        lives = []
        for pid, start, samples in self.incarnations:
            if not samples:
                continue
            life = samples[-1][0] - start
            # the baseline: the first sample after a warm-up of 20 s (or a quarter of the life, if shorter)
            warm = start + min(20.0, life / 4)
            base = next((kb for t, kb in samples if t >= warm), samples[0][1])
            lives.append((life, pid, base, samples[-1][1], max(kb for _, kb in samples)))
        if not lives:
            return "no samples"
        longest = max(lives)
        return ("%.1f MiB at the start, %.1f MiB at the end, peak %.1f MiB; %d processes (%d restarts); the longest-"
                "lived, pid %d for %.0f s: %.1f → %.1f MiB" % (
                    lives[0][2] / 1024, lives[-1][3] / 1024, max(x[4] for x in lives) / 1024, len(lives),
                    len(lives) - 1, longest[1], longest[0], longest[2] / 1024, longest[3] / 1024))

    def check_memory(self):
        for pid, start, samples in self.incarnations:
            if len(samples) < 2 or samples[-1][0] - start < 60:
                continue  # too short a life to say anything
            warm = start + 20.0
            base = next((kb for t, kb in samples if t >= warm), samples[0][1])
            end = samples[-1][1]
            if end > max(base * 1.5, base + 16 * 1024):
                self.soak.violate("%s (pid %d): resident memory grew from %.1f MiB to %.1f MiB" %
                                  (self.name, pid, base / 1024, end / 1024))


class Worker:
    def __init__(self, soak, name, ns, endpoint, broker, curve=()):
        self.soak, self.name, self.ns, self.endpoint, self.broker = soak, name, ns, endpoint, broker
        self.curve = list(curve)
        self.proc = None
        self.generation = 0
        self.stopped = False
        self.down = False

    def launch(self):
        self.generation += 1
        self.proc = self.soak.start("%s-%d" % (self.name, self.generation),
                                    [self.soak.exe("orcs-worker"), "--connect", self.endpoint, "--id",
                                     "%s-%d" % (self.name, self.generation), "--heartbeat", str(HEARTBEAT)] +
                                    self.curve, self.ns)
        self.down = False

    def kill(self, duration):
        if self.down or not self.soak.alive(self.proc):
            return False
        self.soak.signal(self.proc, signal.SIGCONT)
        os.killpg(self.proc.pid, signal.SIGKILL)  # the worker and its simulation process
        self.proc.wait()
        self.stopped = False
        self.down = True
        self.soak.later(duration, "restart " + self.name, self.launch)
        return True

    def pause(self, duration):
        if self.down or self.stopped or not self.soak.alive(self.proc):
            return False
        self.soak.signal(self.proc, signal.SIGSTOP)
        self.stopped = True
        proc = self.proc

        def resume():
            self.soak.signal(proc, signal.SIGCONT)
            self.stopped = False
        self.soak.later(duration, "SIGCONT " + self.name, resume)
        return True

    def tick(self):
        if not self.down and self.proc is not None and self.proc.poll() is not None:
            self.soak.violate("%s exited by itself (code %s); started again (log %s)" % (
                self.proc.chaos_name, self.proc.returncode, os.path.join(self.soak.logdir,
                                                                          self.proc.chaos_name + ".log")))
            self.launch()


class BatchUser:
    """A user running `orcs-batch submit` batches one after another, each of seeded size and seeds."""

    def __init__(self, soak, name, ns, broker, spec, sizes, curve):
        self.soak, self.name, self.ns, self.broker, self.spec, self.sizes = soak, name, ns, broker, spec, sizes
        self.curve = list(curve or [])
        self.rng = random.Random("chaos-user-%s-%d" % (name, soak.args.seed))
        self.index = 0
        self.batch = None
        self.next_start = now() + self.rng.uniform(0, 2)
        self.draining = False

    # the batch under way: dict(dir, n, seed, started, deadline, proc, state, ...)
    def tick(self):
        b = self.batch
        if b is None:
            if self.soak.soaking and now() >= self.next_start:
                self.new_batch()
            return
        proc = b["proc"]
        if proc is not None and proc.poll() is not None:
            self.exited(b, proc.returncode)
        elif proc is not None and b.get("interrupted_at") and now() - b["interrupted_at"] > CTRL_C_LIMIT:
            self.soak.violate("%s: orcs-batch did not exit within %.0f s of Ctrl-C (%s)" % (
                self.name, CTRL_C_LIMIT, b["dir"]))
            self.soak.signal(proc, signal.SIGCONT)
            self.soak.signal(proc, signal.SIGKILL, group=True)
            proc.wait()
            b["proc"] = None
            b["interrupted_at"] = None
            self.resume_later(b, 0.5)
        elif now() > b["deadline"]:
            self.give_up("batch %d of %d jobs not finished %.0f s after it started" % (
                self.index, b["n"], now() - b["started"]))

    def argv(self, b, resume):
        common = ["--broker", self.broker.endpoint, "--heartbeat", str(HEARTBEAT), "--quiet"] + self.curve
        if resume:
            return [self.soak.exe("orcs-batch"), "submit", "--resume", b["dir"]] + common
        return [self.soak.exe("orcs-batch"), "submit", self.soak.specs[self.spec]["path"], "--jobs", str(b["n"]),
                "--seed", str(b["seed"]), "--out", b["dir"]] + common

    def new_batch(self):
        self.index += 1
        n = self.rng.randint(*self.sizes)
        seed = self.rng.randint(1, self.soak.args.pool - n + 1)
        d = os.path.join(self.soak.work, "users", self.name, "batch-%03d" % self.index)
        b = {"dir": d, "n": n, "seed": seed, "started": now(), "deadline": now() + 90 + 3 * n, "runs": 0,
             "interrupted_at": None, "resumes": 0, "proc": None, "cancelled": False}
        self.batch = b
        self.soak.counts["jobs_submitted"] += n
        self.launch(b, resume=False)

    def launch(self, b, resume):
        b["runs"] += 1
        b["proc"] = self.soak.start("%s-b%03d-%d" % (self.name, self.index, b["runs"]), self.argv(b, resume),
                                    self.ns)
        b["interrupted_at"] = None
        b["stopped"] = False

    def resume_later(self, b, delay):
        b["resumes"] += 1
        # without batch.json nothing had been planned yet (killed in its first moments): start it afresh
        self.soak.later(delay, "%s resumes batch %d" % (self.name, self.index),
                        lambda: self.batch is b and b["proc"] is None and self.launch(
                            b, resume=os.path.exists(os.path.join(b["dir"], "batch.json"))))

    def last_batch_id(self, b):
        try:
            with open(os.path.join(b["dir"], "progress.json")) as f:
                return json.load(f).get("broker_batch")
        except (OSError, ValueError):
            return None

    def note_batch_id(self, b):
        """The broker's id of the run's batch (progress.json, broker_batch): every run of a batch has its own."""
        try:
            with open(os.path.join(b["dir"], "progress.json")) as f:
                bid = json.load(f).get("broker_batch")
        except (OSError, ValueError):
            return
        if bid:
            b.setdefault("ids", set()).add(bid)

    def exited(self, b, code):
        self.note_batch_id(b)
        bid = self.last_batch_id(b)
        if bid:  # the process is gone, and its batch must go too (a resumed run opens a batch of its own)
            self.soak.ended_batches.setdefault(bid, now())
        proc = b["proc"]
        b["proc"] = None
        if b.get("killed"):
            b["killed"] = False
            return  # resumed by the fault's timer
        if b.get("interrupted_at") is not None:
            took = now() - b["interrupted_at"]
            b["interrupted_at"] = None
            state = self.progress_state(b)
            self.soak.log("%s: orcs-batch stopped %.2f s after Ctrl-C, exit %s, progress.json state %s" % (
                self.name, took, code, state))
            if code == 0 and os.path.exists(os.path.join(b["dir"], "results.jsonl")):
                self.finish(b)  # it had finished before the Ctrl-C reached it
                return
            if code == -signal.SIGINT:
                # the Ctrl-C came before orcs-batch set its handler (its first milliseconds): the default action
                self.soak.log("%s: orcs-batch ended by SIGINT before it handled it" % self.name)
            elif code != 130 or state != "interrupted":
                self.soak.violate("%s: after Ctrl-C orcs-batch exited %s with progress.json state %s, not 130 and "
                                  "'interrupted' (%s)" % (self.name, code, state, b["dir"]))
            if b.get("abandon"):
                self.soak.counts["batches_cancelled"] += 1
                self.verify(b, complete=False)
                self.batch_over()
            else:
                self.resume_later(b, b.get("resume_delay", 0.5))
            return
        if code == 0:
            self.finish(b)
            return
        stderr = self.stderr_of(proc)
        if code == 2 and "the batch is complete already" in stderr and \
                os.path.exists(os.path.join(b["dir"], "results.jsonl")):
            # a resume of a batch that had finished as the fault reached its client: nothing was lost
            self.soak.log("%s: batch %d was complete when resumed: %s" % (self.name, self.index, stderr.strip()[-200:]))
            self.finish(b)
            return
        cut_off = self.ns is not None and (any(n[0] == self.ns for n in self.soak.links_down) or
                                           now() - self.soak.link_changed.get(self.ns, -1e9) < 8.0)
        if code == 2 and ("no broker answering" in stderr or "lost the broker" in stderr) and \
                (self.broker.recently_down(8.0) or cut_off):
            # what a client must do when it finds no broker (docs/batch.md): exit 2; the user tries again
            self.soak.log("%s: orcs-batch exit 2 while %s; run again: %s" % (
                self.name, "its link was down" if cut_off else self.broker.name + " was down",
                stderr.strip()[-200:]))
            self.soak.counts["client_retries"] += 1
            if os.path.exists(os.path.join(b["dir"], "batch.json")):
                self.resume_later(b, 1.0)
            else:
                self.soak.later(1.0, "%s starts batch %d again" % (self.name, self.index),
                                lambda: self.batch is b and b["proc"] is None and self.launch(b, resume=False))
            return
        self.soak.violate("%s: orcs-batch exited %s by itself (batch %d, %s): %s" % (
            self.name, code, self.index, b["dir"], stderr.strip()[-400:]))
        self.verify(b, complete=False)
        self.soak.counts["batches_unfinished"] += 1
        self.batch_over()

    def stderr_of(self, proc):
        try:
            with open(os.path.join(self.soak.logdir, proc.chaos_name + ".log"), errors="replace") as f:
                return f.read()[-4000:]
        except OSError:
            return ""

    def progress_state(self, b):
        try:
            with open(os.path.join(b["dir"], "progress.json")) as f:
                return json.load(f).get("state")
        except (OSError, ValueError):
            return None

    def rows(self, b):
        rows = []
        for name in ("results.jsonl", "results.jsonl.partial"):
            path = os.path.join(b["dir"], name)
            if os.path.exists(path):
                with open(path) as f:
                    for line in f:
                        if line.strip():
                            try:
                                row = json.loads(line)
                            except ValueError:
                                continue  # a line cut by a SIGKILL: the resume re-runs it
                            rows.append((row.get("seed"), row.get("id"), canonical_line(row)))
                break
        return rows

    def verify(self, b, complete):
        expected = range(b["seed"], b["seed"] + b["n"])
        self.soak.check_results("%s batch %d (%s)" % (self.name, self.index, b["dir"]), self.spec, self.rows(b),
                                set(expected), complete)

    def finish(self, b):
        if not os.path.exists(os.path.join(b["dir"], "results.jsonl")):
            self.soak.violate("%s: orcs-batch exited 0 without results.jsonl (%s)" % (self.name, b["dir"]))
        self.soak.counts["batches_finished"] += 1
        self.verify(b, complete=True)
        self.soak.log("%s: batch %d of %d jobs finished in %.1f s (%d runs)" % (
            self.name, self.index, b["n"], now() - b["started"], b["runs"]))
        self.batch_over()

    def batch_over(self):
        if self.batch is not None:
            self.note_batch_id(self.batch)
            for bid in self.batch.get("ids", ()):
                self.soak.ended_batches[bid] = now()
        self.batch = None
        self.next_start = now() + self.rng.uniform(0, 1.5)

    def give_up(self, why):
        b = self.batch
        if b is None:
            return
        self.soak.violate("%s: %s (%s)" % (self.name, why, b["dir"]))
        if b["proc"] is not None:
            self.soak.signal(b["proc"], signal.SIGCONT)
            self.soak.signal(b["proc"], signal.SIGKILL, group=True)
            b["proc"].wait()
            b["proc"] = None
        self.soak.counts["batches_unfinished"] += 1
        self.verify(b, complete=False)
        self.batch_over()

    # faults
    def kill(self, duration):
        b = self.batch
        if b is None or not self.soak.alive(b["proc"]) or b.get("interrupted_at"):
            return False
        self.soak.signal(b["proc"], signal.SIGCONT)
        self.soak.signal(b["proc"], signal.SIGKILL, group=True)
        b["proc"].wait()
        b["proc"] = None
        self.note_batch_id(b)
        for bid in b.get("ids", ()):  # a killed run's batch is over: the resume opens another
            self.soak.ended_batches.setdefault(bid, now())
        self.resume_later(b, duration)
        return True

    def pause(self, duration):
        b = self.batch
        if b is None or not self.soak.alive(b["proc"]) or b.get("stopped") or b.get("interrupted_at"):
            return False
        proc = b["proc"]
        self.soak.signal(proc, signal.SIGSTOP)
        b["stopped"] = True
        b["deadline"] += duration

        def resume():
            self.soak.signal(proc, signal.SIGCONT)
            b["stopped"] = False
        self.soak.later(duration, "SIGCONT %s" % self.name, resume)
        return True

    def interrupt(self, duration, resume):
        b = self.batch
        if b is None or not self.soak.alive(b["proc"]) or b.get("stopped") or b.get("interrupted_at"):
            return False
        self.soak.signal(b["proc"], signal.SIGINT, group=True)  # a terminal's Ctrl-C: the whole process group
        b["interrupted_at"] = now()
        b["abandon"] = not resume
        b["resume_delay"] = duration
        return True

    def drain(self):
        if self.batch is not None:
            self.batch["deadline"] = min(self.batch["deadline"], now() + self.soak.args.drain)

    def finished(self):
        return self.batch is None


class CancelUser:
    """A hand-made client (pyzmq) that submits a batch and CANCELs it after a seeded delay — or, now and then,
    lets it finish. `orcs-batch` never sends CANCEL (Ctrl-C says DISCONNECT), so this is the one that does."""

    def __init__(self, soak, name, broker, spec, sizes):
        import zmq
        self.zmq = zmq
        self.ctx = zmq.Context.instance()
        self.soak, self.name, self.broker, self.spec, self.sizes = soak, name, broker, spec, sizes
        self.ns = None
        self.rng = random.Random("chaos-user-%s-%d" % (name, soak.args.seed))
        self.index = 0
        self.batch = None
        self.sock = None
        self.next_start = now() + self.rng.uniform(0, 2)
        self.pb = soak.broker_pb2

    def envelope(self, **body):
        m = self.pb.ClientToBroker(protocol_version=wire.PROTOCOL_VERSION)
        for key, value in body.items():
            getattr(m, key).CopyFrom(value)
        return m.SerializeToString()

    def tick(self):
        b = self.batch
        if b is None:
            if self.soak.soaking and now() >= self.next_start:
                self.new_batch()
            return
        while self.sock.poll(0):
            self.on_message(b, self.sock.recv())
            if self.batch is None:
                return
        t = now()
        if t - b["last_sent"] >= HEARTBEAT:
            self.sock.send(self.envelope(heartbeat=self.pb.Heartbeat(interval_ms=int(HEARTBEAT * 1000))))
            b["last_sent"] = t
        if b["accepted_at"] is None and t - b["started"] > 3.0:
            return self.end(b, "abandoned", "no ACCEPTED within 3 s")
        if t - b["last_heard"] > 5 * HEARTBEAT + 1.0:
            return self.end(b, "abandoned", "the broker went silent")
        if b["cancel_after"] is not None and b["accepted_at"] is not None and not b["cancelled"] and \
                t - b["accepted_at"] >= b["cancel_after"]:
            self.sock.send(self.envelope(cancel=self.pb.Cancel(batch_id=b["id"])))
            b["cancelled"] = True
            b["cancelled_at"] = t
            self.soak.faults["cancel"] += 1
            self.soak.log("FAULT cancel of %s batch %d after %d of %d results" % (self.name, self.index,
                                                                                 len(b["rows"]), b["n"]))
        if b["cancelled"] and t - b["cancelled_at"] > 0.5:
            return self.end(b, "cancelled", "")
        if t > b["deadline"]:
            self.soak.violate("%s: batch %d (%d jobs) not finished or cancelled within %.0f s" % (
                self.name, self.index, b["n"], b["deadline"] - b["started"]))
            return self.end(b, "unfinished", "")

    def new_batch(self):
        self.index += 1
        n = self.rng.randint(*self.sizes)
        seed = self.rng.randint(1, self.soak.args.pool - n + 1)
        cancel_after = None if self.rng.random() < 0.2 else self.rng.uniform(0.1, 3.0)
        spec = self.soak.specs[self.spec]
        bid = secrets.token_hex(16)
        submit = self.pb.Submit(batch_id=bid, client_id="%s-%d" % (self.name, self.index),
                                owner_token=secrets.token_bytes(16), batch_size=n,
                                heartbeat_ms=int(HEARTBEAT * 1000))
        for i in range(n):
            submit.jobs.add(protocol_version=wire.PROTOCOL_VERSION, job_id="job-%04d" % i, batch_id=bid,
                            scenario_json=spec["resolved"], genome_json=spec["genome"], seed=seed + i,
                            time_limit_seconds=spec["time_limit"])
        self.sock = self.ctx.socket(self.zmq.DEALER)
        self.sock.setsockopt(self.zmq.LINGER, 0)
        self.sock.connect(self.broker.endpoint)
        self.sock.send(self.envelope(submit=submit))
        t = now()
        self.batch = {"id": bid, "n": n, "seed": seed, "started": t, "deadline": t + 60 + 3 * n,
                      "cancel_after": cancel_after, "cancelled": False, "accepted_at": None, "rows": [],
                      "last_sent": t, "last_heard": t}
        self.soak.counts["jobs_submitted"] += n

    def on_message(self, b, payload):
        m = self.pb.BrokerToClient()
        try:
            m.ParseFromString(payload)
        except Exception:
            return
        b["last_heard"] = now()
        kind = m.WhichOneof("body")
        if kind == "accepted":
            b["accepted_at"] = now()
        elif kind == "result":
            r = m.result
            status = self.soak.result_pb2.Result.Status.Name(r.status).lower()
            sets = tuple((s.index, fhex(s.fitness),
                          self.soak.result_pb2.Result.Status.Name(s.status).lower(),
                          tuple(sorted((d.path, fhex(d.value)) for d in s.drawn)),
                          tuple(sorted((x.name, fhex(x.value)) for x in s.terms))) for s in r.parameter_sets)
            bits = (status, fhex(r.fitness) if status == "ok" else None, sets)
            seed = b["seed"] + int(r.job_id.split("-")[1])
            b["rows"].append((seed, r.job_id, bits))
            if len({j for _, j, _ in b["rows"]}) == b["n"] and not b["cancelled"]:
                self.end(b, "finished", "")
        elif kind == "error":
            self.soak.violate("%s: SUBMIT rejected: %s" % (self.name, m.error.message))
            self.end(b, "unfinished", "")
        elif kind == "disconnect":
            self.end(b, "abandoned", "the broker said DISCONNECT (%s)" % m.disconnect.reason)

    def end(self, b, how, why):
        self.soak.ended_batches[b["id"]] = now()
        if how == "finished":
            self.soak.counts["batches_finished"] += 1
        elif how == "unfinished":
            self.soak.counts["batches_unfinished"] += 1
        else:
            self.soak.counts["batches_cancelled"] += 1
        self.soak.check_results("%s batch %d" % (self.name, self.index), self.spec, b["rows"],
                                set(range(b["seed"], b["seed"] + b["n"])), how == "finished")
        self.soak.log("%s: batch %d %s with %d of %d results%s" % (self.name, self.index, how, len(b["rows"]), b["n"],
                                                                  (": " + why) if why else ""))
        if how == "abandoned" and not b["cancelled"]:
            try:  # what a client that gives up does: say it is leaving, so the broker frees its jobs
                self.sock.send(self.envelope(disconnect=self.pb.Disconnect(reason="chaos client gives up")),
                               self.zmq.NOBLOCK)
            except self.zmq.ZMQError:
                pass
        self.sock.close(0)
        self.sock = None
        self.batch = None
        self.next_start = now() + self.rng.uniform(0, 1.5)

    def kill(self, duration):
        return False

    def drain(self):
        if self.batch is not None:
            self.batch["deadline"] = min(self.batch["deadline"], now() + self.soak.args.drain)
            if self.batch["cancel_after"] is not None:
                self.batch["cancel_after"] = 0.0  # the planned cancel, at once

    def finished(self):
        return self.batch is None

    def give_up(self, why):
        if self.batch is not None:
            self.soak.violate("%s: %s" % (self.name, why))
            self.end(self.batch, "unfinished", why)


def main():
    parser = argparse.ArgumentParser(description="the orcs chaos soak (docs/reliability.md, 'Chaos soak')")
    parser.add_argument("--minutes", type=float, default=2.0, help="how long faults are injected (default 2)")
    parser.add_argument("--seed", type=int, default=1, help="the schedule's seed (same seed, same schedule)")
    parser.add_argument("--bin", default=os.path.join(wire.SOURCE_DIR, "build", "bin"),
                        help="folder holding orcs-broker, orcs-worker, orcs-batch and orcs-keys")
    parser.add_argument("--fault-interval", type=float, default=3.0, help="mean seconds between faults (default 3)")
    parser.add_argument("--pool", type=int, default=40, help="seeds per job spec run undisturbed first (default 40)")
    parser.add_argument("--warmup", type=float, default=4.0, help="seconds before the first fault (default 4)")
    parser.add_argument("--drain", type=float, default=60.0,
                        help="seconds the batches under way may take once the faults stop (default 60)")
    parser.add_argument("--reference", choices=("run", "quiet"), default="run",
                        help="how the undisturbed results are made: `orcs-batch run` (default), or a quiet pass "
                             "through the loopback broker before the faults")
    parser.add_argument("--no-netns", action="store_true", help="loopback only")
    parser.add_argument("--netns-prefix", default="", help="name prefix of the namespaces (chaos.sh sets it)")
    parser.add_argument("--print-schedule", action="store_true", help="print the schedule, one fault a line")
    parser.add_argument("--keep", action="store_true", help="keep the work folder also when every invariant held")
    parser.add_argument("--verbose", action="store_true", help="print every event, not only the summary")
    args = parser.parse_args()
    if args.minutes <= 0 or args.minutes > 24 * 60 or args.pool < 30 or args.fault_interval <= 0:
        parser.error("--minutes must be in (0, 1440], --pool at least 30, --fault-interval positive")
    soak = Soak(args)

    def on_signal(signum, frame):
        raise KeyboardInterrupt
    signal.signal(signal.SIGTERM, on_signal)
    code = 0
    try:
        soak.run()
        for b in soak.brokers:
            b.check_memory()
        code = 1 if soak.violations else 0
    except KeyboardInterrupt:
        soak.say("interrupted")
        code = 1
    except (RuntimeError, subprocess.CalledProcessError, OSError) as error:
        soak.say("cannot run the soak: %s" % error)
        code = 2
    finally:
        soak.cleanup()
    soak.summary()
    if code == 0 and not args.keep:
        shutil.rmtree(soak.work, ignore_errors=True)
    else:
        print("chaos: logs, schedule and results kept in %s" % soak.work, flush=True)
    return code


if __name__ == "__main__":
    sys.exit(main())
