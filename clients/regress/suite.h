// A regression suite (docs/regress.md): named cases, each one job — a scenario with its controller, a genome, a
// seed and optional repository overrides — and the tolerance within which its fitness must stay of the baseline.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "clients/runtime/batch_input.h"

namespace orcs::regress {

/// How far a fitness may move from its baseline and still pass: |now − baseline| ≤ max(absolute, relative ·
/// |baseline|), the looser of the two. Both 0: the same bits only.
struct Tolerance {
  double absolute = 0.0;  ///< allowed difference, in the fitness's unit, ≥ 0
  double relative = 0.0;  ///< allowed difference as a fraction of |baseline|, ≥ 0
  /// The allowed difference around `baseline`.
  double Allowed(double baseline) const;
};

/// One case of a suite: what its job is and how strictly its fitness is compared.
struct SuiteCase {
  std::string name;               ///< unique in the suite: the job id, the JUnit test case, the baseline key
  std::string field;              ///< where it is in the suite file, e.g. "cases[2]", for messages
  runtime::ScenarioInput scenario;  ///< "scenario": loaded and resolved (the path is relative to the suite)
  runtime::Genome genome;           ///< "genome" inline or "@FILE"; else the scenario's "genome"; else empty
  std::uint64_t seed = 1;         ///< "seed": the job's seed
  /// "values": repository path → value text (numbers round-trip, booleans T/F), applied as the job's overrides
  std::vector<std::pair<std::string, std::string>> values;
  Tolerance tolerance;  ///< "tolerance": the case's, member by member falling back to the suite's
};

/// A suite file, read, with every case's scenario and genome loaded.
struct Suite {
  std::string path;              ///< the suite file as given
  std::string name;              ///< "name", default the file name without ".json": a baseline records it
  Tolerance tolerance;           ///< the suite-wide default "tolerance"
  std::vector<SuiteCase> cases;  ///< in file order, at least one
};

/// Reads a suite and loads every case's scenario and genome file (paths relative to the suite's folder). Throws
/// InputError naming the suite file and the field: unknown keys, wrong types, a negative tolerance, a missing,
/// empty, malformed or duplicate case name, a case whose scenario or genome does not load.
Suite ReadSuite(const std::string& path);

/// Where a suite's baseline is when --baseline is not given: beside it, "x.json" → "x.baseline.json" for ODE
/// (the default engine) and "x.mujoco.baseline.json" for MuJoCo: each engine keeps its own.
std::string DefaultBaselinePath(const std::string& suite_path, const std::string& engine = "ODE");

}  // namespace orcs::regress
