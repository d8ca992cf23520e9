#!/usr/bin/env python3
"""The scale benchmark (issue 47): one orcs-broker with many worker connections — lightweight echo workers,
echo_workers.py, COUNT/250 processes of up to 250 DEALER connections each — on 127.0.0.1. scripts/bench_scale.sh
is the entry; docs/benchmarks.md, "1,000 worker connections", records the figures.

For each worker count (a fresh broker each time, default heartbeats of 1 s) it measures:
- connect: seconds from starting the echo processes until the broker's status lists every worker;
- idle: the broker's CPU (utime + stime from /proc/PID/stat over --idle seconds, in % of one core) and resident
  memory while every worker is connected and nothing runs: the cost of heartbeats both ways;
- dispatch: --jobs trivial jobs (their scenario is the word "echo"; the echo workers answer each at once) from one
  hand-made client in SUBMITs of 2,000, until every result is back: jobs/s, and the broker's CPU per job;
- status: the round trip of one STATUS_REQUEST with that many workers (median of 5);
- freeing: a batch of COUNT × credit jobs that the workers hold without answering ("hold"), so every credit is
  taken; the client sends CANCEL and polls the status every 20 ms: seconds until the broker shows no worker busy,
  and (when the schema has REVOKE) until the last REVOKE reached its worker. Without a REVOKE the workers stay held:
  "not freed within --free-timeout s".
Prints one line of JSON per count and a Markdown table.
"""

import argparse
import json
import math
import os
import secrets
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time

import zmq

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import wire  # noqa: E402

CLK = os.sysconf("SC_CLK_TCK")
PER_PROCESS = 250


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def cpu_seconds(pid):
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / CLK  # utime, stime (fields 14 and 15 of stat)


def memory_kb(pid, key):
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith(key + ":"):
                return int(line.split()[1])
    return 0


class Client:
    def __init__(self, pb, status_pb2, endpoint):
        self.pb = pb
        self.status_pb2 = status_pb2
        self.ctx = zmq.Context.instance()
        self.sock = self.ctx.socket(zmq.DEALER)
        self.sock.setsockopt(zmq.LINGER, 0)
        self.sock.setsockopt(zmq.RCVHWM, 0)
        self.sock.connect(endpoint)
        self.status_sock = None
        self.endpoint = endpoint
        self.token = secrets.token_bytes(16)
        self.last_beat = time.monotonic()

    def envelope(self, **body):
        m = self.pb.ClientToBroker(protocol_version=wire.PROTOCOL_VERSION)
        for key, value in body.items():
            getattr(m, key).CopyFrom(value)
        return m.SerializeToString()

    def submit(self, batch_id, jobs, scenario, total):
        for start in range(0, jobs, 2000):
            s = self.pb.Submit(batch_id=batch_id, client_id="bench-scale", owner_token=self.token, batch_size=total,
                               heartbeat_ms=1000)
            for i in range(start, min(jobs, start + 2000)):
                s.jobs.add(protocol_version=wire.PROTOCOL_VERSION, job_id="j%07d" % i, batch_id=batch_id,
                           scenario_json=scenario, genome_json="[]", seed=i, time_limit_seconds=600)
            self.sock.send(self.envelope(submit=s))

    def beat(self):
        if time.monotonic() - self.last_beat >= 1.0:
            self.sock.send(self.envelope(heartbeat=self.pb.Heartbeat(interval_ms=1000)))
            self.last_beat = time.monotonic()

    def collect(self, count, timeout):
        """Receives until `count` RESULTs came; returns (results, time of the last)."""
        got, last = 0, None
        deadline = time.monotonic() + timeout
        m = self.pb.BrokerToClient()
        while got < count and time.monotonic() < deadline:
            self.beat()
            if not self.sock.poll(200):
                continue
            while True:
                try:
                    payload = self.sock.recv(zmq.NOBLOCK)
                except zmq.Again:
                    break
                m.ParseFromString(payload)
                kind = m.WhichOneof("body")
                if kind == "result":
                    got += 1
                    last = time.monotonic()
                elif kind == "error":
                    raise RuntimeError("SUBMIT rejected: " + m.error.message)
        return got, last

    def status(self, timeout=5000):
        if self.status_sock is None:
            self.status_sock = self.ctx.socket(zmq.DEALER)
            self.status_sock.setsockopt(zmq.LINGER, 0)
            self.status_sock.connect(self.endpoint)
        self.status_sock.send(self.envelope(status_request=self.status_pb2.StatusRequest()))
        if not self.status_sock.poll(timeout):
            self.status_sock.close(0)
            self.status_sock = None
            raise RuntimeError("no STATUS within %.1f s" % (timeout / 1000))
        m = self.pb.BrokerToClient()
        m.ParseFromString(self.status_sock.recv())
        return m.status

    def cancel(self, batch_id):
        self.sock.send(self.envelope(cancel=self.pb.Cancel(batch_id=batch_id)))

    def close(self):
        self.sock.send(self.envelope(disconnect=self.pb.Disconnect(reason="bench done")))
        time.sleep(0.1)
        self.sock.close(0)
        if self.status_sock is not None:
            self.status_sock.close(0)


def measure(args, pb, count):
    cport, wport = free_port(), free_port()
    log = open(os.path.join(args.work, "broker-%d.log" % count), "wb")
    broker = subprocess.Popen([os.path.join(args.bin, "orcs-broker"), "--client-port", str(cport), "--worker-port",
                               str(wport)], stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
    echo = []
    row = {"workers": count, "credit": args.credit}
    try:
        client = Client(pb, args.status_pb2, "tcp://127.0.0.1:%d" % cport)
        deadline = time.monotonic() + 10
        while True:
            try:
                client.status(500)
                break
            except RuntimeError:
                if time.monotonic() > deadline or broker.poll() is not None:
                    with open(os.path.join(args.work, "broker-%d.log" % count), errors="replace") as f:
                        raise RuntimeError("orcs-broker does not answer: " + f.read()[-500:])
        row["broker_rss_mb_empty"] = memory_kb(broker.pid, "VmRSS") / 1024
        procs = max(1, math.ceil(count / PER_PROCESS))
        started = time.monotonic()
        for p in range(procs):
            n = count // procs + (1 if p < count % procs else 0)
            first = sum(count // procs + (1 if q < count % procs else 0) for q in range(p))
            echo.append(subprocess.Popen([sys.executable, os.path.join(os.path.dirname(__file__), "echo_workers.py"),
                                          args.bin, "tcp://127.0.0.1:%d" % wport, str(n), str(first),
                                          str(args.credit), "1.0"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                         text=True, start_new_session=True))
        while client.status().workers < count:
            if time.monotonic() - started > 120:
                raise RuntimeError("only %d of %d workers registered within 120 s" % (client.status().workers, count))
            time.sleep(0.1)
        row["connect_s"] = time.monotonic() - started
        time.sleep(3)  # the connections settle (READYs answered, first heartbeats)

        # idle: heartbeats only
        c0, t0 = cpu_seconds(broker.pid), time.monotonic()
        time.sleep(args.idle)
        c1, t1 = cpu_seconds(broker.pid), time.monotonic()
        row["idle_cpu_pct"] = 100.0 * (c1 - c0) / (t1 - t0)
        row["broker_rss_mb_idle"] = memory_kb(broker.pid, "VmRSS") / 1024

        # status round trip
        trips = []
        for _ in range(5):
            s0 = time.monotonic()
            st = client.status()
            trips.append(time.monotonic() - s0)
        row["status_ms"] = 1000 * statistics.median(trips)
        row["status_bytes"] = st.ByteSize()

        # dispatch
        batch = secrets.token_hex(16)
        c0, t0 = cpu_seconds(broker.pid), time.monotonic()
        client.submit(batch, args.jobs, "echo", args.jobs)
        got, last = client.collect(args.jobs, args.dispatch_timeout)
        c1 = cpu_seconds(broker.pid)
        if got < args.jobs:
            row["dispatch"] = "%d of %d results within %.0f s" % (got, args.jobs, args.dispatch_timeout)
        else:
            row["dispatch_jobs_per_s"] = args.jobs / (last - t0)
            row["broker_cpu_us_per_job"] = 1e6 * (c1 - c0) / args.jobs
        row["broker_rss_mb_after_dispatch"] = memory_kb(broker.pid, "VmRSS") / 1024
        row["broker_hwm_mb"] = memory_kb(broker.pid, "VmHWM") / 1024
        time.sleep(1.5)  # every worker's credit back (its jobs were all answered)

        # freeing: every credit held, then CANCEL
        held_jobs = count * args.credit
        hold = secrets.token_hex(16)
        client.submit(hold, held_jobs, "hold", held_jobs)
        wait_until = time.monotonic() + 60
        while True:
            client.beat()
            st = client.status()
            if st.running >= held_jobs and st.busy_workers >= count:
                break
            if time.monotonic() > wait_until:
                raise RuntimeError("only %d of %d jobs held after 60 s" % (st.running, held_jobs))
            time.sleep(0.05)
        for e in echo:
            e.stdin.write("reset\n")
            e.stdin.flush()
            e.stdout.readline()
        cancel_at = time.time()
        client.cancel(hold)
        freed = None
        while time.time() - cancel_at < args.free_timeout:
            st = client.status()
            if st.busy_workers == 0 and sum(w.holding for w in st.worker_list) == 0:
                freed = time.time() - cancel_at
                break
            time.sleep(0.02)
        row["freed_status_s"] = freed
        if freed is None:
            row["still_busy_after_timeout"] = st.busy_workers
        time.sleep(0.5)
        revoked, last_revoke, leases = 0, None, 0
        for e in echo:
            e.stdin.write("stats\n")
            e.stdin.flush()
            s = json.loads(e.stdout.readline())
            revoked += s["workers_revoked"]
            leases += s["revoked_leases"]
            if s["last_revoke"]:
                last_revoke = max(last_revoke or 0, s["last_revoke"])
            row["revoke_in_schema"] = s["revoke_in_schema"]
        row["workers_revoked"] = revoked
        row["leases_revoked"] = leases
        row["last_revoke_s"] = (last_revoke - cancel_at) if last_revoke else None
        client.close()
    finally:
        for e in echo:
            try:
                e.stdin.write("quit\n")
                e.stdin.flush()
            except (BrokenPipeError, ValueError):
                pass
        for e in echo:
            try:
                e.wait(5)
            except subprocess.TimeoutExpired:
                os.killpg(e.pid, signal.SIGKILL)
        broker.send_signal(signal.SIGTERM)
        try:
            broker.wait(10)
        except subprocess.TimeoutExpired:
            broker.kill()
        log.close()
    return row


def fmt(value, pattern):
    return "—" if value is None else pattern % value


def main():
    parser = argparse.ArgumentParser(description="1,000 worker connections on one orcs-broker")
    parser.add_argument("--bin", required=True)
    parser.add_argument("--workers", default="10,1000", help="worker counts, comma-separated (default 10,1000)")
    parser.add_argument("--jobs", type=int, default=20000, help="trivial jobs per dispatch measurement")
    parser.add_argument("--credit", type=int, default=2, help="each echo worker's credit (default 2)")
    parser.add_argument("--idle", type=float, default=10.0, help="seconds of idle CPU measurement")
    parser.add_argument("--dispatch-timeout", type=float, default=300.0)
    parser.add_argument("--free-timeout", type=float, default=15.0)
    args = parser.parse_args()
    args.bin = os.path.abspath(args.bin)
    args.work = tempfile.mkdtemp(prefix="orcs-bench-scale.")
    _, _, args.status_pb2, pb = wire.load(args.bin, args.work)
    rows = []
    for count in [int(c) for c in args.workers.split(",")]:
        load0 = os.getloadavg()[0]
        row = measure(args, pb, count)
        row["load_before"], row["load_after"] = load0, os.getloadavg()[0]
        print(json.dumps(row), flush=True)
        rows.append(row)
    print()
    print("| worker connections | connect | broker CPU idle | broker RSS idle | status round trip | dispatch "
          "(%d trivial jobs) | broker CPU per job | broker peak RSS | CANCEL → no worker busy | CANCEL → last "
          "REVOKE | load avg before→after |" % args.jobs)
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        freed = fmt(r.get("freed_status_s"), "%.3f s") if r.get("freed_status_s") is not None else \
            "not freed within %.0f s (%d busy)" % (args.free_timeout, r.get("still_busy_after_timeout", 0))
        print("| %d | %.1f s | %.2f %% | %.1f MiB | %.1f ms (%.0f kB) | %s | %s | %.1f MiB | %s | %s | %.1f→%.1f |" % (
            r["workers"], r["connect_s"], r["idle_cpu_pct"], r["broker_rss_mb_idle"], r["status_ms"],
            r["status_bytes"] / 1000, fmt(r.get("dispatch_jobs_per_s"), "%.0f jobs/s") if "dispatch" not in r
            else r["dispatch"], fmt(r.get("broker_cpu_us_per_job"), "%.1f µs"), r["broker_hwm_mb"], freed,
            fmt(r.get("last_revoke_s"), "%.3f s") + (" (%d workers)" % r["workers_revoked"]
                                                     if r.get("last_revoke_s") is not None else
                                                     "" if r.get("revoke_in_schema") else " (no REVOKE in the schema)"),
            r["load_before"], r["load_after"]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
