"""JobResult: one job's result as Python values, with the wire message beside it."""

# Result.Status numbers (proto/orcs/v1/result.proto) → the names results.jsonl uses (proto/result_json.cc).
STATUS_NAMES = {1: "ok", 2: "invalid_input", 3: "unstable_physics", 4: "timeout", 5: "worker_lost",
                6: "internal_error", 7: "crashed", 8: "script_error", 9: "script_limit",
                10: "plugin_missing"}


def status_name(status):
    """The results.jsonl name of a Result.Status number; anything unknown (or unset) is "internal_error"."""
    return STATUS_NAMES.get(status, "internal_error")


class JobResult:
    """A thin view of a v1.Result. Fields are read once from the message, which stays available as `proto`."""

    __slots__ = ("proto", "job_id", "batch_id", "status", "fitness", "terms", "message", "worker_id", "attempts")

    def __init__(self, proto):
        self.proto = proto                          # the orcs.v1.Result as it arrived
        self.job_id = proto.job_id                  # the job's id (Job.job_id)
        self.batch_id = proto.batch_id              # the batch it belongs to
        self.status = status_name(proto.status)     # "ok", "invalid_input", ... as in results.jsonl
        # The aggregated fitness (the scenario's mean, min, max or quantile over the parameter sets); None unless
        # ok, so that a failed job's 0 is never taken for a fitness.
        self.fitness = proto.fitness if self.status == "ok" else None
        self.terms = mean_terms(proto)              # each term's mean over the sets, unweighted, in order
        self.message = proto.message                # why, when not ok
        self.worker_id = proto.worker_id            # the worker that ran it
        self.attempts = proto.attempts              # how many times the broker dispatched it

    @property
    def ok(self):
        """True when the job ran to the end and its fitness is valid."""
        return self.status == "ok"

    def __repr__(self):
        fitness = "None" if self.fitness is None else repr(self.fitness)
        return "JobResult(job_id=%r, status=%r, fitness=%s)" % (self.job_id, self.status, fitness)


def mean_terms(result):
    """Each fitness term's mean over the parameter sets that report it, in first-seen order: the `terms` of a
    results.jsonl line, summed in the same order, so the same bits."""
    sums = {}
    for parameter_set in result.parameter_sets:
        for term in parameter_set.terms:
            total, count = sums.get(term.name, (0.0, 0))
            sums[term.name] = (total + term.value, count + 1)
    return {name: total / count for name, (total, count) in sums.items()}
