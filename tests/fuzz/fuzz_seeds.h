// The seed corpus of every fuzz target: valid inputs the fuzzer starts from. Files come from scenarios/ (the
// environments with their robot files inline, motion records and example scenarios, resolved); messages, datagrams, value files and measured runs
// are built here from the same scenarios. scripts/fuzz.sh writes them with orcs-fuzz-seeds; the regression test
// feeds them in memory, and every one must be accepted.
#pragma once

#include <string>
#include <vector>

namespace orcs::fuzz {

/// One seed input.
struct Seed {
  std::string name;   ///< file name in the corpus folder, e.g. "example.xml"
  std::string bytes;  ///< the input
};

/// The seeds of target `target` (a FuzzTargets() name), built from the sources under `source_dir` (the
/// repository root). Throws InputError when a scenario file cannot be read.
std::vector<Seed> SeedsFor(const std::string& target, const std::string& source_dir);

}  // namespace orcs::fuzz
