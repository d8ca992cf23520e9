// report.md as orcs-gap writes it (clients/gap/gap_report.h), on a diagnosis put together by hand: what the
// candidate table says about fits the race abandoned.
#include "clients/gap/gap_report.h"

#include <gtest/gtest.h>

#include <string>

namespace orcs::gap {
namespace {

identify::ModelScore Candidate(const std::string& label, bool abandoned, bool unmoved) {
  identify::ModelScore score;
  score.label = label;
  score.score = 1.0;
  score.fit.abandoned = abandoned;
  score.fit.abandoned_unmoved = unmoved;
  score.fit.generations = abandoned ? 10 : 40;
  return score;
}

std::size_t Count(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

TEST(GapReportTest, ACandidateAbandonedBeforeItsSearchMovedIsMarkedAndTheReportSuggestsNoRace) {
  identify::Diagnosis diagnosis;
  diagnosis.base = Candidate("refit", false, false);
  diagnosis.candidates = {Candidate("GearEfficiency", true, true), Candidate("Stribeck", true, false),
                          Candidate("Backlash", false, false)};
  identify::Rig rig;
  rig.kind = "pendulum";
  const identify::DiagnosisOptions options;
  const std::string md = ReportMarkdown(diagnosis, rig, options);
  EXPECT_EQ(Count(md, "| abandoned after 10 generations, before its search moved |"), 1u) << md;
  EXPECT_EQ(Count(md, "| abandoned after 10 generations |"), 1u) << md;
  EXPECT_NE(md.find("1 candidate was abandoned before its search moved"), std::string::npos) << md;
  EXPECT_NE(md.find("`--no-race` fits every candidate to the end"), std::string::npos) << md;

  diagnosis.candidates[1].fit.abandoned_unmoved = true;
  EXPECT_NE(ReportMarkdown(diagnosis, rig, options).find("2 candidates were abandoned before their search moved"),
            std::string::npos);
  diagnosis.candidates[0].fit.abandoned_unmoved = false;
  diagnosis.candidates[1].fit.abandoned_unmoved = false;
  EXPECT_EQ(ReportMarkdown(diagnosis, rig, options).find("before its search moved"), std::string::npos)
      << "no hint when every abandoned search had moved";
}

}  // namespace
}  // namespace orcs::gap
