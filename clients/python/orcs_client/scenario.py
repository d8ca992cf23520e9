"""Scenario: a scenario file resolved by `orcs-batch resolve` (every referenced file inlined), and jobs made from it.

The resolution rules (environment XML, value files, motion records; paths relative to the scenario) live in C++
alone (model/scene/scenario.h, ResolveScenarioFile); this module runs the orcs-batch program of the build to apply
them, so a job made here carries exactly the scenario text a job of `orcs-batch run` carries.
"""

import json
import math
import os
import shutil
import subprocess

from . import _proto
from .errors import ScenarioError, SetupError

job_pb2 = _proto.load_modules()[0]


def find_orcs_batch(program=None):
    """The orcs-batch program: `program` if given, else $ORCS_BIN/orcs-batch, else the source tree's
    build/bin/orcs-batch, else orcs-batch on PATH. Raises SetupError when none exists."""
    if program:
        candidates = [program]
    elif os.environ.get("ORCS_BIN"):
        candidates = [os.path.join(os.environ["ORCS_BIN"], "orcs-batch")]
    else:
        candidates = [os.path.join(_proto.SOURCE_DIR, "build", "bin", "orcs-batch"), shutil.which("orcs-batch") or ""]
    for candidate in candidates:
        if candidate and os.path.isfile(candidate) and os.access(candidate, os.X_OK):
            return candidate
    raise SetupError("orcs-batch not found (looked for %s): build it (`ninja -C build orcs-batch`) or set ORCS_BIN "
                     "to the folder holding it" % ", ".join(c for c in candidates if c))


def _override_text(value):
    """A repository value as the text a value file would hold: true/false, the shortest exact float, a string."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError("override value %r is not finite" % value)
        return repr(value)
    return str(value)


def genome_json(genome):
    """A genome as the JSON text a job carries: a flat list of finite numbers, or a network object. Raises
    ValueError naming the first bad element."""
    if isinstance(genome, (list, tuple)):
        for index, gene in enumerate(genome):
            if isinstance(gene, bool) or not isinstance(gene, (int, float)) or not math.isfinite(gene):
                raise ValueError("genome[%d]: expected a finite number, found %r" % (index, gene))
        genome = list(genome)
    elif not isinstance(genome, dict):
        raise ValueError("genome: expected a list of numbers or a network object, found %s" % type(genome).__name__)
    try:
        return json.dumps(genome, allow_nan=False, separators=(",", ":"))
    except (TypeError, ValueError) as error:
        raise ValueError("genome: not JSON: %s" % error) from None


class Scenario:
    """A resolved scenario: `text` is what every job carries, `data` the same parsed."""

    def __init__(self, path, text):
        self.path = path                  # the scenario file as given
        self.text = text                  # the resolved, self-contained scenario JSON (Job.scenario_json)
        self.data = json.loads(text)      # the same, parsed
        # A label for reports: the scenario's "name", else the file's stem (as orcs-batch names it).
        self.name = self.data.get("name") or os.path.splitext(os.path.basename(path))[0]
        self.genome = self.data.get("genome")  # the scenario's own genome, None when it has none

    @classmethod
    def load(cls, path, orcs_batch=None, timeout=60.0):
        """Reads and resolves a scenario file with `orcs-batch resolve`. Raises ScenarioError with orcs-batch's
        one line naming the file and field when the scenario (or a file it references) is bad."""
        program = find_orcs_batch(orcs_batch)
        try:
            run = subprocess.run([program, "resolve", path], stdin=subprocess.DEVNULL, capture_output=True,
                                 text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise ScenarioError("%s resolve %s: no answer within %g s" % (program, path, timeout)) from None
        if run.returncode != 0:
            lines = [line for line in run.stderr.splitlines() if line.strip()]
            why = lines[-1] if lines else "exit code %d" % run.returncode
            raise ScenarioError(why[len("orcs-batch: "):] if why.startswith("orcs-batch: ") else why)
        return cls(path, run.stdout.strip())

    def job(self, genome=None, seed=1, job_id="", overrides=(), time_limit=0.0):
        """An orcs.v1.Job of this scenario. genome: a list of numbers or a network object; None = the scenario's
        "genome", else an empty one. seed: every random stream of the job (uint64). job_id: "" = let
        BatchClient.submit number it. overrides: (path, value) pairs or a dict, applied after the scenario's
        values. time_limit: wall-clock seconds, 0 = none. Raises ValueError for a bad genome, seed or value."""
        if genome is None:
            genome = self.genome if self.genome is not None else []
        if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2 ** 64:
            raise ValueError("seed: expected an integer in [0, 2^64), found %r" % (seed,))
        if not (isinstance(time_limit, (int, float)) and math.isfinite(time_limit) and time_limit >= 0):
            raise ValueError("time_limit: expected seconds ≥ 0, found %r" % (time_limit,))
        job = job_pb2.Job(job_id=job_id, scenario_json=self.text, genome_json=genome_json(genome), seed=seed,
                          time_limit_seconds=float(time_limit))
        pairs = overrides.items() if isinstance(overrides, dict) else overrides
        for path, value in pairs:
            job.overrides.add(path=str(path), value=_override_text(value))
        return job
