// What `orcs-batch sweep` reports: per grid point the swept values and the fitness (mean over the point's
// repeats that ran ok), as a table on stdout and as DIR/sweep.csv, which scripts/plot_sweep.py plots.
#pragma once

#include <string>
#include <vector>

#include "clients/batch/sweep_grid.h"
#include "clients/runtime/batch_input.h"
#include "orcs/v1/result.pb.h"

namespace orcs::batch {

/// One grid point's outcome.
struct SweepRow {
  runtime::SweepPoint point;        ///< the swept values
  int jobs = 0;            ///< repeats submitted
  int ok = 0;              ///< repeats that ran ok
  double fitness = 0.0;    ///< mean fitness of the ok repeats (NaN when none)
  double min_fitness = 0.0;  ///< lowest fitness of the ok repeats (NaN when none)
  double max_fitness = 0.0;  ///< highest fitness of the ok repeats (NaN when none)
};

/// Collects the results (job ids "point-NNNN-rR" as PlanSweepJobs made them) into one row per point.
std::vector<SweepRow> SweepRows(const std::vector<runtime::SweepPoint>& points, const std::vector<runtime::PlannedJob>& jobs,
                                const std::vector<v1::Result>& results);
/// The same for the jobs of a source (SweepJobSource), made one at a time.
std::vector<SweepRow> SweepRows(const std::vector<runtime::SweepPoint>& points, const runtime::JobSource& jobs,
                                const std::vector<v1::Result>& results);

/// A fixed-width table: one column per axis (its path's last two parts), then fitness, min, max, ok/jobs.
std::string SweepTable(const std::vector<SweepAxis>& axes, const std::vector<SweepRow>& rows);

/// Writes FOLDER/sweep.csv: a header "PATH1,PATH2,...,fitness,min_fitness,max_fitness,ok,jobs", then one line
/// per point; numbers round-trip, categories are written as they are; an empty field where a point has no ok
/// repeat. Throws InputError.
void WriteSweepCsv(const std::string& folder, const std::vector<SweepAxis>& axes, const std::vector<SweepRow>& rows);

}  // namespace orcs::batch
