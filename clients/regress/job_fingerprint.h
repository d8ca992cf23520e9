// The fingerprint of a regression case's job (docs/regress.md): a hash of everything the worker receives that
// decides the result — the resolved scenario (with every referenced file inlined), the genome, the seed and the
// value overrides. A baseline stores it per case, so a baseline recorded for another job is refused instead of
// being compared with numbers it never described.
#pragma once

#include <string>

#include "orcs/v1/job.pb.h"

namespace orcs::regress {

/// "fnv1a64:" and 16 hex digits: FNV-1a (64 bit) over the job's scenario JSON, genome JSON, seed and overrides
/// (path and value, in order), each field length-prefixed so that no two jobs share a byte stream. The job id,
/// batch id and time limit are not part of it. Not a cryptographic hash: it detects changes, not tampering.
std::string JobFingerprint(const v1::Job& job);

}  // namespace orcs::regress
