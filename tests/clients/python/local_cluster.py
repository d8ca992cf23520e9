"""A real orcs-broker and real orcs-worker processes on 127.0.0.1 for the Python client's tests.

Every process is started with PR_SET_PDEATHSIG, so it dies with the test even when the test is killed; close()
stops them (SIGTERM, then SIGKILL after a bounded wait) and is safe to call twice. Waits are bounded.
"""

import ctypes
import os
import re
import select
import shutil
import signal
import socket
import subprocess
import tempfile
import time

BIN = os.environ.get("ORCS_BIN", os.path.join(os.path.dirname(__file__), "..", "..", "..", "build", "bin"))
_PR_SET_PDEATHSIG = 1
_libc = ctypes.CDLL(None, use_errno=True)


def _die_with_parent():
    _libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)


def start_process(argv, log_path):
    """Starts argv with stdout piped to the caller, stderr to log_path, and death with the calling thread."""
    with open(log_path, "ab") as log:
        return subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=log,
                                preexec_fn=_die_with_parent)


def stop_process(process, grace=5.0):
    """SIGTERM, then SIGKILL after `grace` seconds; reaps it."""
    if process.poll() is None:
        process.terminate()
        try:
            process.wait(timeout=grace)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=grace)
    if process.stdout is not None:
        process.stdout.close()


def read_line(process, timeout):
    """The next stdout line of process (without newline), or None when none is complete within timeout seconds."""
    deadline = time.monotonic() + timeout
    line = b""
    fd = process.stdout.fileno()
    while not line.endswith(b"\n"):
        left = deadline - time.monotonic()
        if left <= 0 or not select.select([fd], [], [], left)[0]:
            return None
        chunk = os.read(fd, 1)
        if not chunk:
            return None
        line += chunk
    return line.decode().rstrip("\n")


def unused_port():
    """A loopback TCP port nothing listens on (bound, then released)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


class LocalCluster:
    """orcs-broker on ephemeral loopback ports (or the given ones) and `workers` orcs-worker processes."""

    def __init__(self, workers=2, heartbeat=0.2, client_port=0, worker_port=0):
        self.heartbeat = heartbeat
        self.folder = tempfile.mkdtemp(prefix="orcs-python-cluster-")
        self.broker = None
        self.workers = []
        self.clients = ""  # the broker's client endpoint
        self.worker_endpoint = ""
        try:
            self.start_broker(client_port, worker_port)
            for index in range(workers):
                self.workers.append(start_process(
                    [os.path.join(BIN, "orcs-worker"), "--connect", self.worker_endpoint, "--heartbeat",
                     str(heartbeat), "--id", "py-worker-%d" % index],
                    os.path.join(self.folder, "worker-%d.log" % index)))
        except BaseException:
            self.close()
            raise

    def start_broker(self, client_port=0, worker_port=0):
        """(Re)starts the broker, on the given ports (0 = any free one); waits at most 10 s for its endpoints."""
        self.broker = start_process(
            [os.path.join(BIN, "orcs-broker"), "--client-port", str(client_port), "--worker-port", str(worker_port),
             "--heartbeat", str(self.heartbeat)], os.path.join(self.folder, "broker.log"))
        line = read_line(self.broker, 10.0)
        match = re.fullmatch(r"orcs-broker clients=(\S+) workers=(\S+)", line or "")
        if not match:
            raise RuntimeError("orcs-broker did not print its endpoints (first line %r); its log: %s"
                               % (line, self.log("broker.log")))
        self.clients, self.worker_endpoint = match.group(1), match.group(2)

    def kill_broker(self):
        """SIGKILL to the broker: it says nothing to its peers, as in a crash."""
        self.broker.kill()
        self.broker.wait(timeout=10)
        self.broker.stdout.close()

    def port(self, endpoint):
        return int(endpoint.rsplit(":", 1)[1])

    def log(self, name):
        try:
            with open(os.path.join(self.folder, name), errors="replace") as log:
                return log.read()[-4000:]
        except OSError:
            return ""

    def close(self):
        for process in self.workers + ([self.broker] if self.broker else []):
            stop_process(process)
        self.workers = []
        self.broker = None
        shutil.rmtree(self.folder, ignore_errors=True)
