"""BatchClient: a client's connection to an orcs broker, in Python (docs/protocol.md, "Client conversation").

It behaves on the wire as the C++ BatchClient (clients/runtime/batch_client.h) does: one DEALER socket, one frame per message,
SUBMITs of at most about 4 MiB, a HEARTBEAT every interval while jobs are outstanding, a new connection and a
resubmission of every job still without a result when the broker is silent for liveness × heartbeat or says
DISCONNECT, and each job's first result handed out once (later duplicates are dropped). A background I/O thread
owns the socket, so heartbeats go on while the caller is busy between results.

Each submit() opens a batch of its own (ids "<client id>-1", "-2", ...), so an optimiser can send one batch per
generation over one connection.
"""

import atexit
import collections
import itertools
import math
import os
import secrets
import socket as _socket
import sys
import threading
import time
import weakref

from . import _proto
from .errors import BrokerError, ResultTimeout, SetupError
from .job_result import JobResult

try:
    import zmq
except ImportError as _error:  # pragma: no cover - depends on the machine
    raise SetupError("orcs_client needs pyzmq, Debian's python3-zmq (scripts/setup.sh installs it): %s" % _error)

job_pb2, result_pb2, broker_pb2 = _proto.load_modules()

PROTOCOL_VERSION = 1  # orcs::proto::kProtocolVersion
_GOODBYE_LINGER_MS = 200  # how long a DISCONNECT may take to leave at close()
_CLIENT_NUMBERS = itertools.count(1)
_OPEN_CLIENTS = weakref.WeakSet()  # closed at exit, so that a client left open never holds the process up


@atexit.register
def _close_open_clients():
    for client in list(_OPEN_CLIENTS):
        client.close()


def _seconds(value):
    """"3 s", "0.5 s", as the C++ client prints durations."""
    return "%g s" % value


class _BatchState:
    """What the callers' side knows of one batch. Guarded by the client's lock."""

    __slots__ = ("job_ids", "results", "outstanding")

    def __init__(self, job_ids):
        self.job_ids = job_ids                 # the batch's job ids, in submission order
        self.results = collections.deque()     # JobResults arrived and not yet handed out
        self.outstanding = len(job_ids)        # jobs whose result has not been handed out yet


class Batch:
    """One submitted batch: its id, its job ids, and its results as they arrive."""

    def __init__(self, client, batch_id, job_ids):
        self._client = client
        self.batch_id = batch_id  # the batch's id at the broker
        self.job_ids = job_ids    # tuple of the job ids, in the order the jobs were given

    @property
    def outstanding(self):
        """Jobs whose result has not been handed out yet."""
        return self._client._outstanding(self.batch_id)

    def next(self, timeout=None):
        """The next JobResult in arrival order; None when none arrives within `timeout` seconds (None = no limit)
        or at once when every result has been handed out. Raises BrokerError when the broker is gone for good
        (after handing out the results that arrived before)."""
        return self._client._next(self.batch_id, timeout)

    def results(self, timeout=None):
        """Yields each job's JobResult exactly once, in arrival order, until every job has one. Raises
        ResultTimeout when no result arrives within `timeout` seconds of the previous one (None = no limit; a lost
        broker still ends the wait with BrokerError after the client's reconnect timeout)."""
        while True:
            result = self.next(timeout)
            if result is not None:
                yield result
                continue
            left = self.outstanding
            if left == 0:
                return
            raise ResultTimeout("no result for batch %s within %s (%d of %d jobs without a result)"
                                % (self.batch_id, _seconds(timeout), left, len(self.job_ids)))

    def collect(self, timeout=None):
        """Every JobResult, in the order the jobs were submitted. `timeout` as for results()."""
        by_id = {result.job_id: result for result in self.results(timeout)}
        return [by_id[job_id] for job_id in self.job_ids]


class BatchClient:
    """A connection to the broker's client endpoint. Thread-safe; use as a context manager (or call close())."""

    def __init__(self, endpoint, heartbeat=1.0, liveness=5, connect_timeout=3.0, reconnect_timeout=30.0,
                 max_submit_bytes=4 << 20, log=None):
        """endpoint: the broker's client endpoint, e.g. "tcp://127.0.0.1:5555". heartbeat: seconds between
        heartbeats (said to the broker, which waits for the slower of its pace and this one). liveness: heartbeats of silence after which the broker counts as lost.
        connect_timeout: seconds submit() waits for a broker that has never answered. reconnect_timeout: seconds
        the client keeps trying after the broker was lost. max_submit_bytes: about how large one SUBMIT gets.
        log: a function taking one line (connection events); None = stderr. Raises ValueError for a bad value."""
        if not endpoint:
            raise ValueError("BatchClient: empty broker endpoint")
        for name, value in (("heartbeat", heartbeat), ("connect_timeout", connect_timeout),
                            ("reconnect_timeout", reconnect_timeout)):
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ValueError("BatchClient: %s must be a positive number of seconds, found %r" % (name, value))
        if not isinstance(liveness, int) or liveness < 2:
            raise ValueError("BatchClient: liveness must be an integer of at least 2, found %r" % (liveness,))
        if not isinstance(max_submit_bytes, int) or max_submit_bytes <= 0:
            raise ValueError("BatchClient: max_submit_bytes must be positive, found %r" % (max_submit_bytes,))
        self.endpoint = endpoint
        self._heartbeat = float(heartbeat)
        self._liveness = liveness
        self._liveness_period = float(heartbeat) * liveness
        self._connect_timeout = float(connect_timeout)
        self._reconnect_timeout = float(reconnect_timeout)
        self._max_submit_bytes = max_submit_bytes
        self._log_function = log
        # "<hostname>-<pid>-<n>": a name for the broker's log, as in the C++ client. Not a secret: the batches belong
        # to the owner token, 128 random bits from the OS sent with every SUBMIT and never logged (docs/protocol.md).
        self.client_id = "%s-%d-py%d" % (_socket.gethostname(), os.getpid(), next(_CLIENT_NUMBERS))
        self._owner_token = secrets.token_bytes(16)
        self._context = zmq.Context()
        try:  # a malformed endpoint fails here, at once, rather than at the first submit()
            probe = self._context.socket(zmq.DEALER)
            probe.setsockopt(zmq.LINGER, 0)
            try:
                probe.connect(endpoint)
            finally:
                probe.close()
        except zmq.ZMQError as error:
            self._context.term()
            raise ValueError("BatchClient: cannot connect to '%s': %s" % (endpoint, error)) from None

        # Shared with the callers, guarded by _lock.
        self._lock = threading.Lock()
        self._changed = threading.Condition(self._lock)
        self._to_submit = collections.deque()  # (submission number, batch id, jobs) not yet taken by the I/O thread
        self._submissions = 0                  # submit() calls that got past validation
        self._accepted_through = 0             # submissions 1..this are accepted
        self._batches = {}                     # batch id → _BatchState
        self._error = ""                       # the terminal error, once there is one
        self._stopping = False
        self._closed = False
        self._stats = {"connections": 0, "submit_messages": 0, "results": 0, "duplicates_dropped": 0,
                       "messages_dropped": 0}

        # Owned by the I/O thread.
        self._socket = None
        self._outstanding_jobs = collections.OrderedDict()  # (batch id, job id) → Job: submitted, no result yet
        self._unanswered = collections.deque()  # per SUBMIT sent on this socket, the submission it belongs to
        self._latest_sent = 0                   # the newest submission sent
        self._heard = False                     # the broker has answered since the client became active
        self._active_since = 0.0                # when the client last went from idle to active
        self._last_heard = 0.0                  # when the broker was last heard
        self._next_heartbeat = 0.0
        self._last_connect = 0.0                # when the current socket was opened
        self._warned_bad_message = False        # a dropped message was logged on this socket
        self._warned_silence = False            # a reconnection was logged and the broker has not answered since

        self._wake_read, self._wake_write = os.pipe()  # submit() and close() wake the I/O thread's poll through it
        os.set_blocking(self._wake_read, False)
        os.set_blocking(self._wake_write, False)
        self._thread = threading.Thread(target=self._io_loop, name="orcs-client-io", daemon=True)
        self._thread.start()
        _OPEN_CLIENTS.add(self)

    # -----------------------------------------------------------------------------------------------------------
    # The callers' side

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()
        return False

    def close(self):
        """Tells the broker the client is leaving (its queued jobs are dropped) and stops the I/O thread."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            self._stopping = True
            self._changed.notify_all()
        self._wake()
        self._thread.join(timeout=10.0)
        _OPEN_CLIENTS.discard(self)
        if self._thread.is_alive():  # a bug left it running: leave its pipe and context to the process's end
            return
        os.close(self._wake_read)
        os.close(self._wake_write)
        self._context.term()

    def submit(self, jobs, batch_id=None):
        """Submits the jobs (orcs.v1.Job messages; copies are sent) as a new batch and returns its Batch once the
        broker has accepted them. A job without a job_id gets "job-<its position>", zero-padded to the digits of the
        last position ("job-00" ... "job-11" for 12 jobs), as orcs-batch numbers its jobs.
        batch_id: None = 128 random bits as 32 hex digits, a name nobody can guess. Raises ValueError for no jobs, a repeated job id or a batch id used
        before, and BrokerError when no broker answers within connect_timeout or it rejects the batch."""
        jobs = list(jobs)
        if not jobs:
            raise ValueError("submit: no jobs")
        width = len(str(len(jobs) - 1))
        sending, ids, seen = [], [], set()
        for index, job in enumerate(jobs):
            if not isinstance(job, job_pb2.Job):
                raise TypeError("submit: job %d is a %s, not an orcs.v1.Job" % (index, type(job).__name__))
            copy = job_pb2.Job()
            copy.CopyFrom(job)
            if not copy.job_id:
                copy.job_id = "job-%0*d" % (width, index)
            if copy.job_id in seen:
                raise ValueError("submit: job %d: job_id '%s' repeated" % (index, copy.job_id))
            seen.add(copy.job_id)
            ids.append(copy.job_id)
            sending.append(copy)
        with self._lock:
            if self._error:
                raise BrokerError(self._error)
            if self._closed:
                raise ValueError("submit: the client is closed")
            if batch_id is None:
                batch_id = secrets.token_hex(16)
            if not batch_id or batch_id in self._batches:
                raise ValueError("submit: batch id %r is empty or was used before" % (batch_id,))
            for job in sending:
                job.batch_id = batch_id
                job.protocol_version = PROTOCOL_VERSION
            self._batches[batch_id] = _BatchState(tuple(ids))
            self._submissions += 1
            submission = self._submissions
            self._to_submit.append((submission, batch_id, sending))
        self._wake()
        # The I/O thread answers within connect_timeout or reconnect_timeout (plus the liveness period that
        # reveals a lost broker); the bound here only guards against a bug there.
        bound = self._connect_timeout + self._reconnect_timeout + self._liveness_period + 2 * self._heartbeat + 5
        with self._lock:
            if not self._changed.wait_for(
                    lambda: self._accepted_through >= submission or self._error or self._stopping, bound):
                self._error = "no answer from the client's I/O thread after %s" % _seconds(bound)
            if self._error:
                raise BrokerError(self._error)
            if self._accepted_through < submission:
                raise BrokerError("the client was closed before the broker at %s accepted batch %s"
                                  % (self.endpoint, batch_id))
        return Batch(self, batch_id, tuple(ids))

    def outstanding(self):
        """Jobs submitted, over all batches, whose result has not been handed out yet."""
        with self._lock:
            return sum(state.outstanding for state in self._batches.values())

    def stats(self):
        """A copy of the counters: connections, submit_messages, results, duplicates_dropped, messages_dropped."""
        with self._lock:
            return dict(self._stats)

    def _outstanding(self, batch_id):
        with self._lock:
            return self._batches[batch_id].outstanding

    def _next(self, batch_id, timeout):
        with self._lock:
            state = self._batches[batch_id]
            self._changed.wait_for(
                lambda: state.results or self._error or self._stopping or state.outstanding == 0, timeout)
            if state.results:
                state.outstanding -= 1
                return state.results.popleft()
            if self._error:
                raise BrokerError(self._error)
            if self._stopping and state.outstanding > 0:
                raise BrokerError("the client was closed with %d jobs of batch %s without a result"
                                  % (state.outstanding, batch_id))
            return None

    def _wake(self):
        try:
            os.write(self._wake_write, b"\x01")
        except (BlockingIOError, OSError):  # full: the I/O thread wakes anyway; closed: it is gone
            pass

    def _log(self, line):
        if self._log_function is not None:
            self._log_function(line)
        else:
            print("orcs_client: " + line, file=sys.stderr, flush=True)

    # -----------------------------------------------------------------------------------------------------------
    # The I/O thread

    def _io_loop(self):
        try:
            self._serve()
        except Exception as error:  # a bug or a ZeroMQ failure: fail every caller with it, never hang them
            self._fail("the client's connection to %s failed: %s" % (self.endpoint, error))
        finally:
            if self._socket is not None:
                self._socket.close()
                self._socket = None

    def _active(self):
        return self._socket is not None and (bool(self._outstanding_jobs) or bool(self._unanswered))

    def _serve(self):
        while True:
            timeout_ms = None
            if self._active():
                if not self._heard:
                    deadline = self._active_since + self._connect_timeout
                else:
                    deadline = max(self._last_heard, self._last_connect) + self._liveness_period
                wait = max(min(self._next_heartbeat, deadline) - time.monotonic(), 0.0)
                timeout_ms = int(math.ceil(wait * 1000.0))
            poller = zmq.Poller()
            poller.register(self._wake_read, zmq.POLLIN)
            if self._socket is not None:
                poller.register(self._socket, zmq.POLLIN)
            ready = dict(poller.poll(timeout_ms))
            if self._wake_read in ready:
                try:
                    os.read(self._wake_read, 4096)
                except BlockingIOError:
                    pass

            with self._lock:
                taken = list(self._to_submit)
                self._to_submit.clear()
                stopping = self._stopping
                failed = bool(self._error)
            if stopping:
                if self._socket is not None:
                    self._send(self._envelope(disconnect=broker_pb2.Disconnect(reason="client done")))
                    self._socket.close(linger=_GOODBYE_LINGER_MS)
                    self._socket = None
                return
            for submission, batch_id, jobs in taken:
                self._latest_sent = submission
                if failed:
                    continue
                if self._socket is None:
                    self._connect()
                now = time.monotonic()
                if not self._active():  # from idle: a fresh start for the timeouts
                    self._heard = False
                    self._active_since = now
                    self._next_heartbeat = now + self._heartbeat
                for job in jobs:
                    self._outstanding_jobs[(batch_id, job.job_id)] = job
                self._send_jobs(batch_id, jobs, submission)

            if self._socket is not None and self._socket in ready:
                while self._socket is not None:
                    try:
                        frames = self._socket.recv_multipart(zmq.NOBLOCK)
                    except zmq.Again:
                        break
                    if len(frames) != 1:  # the protocol has one frame per message
                        self._drop_message("a message of several frames")
                        continue
                    if not self._on_broker_message(frames[0]):
                        break

            if not self._active():
                continue
            now = time.monotonic()
            if now >= self._next_heartbeat:
                self._send(self._envelope(heartbeat=broker_pb2.Heartbeat(interval_ms=self._heartbeat_ms())))
                self._next_heartbeat = now + self._heartbeat
            if not self._heard:
                if now - self._active_since >= self._connect_timeout:
                    self._fail("no broker answering at %s after %s" % (self.endpoint, _seconds(self._connect_timeout)))
            elif now - self._last_heard >= self._reconnect_timeout:
                self._fail("lost the broker at %s: no answer for %s (%d jobs without a result)"
                           % (self.endpoint, _seconds(round(now - self._last_heard, 1)), len(self._outstanding_jobs)))
            elif now - max(self._last_heard, self._last_connect) >= self._liveness_period:
                self._reconnect("no answer from the broker at %s for %s"
                                % (self.endpoint, _seconds(round(now - self._last_heard, 1))))

    def _envelope(self, **body):
        message = broker_pb2.ClientToBroker(protocol_version=PROTOCOL_VERSION, **body)
        for name in body:  # an empty body (HEARTBEAT) is set only by SetInParent, not by the constructor
            getattr(message, name).SetInParent()
        return message

    def _connect(self):
        sock = self._context.socket(zmq.DEALER)
        sock.setsockopt(zmq.LINGER, 0)
        sock.setsockopt(zmq.SNDHWM, 0)  # never block the I/O thread
        sock.setsockopt(zmq.RCVHWM, 0)  # never make the broker hold results back
        sock.setsockopt(zmq.SNDTIMEO, 0)
        sock.connect(self.endpoint)  # asynchronous: ZeroMQ keeps trying until a broker listens
        self._socket = sock
        self._last_connect = time.monotonic()
        self._warned_bad_message = False
        self._unanswered.clear()
        with self._lock:
            self._stats["connections"] += 1

    def _reconnect(self, why):
        if not self._warned_silence:
            self._log("%s; connecting again (%d jobs to submit again)" % (why, len(self._outstanding_jobs)))
            self._warned_silence = True
        self._socket.close()
        self._connect()
        self._resubmit()

    def _resubmit(self):
        by_batch = collections.OrderedDict()
        for (batch_id, _), job in self._outstanding_jobs.items():
            by_batch.setdefault(batch_id, []).append(job)
        for batch_id, jobs in by_batch.items():
            self._send_jobs(batch_id, jobs, self._latest_sent)
        if not by_batch:  # no job of an unaccepted submission is left waiting: nothing to accept any more
            with self._lock:
                self._accepted_through = max(self._accepted_through, self._latest_sent)
                self._changed.notify_all()

    def _heartbeat_ms(self):
        """This client's heartbeat interval as the protocol says it, ms."""
        return max(1, int(round(self._heartbeat * 1000)))

    def _send_jobs(self, batch_id, jobs, submission):
        start = 0
        while True:
            message = self._envelope(submit=broker_pb2.Submit(batch_id=batch_id, client_id=self.client_id,
                                                                owner_token=self._owner_token,
                                                                heartbeat_ms=self._heartbeat_ms()))
            size = 0
            end = start
            while end < len(jobs):
                job_size = jobs[end].ByteSize()
                if end > start and size + job_size > self._max_submit_bytes:
                    break
                size += job_size
                end += 1
            message.submit.jobs.extend(jobs[start:end])
            self._send(message)
            self._unanswered.append(submission)
            with self._lock:
                self._stats["submit_messages"] += 1
            start = end
            if start >= len(jobs):
                return

    def _on_broker_message(self, payload):
        """Handles one message; False when it replaced the socket (stop reading the old one)."""
        message = broker_pb2.BrokerToClient()
        try:
            message.ParseFromString(payload)
        except Exception:  # google.protobuf.message.DecodeError (its module differs between implementations)
            self._drop_message("not a protocol message (failed to parse)")
            return True
        if message.protocol_version != PROTOCOL_VERSION:
            self._drop_message("wrong protocol version %d" % message.protocol_version)
            return True
        body = message.WhichOneof("body")
        if body is None:
            self._drop_message("message without a body")
            return True
        self._heard = True
        self._last_heard = time.monotonic()
        if self._warned_silence:
            self._log("the broker at %s answers again" % self.endpoint)
            self._warned_silence = False
        if body == "heartbeat":
            # A broker slower than this client is waited for at its pace (up to a minute's), not taken for dead.
            broker_seconds = min(message.heartbeat.interval_ms / 1000.0, 60.0)
            self._liveness_period = max(self._heartbeat, broker_seconds) * self._liveness
        elif body == "accepted":
            self._on_accepted()
        elif body == "result":
            self._on_result(message.result)
        elif body == "error":
            self._fail("the broker at %s rejected batch %s: %s"
                       % (self.endpoint, message.error.batch_id, message.error.message))
        elif body == "disconnect":
            if not self._active():  # nothing to lose: connect again on the next submit()
                self._socket.close()
                self._socket = None
                return False
            self._reconnect("the broker at %s said goodbye (%s)" % (self.endpoint, message.disconnect.reason))
            return False
        return True

    def _on_accepted(self):
        if not self._unanswered:  # an answer to a SUBMIT of a previous socket
            return
        self._unanswered.popleft()
        through = self._latest_sent if not self._unanswered else self._unanswered[0] - 1
        with self._lock:
            self._accepted_through = max(self._accepted_through, through)
            self._changed.notify_all()

    def _on_result(self, result):
        job = self._outstanding_jobs.pop((result.batch_id, result.job_id), None)
        if job is None:  # answered already (a resubmission ran it twice) or not ours
            with self._lock:
                self._stats["duplicates_dropped"] += 1
            return
        copy = result_pb2.Result()
        copy.CopyFrom(result)
        with self._lock:
            state = self._batches.get(result.batch_id)
            if state is not None:
                state.results.append(JobResult(copy))
                self._stats["results"] += 1
                self._changed.notify_all()

    def _fail(self, message):
        with self._lock:
            if not self._error:
                self._error = message
            self._changed.notify_all()
        # Nothing is outstanding any more: the client goes idle and stops heartbeating.
        self._outstanding_jobs.clear()
        self._unanswered.clear()

    def _drop_message(self, why):
        with self._lock:
            self._stats["messages_dropped"] += 1
        if self._warned_bad_message:
            return
        self._warned_bad_message = True
        self._log("dropped a message from the broker at %s: %s (further bad messages on this connection are "
                  "dropped without a log line)" % (self.endpoint, why))

    def _send(self, message):
        try:
            self._socket.send(message.SerializeToString(), zmq.NOBLOCK)
        except zmq.Again:  # no connection can take it (a refused handshake): the timeouts deal with that
            pass
