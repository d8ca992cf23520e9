"""orcs_client: submit batches of jobs to an orcs broker from Python and read their results.

    from orcs_client import BatchClient, Scenario

    scenario = Scenario.load("scenarios/examples/swing_oscillator.json")   # via `orcs-batch resolve`
    with BatchClient("tcp://127.0.0.1:5555", heartbeat=1.0) as client:
        batch = client.submit([scenario.job(genome, seed=1) for genome in genomes])
        for result in batch.results(timeout=120):                          # each job's result once, as it arrives
            print(result.job_id, result.status, result.fitness)

Needs only the standard library, Debian's python3-zmq and python3-protobuf, and the modules generated from
proto/orcs/v1 at build time (found through ORCS_PYTHON_PATH or the source tree's build/python). See
clients/python/README.md.
"""

from ._proto import load_modules as _load_modules
from .batch_client import Batch, BatchClient, PROTOCOL_VERSION
from .errors import BrokerError, OrcsClientError, ResultTimeout, ScenarioError, SetupError
from .job_result import JobResult, status_name
from .scenario import Scenario, find_orcs_batch, genome_json

job_pb2, result_pb2, broker_pb2 = _load_modules()
Job = job_pb2.Job        # orcs.v1.Job
Override = job_pb2.Override  # orcs.v1.Override
Result = result_pb2.Result  # orcs.v1.Result

__all__ = ["Batch", "BatchClient", "BrokerError", "Job", "JobResult", "OrcsClientError", "Override",
           "PROTOCOL_VERSION", "Result", "ResultTimeout", "Scenario", "ScenarioError", "SetupError",
           "find_orcs_batch", "genome_json", "status_name", "job_pb2", "result_pb2", "broker_pb2"]
