#!/usr/bin/env python3
"""Many lightweight workers in one process, for scripts/bench_scale.sh: each a DEALER connection to the broker's
worker port that says READY, heartbeats every H, answers each JOB at once with an OK RESULT carrying the job's
lease token (docs/protocol.md, "Worker conversation", "Leases") — or, for a job whose scenario_json is "hold",
keeps it until the broker REVOKEs it (and notes when the REVOKE came).

Usage: echo_workers.py BIN_DIR ENDPOINT COUNT FIRST_INDEX CREDIT HEARTBEAT_S
Commands on stdin, one a line; each is answered with one JSON line on stdout:
  stats   {"workers", "ready_sent", "jobs", "held", "revokes", "revoked_leases", "last_revoke", "disconnects", ...}
  reset   clears the job, revoke and timing counters (answers like stats)
  quit    sends DISCONNECT on every connection and exits
"""

import json
import os
import sys
import time

import zmq

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import wire  # noqa: E402


def main():
    bin_dir, endpoint, count, first, credit, heartbeat = sys.argv[1:7]
    count, first, credit, heartbeat = int(count), int(first), int(credit), float(heartbeat)
    _, result_pb2, _, broker_pb2 = wire.load(bin_dir, os.environ.get("TMPDIR", "/tmp"))
    has_revoke = wire.has_field(broker_pb2.BrokerToWorker, "revoke")
    ctx = zmq.Context(io_threads=1)
    ctx.setsockopt(zmq.MAX_SOCKETS, count + 64)
    poller = zmq.Poller()
    sockets = []
    ids = []

    def envelope(**body):
        m = broker_pb2.WorkerToBroker(protocol_version=wire.PROTOCOL_VERSION)
        for key, value in body.items():
            getattr(m, key).CopyFrom(value)
        return m.SerializeToString()

    hb_ms = int(heartbeat * 1000)
    stats = {"workers": count, "ready_sent": 0, "jobs": 0, "held": 0, "revokes": 0, "revoked_leases": 0,
             "first_revoke": None, "last_revoke": None, "disconnects": 0, "first_job": None, "last_job": None,
             "workers_revoked": 0, "revoke_in_schema": has_revoke}
    revoked_workers = set()
    held = {}  # socket index -> set of held leases

    def ready(i):
        sockets[i].send(envelope(ready=broker_pb2.Ready(worker_id=ids[i], credit=credit, host="bench",
                                                         heartbeat_ms=hb_ms)))
        stats["ready_sent"] += 1

    for i in range(count):
        s = ctx.socket(zmq.DEALER)
        s.setsockopt(zmq.LINGER, 0)
        s.setsockopt(zmq.SNDHWM, 10000)
        s.setsockopt(zmq.RCVHWM, 10000)
        s.connect(endpoint)
        sockets.append(s)
        ids.append("echo-%04d" % (first + i))
        held[i] = set()
        poller.register(s, zmq.POLLIN)
        ready(i)
    index_of = {s: i for i, s in enumerate(sockets)}
    poller.register(sys.stdin.fileno(), zmq.POLLIN)
    heartbeat_msg = envelope(heartbeat=broker_pb2.Heartbeat(interval_ms=hb_ms))
    next_beat = time.monotonic() + heartbeat
    incoming = broker_pb2.BrokerToWorker()
    ok = result_pb2.Result.OK
    while True:
        timeout = max(0.0, next_beat - time.monotonic())
        for s, _ in poller.poll(timeout * 1000):
            if s == sys.stdin.fileno():
                line = sys.stdin.readline()
                command = line.strip()
                if command in ("quit", ""):
                    for sock in sockets:
                        sock.send(envelope(disconnect=broker_pb2.Disconnect(reason="echo workers leaving")))
                    time.sleep(0.2)
                    return
                if command == "reset":
                    for key in ("jobs", "revokes", "revoked_leases", "disconnects", "workers_revoked"):
                        stats[key] = 0
                    for key in ("first_revoke", "last_revoke", "first_job", "last_job"):
                        stats[key] = None
                    revoked_workers.clear()
                stats["held"] = sum(len(h) for h in held.values())
                stats["workers_revoked"] = len(revoked_workers)
                print(json.dumps(stats), flush=True)
                continue
            i = index_of[s]
            while True:
                try:
                    payload = s.recv(zmq.NOBLOCK)
                except zmq.Again:
                    break
                incoming.ParseFromString(payload)
                kind = incoming.WhichOneof("body")
                if kind == "job":
                    job = incoming.job
                    t = time.time()
                    stats["jobs"] += 1
                    stats["first_job"] = stats["first_job"] or t
                    stats["last_job"] = t
                    if job.scenario_json == "hold":
                        held[i].add(job.lease)
                        continue
                    r = result_pb2.Result(protocol_version=wire.PROTOCOL_VERSION, job_id=job.job_id,
                                          batch_id=job.batch_id, status=ok, worker_id=ids[i], lease=job.lease)
                    s.send(envelope(result=r))
                elif kind == "revoke":
                    t = time.time()
                    stats["revokes"] += 1
                    stats["revoked_leases"] += len(incoming.revoke.leases)
                    for lease in incoming.revoke.leases:
                        held[i].discard(lease)
                    revoked_workers.add(i)
                    stats["first_revoke"] = stats["first_revoke"] or t
                    stats["last_revoke"] = t
                elif kind == "disconnect":
                    stats["disconnects"] += 1
                    held[i].clear()
                    ready(i)
        if time.monotonic() >= next_beat:
            for sock in sockets:
                sock.send(heartbeat_msg)
            next_beat += heartbeat
            if next_beat < time.monotonic():
                next_beat = time.monotonic() + heartbeat


if __name__ == "__main__":
    main()
