// A console reporter that also keeps each benchmark's steps/s (items_per_second: the mean when there are
// repetitions, else the average of the single runs), so that a benchmark program can print its ratios after the
// run (peers compared within one run: absolute times on shared machines move by 30 %).
#pragma once

#include <benchmark/benchmark.h>

#include <map>
#include <string>
#include <vector>

namespace orcs::bench {

class RateReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      if (run.error_occurred) continue;
      const bool mean = run.run_type == Run::RT_Aggregate && run.aggregate_name == "mean";
      if (run.run_type == Run::RT_Aggregate && !mean) continue;
      const auto rate = run.counters.find("items_per_second");
      if (rate == run.counters.end()) continue;
      Rate& entry = rates_[run.run_name.str()];
      if (mean) {
        entry = {rate->second.value, 1, true};
      } else if (!entry.mean) {  // average single runs until a mean arrives
        entry.per_second += (rate->second.value - entry.per_second) / ++entry.runs;
      }
    }
  }

  /// Items per second of the benchmark `name` (its run name, e.g. "BM_Stand/1"), 0 if it did not run.
  double Get(const std::string& name) const {
    const auto it = rates_.find(name);
    return it == rates_.end() ? 0.0 : it->second.per_second;
  }

 private:
  struct Rate {
    double per_second = 0.0;
    int runs = 0;
    bool mean = false;
  };
  std::map<std::string, Rate> rates_;
};

}  // namespace orcs::bench
