// DIR/checkpoint.json: what is written reads back exactly (history with its NaN fields, champion, the pagmo state,
// which restores a run that continues as if never stopped), and every reason to refuse a resume is an InputError
// naming the file and what differs, before anything is submitted.
#include "clients/evolve/evolution_checkpoint.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "clients/evolve/evolution.h"
#include "clients/evolve/evolution_settings.h"
#include "clients/runtime/batch_input.h"
#include "tests/support/input_error_of.h"
#include "tests/support/temp_dir.h"

namespace orcs::evolve {
namespace {

using test_support::InputErrorOf;
using test_support::TempDir;
using ::testing::AllOf;
using ::testing::HasSubstr;

// Two hip oscillators (8 genes), evolved with CMA-ES on 5 genomes.
std::string HipsScenario(const std::string& name = "hips", double duration = 0.1) {
  return R"({
  "name": ")" +
         name + R"(",
  "duration": )" +
         std::to_string(duration) + R"(,
  "controller": {"type": "oscillator", "joints": ["Right/HipYaw", "Left/HipYaw"]},
  "fitness": {"terms": [{"type": "final_height", "body": "Middle/Head"}]},
  "evolution": {"bounds": [-1, 1], "algorithm": "cmaes", "population": 5, "seed": 3}
})";
}

// −Σ(g_i − i/10)², except that the whole first batch fails (a generation without ok jobs: NaN statistics) unless
// the run `resumes` after it.
GenomeEvaluator FirstBatchFails(bool resumes = false) {
  auto calls = std::make_shared<int>(resumes ? 1 : 0);
  return [calls](const std::vector<std::vector<double>>& genomes, std::uint64_t) {
    std::vector<Evaluation> evaluations;
    for (const std::vector<double>& genome : genomes) {
      double sum = 0.0;
      for (std::size_t i = 0; i < genome.size(); ++i) sum += std::pow(genome[i] - 0.1 * static_cast<double>(i), 2);
      evaluations.push_back({-sum, *calls > 0});
    }
    ++*calls;
    return evaluations;
  };
}

std::uint64_t Bits(double value) { return std::bit_cast<std::uint64_t>(value); }

class EvolutionCheckpointTest : public ::testing::Test {
 protected:
  void SetUp() override {
    input_ = runtime::LoadScenario(dir_.Write("hips.json", HipsScenario()));
    settings_ = ReadEvolutionSettings(input_, {});
    folder_ = dir_.PathOf("run");
    std::filesystem::create_directories(folder_);
  }
  // A run of generations 0..2 (0 without ok jobs), checkpointed into folder_.
  std::unique_ptr<Evolution> RunAndCheckpoint() {
    auto evolution = std::make_unique<Evolution>(settings_, FirstBatchFails());
    evolution->Initialise();
    evolution->Step();
    evolution->Step();
    WriteCheckpoint(folder_, CheckpointOf(*evolution, Fingerprint(input_, settings_), nlohmann::ordered_json::object()));
    return evolution;
  }
  std::string Checkpoint() const { return folder_ + "/checkpoint.json"; }
  // Rewrites checkpoint.json with `change` applied to its JSON.
  template <typename Change>
  void Edit(Change change) {
    nlohmann::ordered_json document = nlohmann::ordered_json::parse(dir_.Read(Checkpoint()));
    change(document);
    dir_.Write(Checkpoint(), document.dump(1));
  }

  TempDir dir_;
  runtime::ScenarioInput input_;
  EvolutionSettings settings_;
  std::string folder_;
};

TEST_F(EvolutionCheckpointTest, ReadsBackWhatWasWrittenExactly) {
  const std::unique_ptr<Evolution> evolution = RunAndCheckpoint();
  const nlohmann::ordered_json fingerprint = Fingerprint(input_, settings_);
  const EvolutionCheckpoint read = ReadCheckpoint(folder_, fingerprint);

  EXPECT_EQ(read.fingerprint, fingerprint);
  ASSERT_EQ(read.history.size(), 3u);
  EXPECT_TRUE(std::isnan(read.history[0].best)) << "generation 0 had no ok job";
  EXPECT_TRUE(std::isnan(read.history[0].best_so_far));
  for (std::size_t g = 0; g < 3; ++g) {
    SCOPED_TRACE("generation " + std::to_string(g));
    const GenerationRecord& w = evolution->history()[g];
    const GenerationRecord& r = read.history[g];
    EXPECT_EQ(r.generation, w.generation);
    EXPECT_EQ(r.evaluations, w.evaluations);
    EXPECT_EQ(r.failed, w.failed);
    for (auto field : {&GenerationRecord::best, &GenerationRecord::mean, &GenerationRecord::median,
                       &GenerationRecord::worst, &GenerationRecord::best_so_far, &GenerationRecord::seconds}) {
      if (std::isnan(w.*field)) {
        EXPECT_TRUE(std::isnan(r.*field));
      } else {
        EXPECT_EQ(Bits(r.*field), Bits(w.*field));
      }
    }
  }
  EXPECT_EQ(read.history[0].failed, 5u);
  EXPECT_EQ(read.champion.genome, evolution->champion().genome);
  EXPECT_EQ(Bits(read.champion.fitness), Bits(evolution->champion().fitness));
  EXPECT_EQ(read.champion.generation, evolution->champion().generation);
  EXPECT_EQ(read.champion.seed, evolution->champion().seed);
  EXPECT_EQ(read.pagmo_state, evolution->SaveState());

  // Restored from the file, a run continues exactly as the one that wrote it.
  Evolution resumed(settings_, FirstBatchFails(/*resumes=*/true));
  resumed.Restore(read.pagmo_state, read.history, read.champion, Checkpoint());
  evolution->Step();
  resumed.Step();
  EXPECT_EQ(resumed.population().get_x(), evolution->population().get_x());
  EXPECT_EQ(resumed.population().get_f(), evolution->population().get_f());
  EXPECT_EQ(resumed.champion().genome, evolution->champion().genome);
  EXPECT_EQ(resumed.history().back().evaluations, evolution->history().back().evaluations);
  EXPECT_EQ(Bits(resumed.history().back().best), Bits(evolution->history().back().best));
}

TEST_F(EvolutionCheckpointTest, ThePagmoStateNamesTheProblemByTheKeyOlderCheckpointsUse) {
  // boost files the problem under its export key; BatchProblem moved from clients/evolve to model/identify and
  // kept the key it had, so that checkpoints written before the move still load (model/identify/batch_problem.h).
  const std::unique_ptr<Evolution> evolution = RunAndCheckpoint();
  EXPECT_NE(evolution->SaveState().find("udp orcs::evolve::BatchProblem"), std::string::npos);
}

TEST_F(EvolutionCheckpointTest, AFolderWithoutACheckpointIsNamed) {
  EXPECT_THAT(InputErrorOf([&] { ReadCheckpoint(folder_, Fingerprint(input_, settings_)); }),
              AllOf(HasSubstr("--resume " + folder_), HasSubstr("no checkpoint.json")));
}

TEST_F(EvolutionCheckpointTest, AnotherScenarioIsRefusedNamingBoth) {
  RunAndCheckpoint();
  const runtime::ScenarioInput other = runtime::LoadScenario(dir_.Write("other.json", HipsScenario("other")));
  const std::string renamed =
      InputErrorOf([&] { ReadCheckpoint(folder_, Fingerprint(other, ReadEvolutionSettings(other, {}))); });
  EXPECT_THAT(renamed, AllOf(HasSubstr(Checkpoint()), HasSubstr("written for scenario 'hips'"),
                             HasSubstr("not for 'other'"), HasSubstr("other.json")));

  // The same name, other content (a longer duration): the digests differ, and both are named.
  const runtime::ScenarioInput longer = runtime::LoadScenario(dir_.Write("longer.json", HipsScenario("hips", 0.2)));
  const nlohmann::ordered_json fingerprint = Fingerprint(longer, ReadEvolutionSettings(longer, {}));
  const std::string old_digest = Fingerprint(input_, settings_)["scenario_digest"];
  const std::string new_digest = fingerprint["scenario_digest"];
  ASSERT_NE(old_digest, new_digest);
  EXPECT_THAT(InputErrorOf([&] { ReadCheckpoint(folder_, fingerprint); }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("hips.json, digest " + old_digest),
                    HasSubstr("longer.json, digest " + new_digest)));

  // The same scenario given by another path is fine.
  const runtime::ScenarioInput copy = runtime::LoadScenario(dir_.Write("copy/hips.json", HipsScenario()));
  EXPECT_NO_THROW(ReadCheckpoint(folder_, Fingerprint(copy, settings_)));
}

TEST_F(EvolutionCheckpointTest, OtherSettingsAreRefusedNamingTheFieldAndBothValues) {
  RunAndCheckpoint();
  const auto error_with = [&](auto change) {
    EvolutionSettings settings = settings_;
    change(settings);
    return InputErrorOf([&] { ReadCheckpoint(folder_, Fingerprint(input_, settings)); });
  };
  EXPECT_THAT(error_with([](EvolutionSettings& s) { s.algorithm = Algorithm::kDe; }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("made with algorithm \"cmaes\", this run has \"de\"")));
  EXPECT_THAT(error_with([](EvolutionSettings& s) { s.population = 7; }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("made with population 5, this run has 7")));
  EXPECT_THAT(error_with([](EvolutionSettings& s) { s.seed = 4; }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("made with seed 3, this run has 4")));
  EXPECT_THAT(error_with([](EvolutionSettings& s) { s.bounds[2].high = 2.0; }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("made with bounds [[-1.0,1.0],"),
                    HasSubstr("this run has [[-1.0,1.0],[-1.0,1.0],[-1.0,2.0],")));
  EXPECT_THAT(error_with([](EvolutionSettings& s) { s.sigma = 0.5; }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("made with sigma 0.3, this run has 0.5")));
  EXPECT_THAT(error_with([](EvolutionSettings& s) { s.fresh_sets = true; }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("made with fresh_sets none, this run has true")));
  // What may change between runs: more generations, other validation seeds.
  EXPECT_NO_THROW(ReadCheckpoint(folder_, Fingerprint(input_, [&] {
                                   EvolutionSettings s = settings_;
                                   s.generations += 10;
                                   s.validate = 0;
                                   return s;
                                 }())));
}

// fresh_sets is in the fingerprint only when on (older checkpoints stay valid), so a setting only the checkpoint
// holds must be caught too: a fresh-sets run is not continued with the same sets throughout.
TEST_F(EvolutionCheckpointTest, AFreshSetsCheckpointIsNotResumedWithoutThem) {
  settings_.fresh_sets = true;
  const std::unique_ptr<Evolution> evolution = RunAndCheckpoint();
  EXPECT_NE(evolution->champion().seed, settings_.seed) << "scored on a generation's own sets";
  EXPECT_EQ(ReadCheckpoint(folder_, Fingerprint(input_, settings_)).champion.seed, evolution->champion().seed);
  EvolutionSettings same_sets = settings_;
  same_sets.fresh_sets = false;
  EXPECT_THAT(InputErrorOf([&] { ReadCheckpoint(folder_, Fingerprint(input_, same_sets)); }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("made with fresh_sets true, this run has none")));
}

TEST_F(EvolutionCheckpointTest, ADamagedPagmoStateIsAnInputErrorNamingTheFile) {
  const std::unique_ptr<Evolution> evolution = RunAndCheckpoint();
  const std::string state = evolution->SaveState();
  for (const std::string& damaged :
       {std::string("not a boost archive"), state.substr(0, state.size() / 2), std::string()}) {
    SCOPED_TRACE(damaged.substr(0, 40));
    Edit([&](nlohmann::ordered_json& document) { document["pagmo_state"] = damaged; });
    const EvolutionCheckpoint read = ReadCheckpoint(folder_, Fingerprint(input_, settings_));
    Evolution resumed(settings_, FirstBatchFails());
    EXPECT_THAT(InputErrorOf([&] { resumed.Restore(read.pagmo_state, read.history, read.champion, Checkpoint()); }),
                AllOf(HasSubstr(Checkpoint()), HasSubstr("field 'pagmo_state' does not read back")));
  }
}

TEST_F(EvolutionCheckpointTest, AStateOfAnotherGenomeLengthIsRefused) {
  const std::unique_ptr<Evolution> evolution = RunAndCheckpoint();
  EvolutionSettings shorter = settings_;
  shorter.bounds.resize(3);
  Evolution other(shorter, FirstBatchFails());
  EXPECT_THAT(InputErrorOf([&] {
                other.Restore(evolution->SaveState(), evolution->history(), evolution->champion(), Checkpoint());
              }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("another problem")));
}

TEST_F(EvolutionCheckpointTest, AnotherFormatOrAMalformedFileIsNamed) {
  RunAndCheckpoint();
  Edit([](nlohmann::ordered_json& document) { document["format"] = "orcs evolve checkpoint 2"; });
  EXPECT_THAT(InputErrorOf([&] { ReadCheckpoint(folder_, Fingerprint(input_, settings_)); }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("field 'format'"), HasSubstr("orcs evolve checkpoint 1")));

  dir_.Write(Checkpoint(), "{\"format\": \"orcs evolve checkpoint 1\",\n \"fingerprint\": ");
  EXPECT_THAT(InputErrorOf([&] { ReadCheckpoint(folder_, Fingerprint(input_, settings_)); }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("malformed JSON")));
}

TEST_F(EvolutionCheckpointTest, AMissingOrEmptyHistoryIsNamed) {
  RunAndCheckpoint();
  Edit([](nlohmann::ordered_json& document) { document["history"] = nlohmann::ordered_json::array(); });
  EXPECT_THAT(InputErrorOf([&] { ReadCheckpoint(folder_, Fingerprint(input_, settings_)); }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("field 'history'"), HasSubstr("generation 0")));
  Edit([](nlohmann::ordered_json& document) { document.erase("champion"); });
  EXPECT_THAT(InputErrorOf([&] { ReadCheckpoint(folder_, Fingerprint(input_, settings_)); }),
              AllOf(HasSubstr(Checkpoint()), HasSubstr("field 'champion'")));
}

}  // namespace
}  // namespace orcs::evolve
