// Between wire jobs/results (proto orcs.v1) and the model's evaluation types: the one place where a worker
// turns bytes into a scenario and an outcome back into bytes (docs/architecture.md: model/ never sees protobuf).
#pragma once

#include "orcs/v1/job.pb.h"
#include "orcs/v1/result.pb.h"
#include "model/evaluation/evaluation.h"

namespace orcs::worker {

/// Runs a job: parses its scenario and genome (bad JSON or fields → INVALID_INPUT with the message), evaluates
/// it and returns the result. Never throws; running out of memory is CRASHED with a message naming the process's
/// memory limit (RLIMIT_AS, orcs-worker --memory-limit). `inject_faults`: carry out the scenario's "fault" test hook (only the
/// sandboxed simulation process passes true; see EvaluationRequest::inject_faults).
/// `plugins`: the components orcs-worker --plugins loaded (null: none; a job naming one is PLUGIN_MISSING).
v1::Result RunJob(const v1::Job& job, bool inject_faults = false, const script::PluginRegistry* plugins = nullptr);

/// The evaluation request of a job: its scenario and genome parsed, its overrides and limits taken over. Throws
/// InputError naming the job and the field for bad JSON or fields. RunJob uses it; the fuzzer feeds it.
/// `inject_faults` as for RunJob.
evaluation::EvaluationRequest RequestOf(const v1::Job& job, bool inject_faults = false,
                                        const script::PluginRegistry* plugins = nullptr);

/// The wire result of an evaluation outcome for `job`.
v1::Result ToResult(const v1::Job& job, const evaluation::EvaluationOutcome& outcome);

}  // namespace orcs::worker
