#include "clients/evolve/evolution_report.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "model/core/atomic_file.h"
#include "model/core/text.h"

namespace orcs::evolve {
namespace {

std::string Field(double value) { return std::isfinite(value) ? text::FormatDouble(value) : ""; }

std::string Short(double value) {
  if (!std::isfinite(value)) return "-";
  std::ostringstream text;
  text << std::setprecision(4) << value;
  return text.str();
}

}  // namespace

void WriteFitnessCsv(const std::string& folder, const std::vector<GenerationRecord>& history) {
  AtomicFile file((std::filesystem::path(folder) / "fitness.csv").string());
  std::ostream& out = file.stream();
  out << "generation,evaluations,failed,best,mean,median,worst,best_so_far,seconds\n";
  for (const GenerationRecord& r : history) {
    out << r.generation << ',' << r.evaluations << ',' << r.failed << ',' << Field(r.best) << ',' << Field(r.mean)
        << ',' << Field(r.median) << ',' << Field(r.worst) << ',' << Field(r.best_so_far) << ',' << Field(r.seconds)
        << '\n';
  }
  file.Commit();
}

void WriteBestGenome(const std::string& folder, const Champion& champion) {
  if (champion.genome.empty()) return;
  AtomicFile file((std::filesystem::path(folder) / "best_genome.json").string());
  file.stream() << nlohmann::json(champion.genome).dump() << "\n";
  file.Commit();
}

std::string GenerationLine(const GenerationRecord& record, int generations) {
  std::ostringstream line;
  line << "generation " << record.generation << "/" << generations << ": best " << Short(record.best) << ", mean "
       << Short(record.mean) << " (" << record.evaluations << " jobs, " << record.failed << " failed, " << std::fixed
       << std::setprecision(1) << record.seconds << " s); best so far " << Short(record.best_so_far);
  return line.str();
}

}  // namespace orcs::evolve
