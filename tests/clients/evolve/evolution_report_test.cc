// fitness.csv, best_genome.json and the terminal line: numbers that read back to the same doubles, empty fields for
// NaN, and a genome file that replays the champion exactly.
#include "clients/evolve/evolution_report.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "model/core/error.h"
#include "tests/support/temp_dir.h"

namespace orcs::evolve {
namespace {

using test_support::TempDir;
using ::testing::HasSubstr;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::uint64_t Bits(double value) { return std::bit_cast<std::uint64_t>(value); }

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.push_back("");
  return parts;
}

// A field of fitness.csv as a double: NaN for an empty one.
double Parse(const std::string& field) { return field.empty() ? kNaN : std::strtod(field.c_str(), nullptr); }

// Numbers that print badly with few digits: 0.1 + 0.2, 1/3, tiny, huge, negative.
std::vector<GenerationRecord> History() {
  GenerationRecord none{0, 16, 16, kNaN, kNaN, kNaN, kNaN, kNaN, 4.125};
  GenerationRecord first{1, 16, 3, 0.1 + 0.2, 1.0 / 3.0, -1e-300, -123456.789e10, 0.1 + 0.2, 2.0 / 3.0};
  GenerationRecord second{2, 15, 0, 5e300, -0.0, 1.0 / 7.0, -2.5, 5e300, 0.0};
  return {none, first, second};
}

TEST(EvolutionReportTest, FitnessCsvHasTheHeaderAndNumbersThatReadBackExactly) {
  TempDir dir;
  const std::vector<GenerationRecord> history = History();
  WriteFitnessCsv(dir.path().string(), history);
  const std::vector<std::string> lines = Split(dir.Read("fitness.csv"), '\n');
  ASSERT_EQ(lines.size(), 5u) << "header, 3 generations, and the final newline";
  EXPECT_EQ(lines[0], "generation,evaluations,failed,best,mean,median,worst,best_so_far,seconds");
  EXPECT_EQ(lines[4], "");
  // A generation without ok jobs: empty fields, not "nan".
  EXPECT_EQ(lines[1], "0,16,16,,,,,,4.125");
  for (std::size_t g = 0; g < history.size(); ++g) {
    SCOPED_TRACE("generation " + std::to_string(g));
    const std::vector<std::string> fields = Split(lines[g + 1], ',');
    ASSERT_EQ(fields.size(), 9u);
    const GenerationRecord& r = history[g];
    EXPECT_EQ(fields[0], std::to_string(r.generation));
    EXPECT_EQ(fields[1], std::to_string(r.evaluations));
    EXPECT_EQ(fields[2], std::to_string(r.failed));
    const double expected[] = {r.best, r.mean, r.median, r.worst, r.best_so_far, r.seconds};
    for (int k = 0; k < 6; ++k) {
      const double read = Parse(fields[3 + k]);
      if (std::isnan(expected[k])) {
        EXPECT_EQ(fields[3 + k], "") << "column " << 3 + k;
      } else {
        EXPECT_EQ(Bits(read), Bits(expected[k])) << "column " << 3 + k << ": " << fields[3 + k];
      }
    }
  }
  // Rewritten after every generation: a shorter history replaces the file, no temporary file is left.
  WriteFitnessCsv(dir.path().string(), {history[0]});
  EXPECT_EQ(dir.Read("fitness.csv"),
            "generation,evaluations,failed,best,mean,median,worst,best_so_far,seconds\n"
            "0,16,16,,,,,,4.125\n");
  EXPECT_EQ(dir.FileNames(), std::vector<std::string>{"fitness.csv"});
}

TEST(EvolutionReportTest, BestGenomeJsonIsTheChampionsGenomeExactly) {
  TempDir dir;
  const Champion champion{{0.1 + 0.2, -1.0 / 3.0, 1e-310, 12345678.9, -0.0, 0.0}, 0.75, 4};
  WriteBestGenome(dir.path().string(), champion);
  const nlohmann::json genome = nlohmann::json::parse(dir.Read("best_genome.json"));
  ASSERT_TRUE(genome.is_array());
  ASSERT_EQ(genome.size(), champion.genome.size());
  for (std::size_t i = 0; i < champion.genome.size(); ++i) {
    EXPECT_EQ(Bits(genome[i].get<double>()), Bits(champion.genome[i])) << "gene " << i;
  }
}

TEST(EvolutionReportTest, NoBestGenomeFileBeforeAnyGenomeRanOk) {
  TempDir dir;
  WriteBestGenome(dir.path().string(), Champion{});
  EXPECT_TRUE(dir.FileNames().empty());
}

TEST(EvolutionReportTest, WritingIntoAMissingFolderIsAnInputError) {
  TempDir dir;
  const std::string missing = dir.PathOf("no/such/folder");
  EXPECT_THROW(WriteFitnessCsv(missing, History()), InputError);
  EXPECT_THROW(WriteBestGenome(missing, Champion{{1.0}, 1.0, 0}), InputError);
}

TEST(EvolutionReportTest, GenerationLineSaysWhereTheRunIs) {
  const GenerationRecord record{3, 16, 2, 1.25, 0.4, 0.5, -1.0, 1.3, 4.06};
  EXPECT_EQ(GenerationLine(record, 30),
            "generation 3/30: best 1.25, mean 0.4 (16 jobs, 2 failed, 4.1 s); best so far 1.3");
  // Four significant digits; a dash for a generation without ok jobs.
  const GenerationRecord long_numbers{7, 8, 0, 1.0 / 3.0, -123.456789, 0.0, 0.0, 2.0 / 3.0, 0.04};
  EXPECT_EQ(GenerationLine(long_numbers, 10),
            "generation 7/10: best 0.3333, mean -123.5 (8 jobs, 0 failed, 0.0 s); best so far 0.6667");
  const GenerationRecord none{0, 16, 16, kNaN, kNaN, kNaN, kNaN, kNaN, 2.0};
  EXPECT_EQ(GenerationLine(none, 5), "generation 0/5: best -, mean - (16 jobs, 16 failed, 2.0 s); best so far -");
}

}  // namespace
}  // namespace orcs::evolve
