// report.md and report.json as orcs-gap writes them (clients/gap/gap_report.h), on a diagnosis put together by hand:
// what the candidate table says about fits the race abandoned and about values that ended at a bound.
#include "clients/gap/gap_report.h"

#include <gtest/gtest.h>

#include <string>

namespace orcs::gap {
namespace {

identify::ModelScore Candidate(const std::string& label, bool abandoned) {
  identify::ModelScore score;
  score.label = label;
  score.score = 1.0;
  score.fit.abandoned = abandoned;
  score.fit.converged = true;
  score.fit.generations = abandoned ? 10 : 40;
  return score;
}

identify::FittedValue Value(const std::string& path, double value, identify::BoundState bound) {
  identify::FittedValue fitted;
  fitted.path = path;
  fitted.unit = "N·m";
  fitted.value = value;
  fitted.identified = true;
  fitted.bound = bound;
  return fitted;
}

std::size_t Count(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

TEST(GapReportTest, AnAbandonedCandidateSaysItConvergedFirst) {
  identify::Diagnosis diagnosis;
  diagnosis.base = Candidate("refit", false);
  diagnosis.candidates = {Candidate("Stribeck", true), Candidate("Backlash", false)};
  identify::Rig rig;
  rig.kind = "pendulum";
  const identify::DiagnosisOptions options;
  const std::string md = ReportMarkdown(diagnosis, rig, options);
  EXPECT_EQ(Count(md, "| abandoned after 10 generations, converged yes |"), 1u) << md;
  EXPECT_EQ(Count(md, "| yes |"), 2u) << md;
}

TEST(GapReportTest, AValueAtABoundOrBeyondTheCatalogueIsSaidInBothReports) {
  identify::Diagnosis diagnosis;
  diagnosis.base = Candidate("refit", false);
  diagnosis.candidates = {Candidate("Stribeck", false)};
  diagnosis.candidates[0].values = {Value("/Effects/Stribeck/BreakawayTorque", 0.5, identify::BoundState::kAtUpper),
                                    Value("/Effects/Stribeck/Velocity", 2.5, identify::BoundState::kBeyond),
                                    Value("/AngularMotor/FMaxFactor", 1.0, identify::BoundState::kInside)};
  identify::Rig rig;
  rig.kind = "pendulum";
  const identify::DiagnosisOptions options;
  const std::string md = ReportMarkdown(diagnosis, rig, options);
  EXPECT_NE(md.find("BreakawayTorque 0.5 N·m (at the top of its range);"), std::string::npos) << md;
  EXPECT_NE(md.find("Velocity 2.5 N·m (beyond the catalogue's range);"), std::string::npos) << md;
  EXPECT_NE(md.find("FMaxFactor 1 N·m;"), std::string::npos) << md;
  const nlohmann::json json = ReportJson(diagnosis, rig, options);
  const nlohmann::json& values = json.at("candidates").at(0).at("parameters");
  EXPECT_EQ(values.at(0).at("bound"), "upper");
  EXPECT_EQ(values.at(1).at("bound"), "beyond");
  EXPECT_TRUE(values.at(2).at("bound").is_null());
}

}  // namespace
}  // namespace orcs::gap
