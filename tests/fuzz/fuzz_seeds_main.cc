// orcs-fuzz-seeds DIR: writes every fuzz target's seed corpus to DIR/<target>/ (scripts/fuzz.sh starts from it).
#include <filesystem>
#include <fstream>
#include <iostream>

#include "model/core/error.h"
#include "tests/fuzz/fuzz_entries.h"
#include "tests/fuzz/fuzz_seeds.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: orcs-fuzz-seeds DIR\n";
    return 2;
  }
  try {
    for (const orcs::fuzz::FuzzTarget& target : orcs::fuzz::FuzzTargets()) {
      const std::filesystem::path dir = std::filesystem::path(argv[1]) / target.name;
      std::filesystem::create_directories(dir);
      for (const orcs::fuzz::Seed& seed : orcs::fuzz::SeedsFor(target.name, ORCS_SOURCE_DIR)) {
        std::ofstream(dir / seed.name, std::ios::binary) << seed.bytes;
      }
    }
  } catch (const orcs::InputError& error) {
    std::cerr << "orcs-fuzz-seeds: " << error.what() << "\n";
    return 2;
  }
  return 0;
}
