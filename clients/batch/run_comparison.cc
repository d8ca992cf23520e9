#include "clients/batch/run_comparison.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unordered_map>

#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/text.h"

namespace orcs::batch {
namespace {

namespace fs = std::filesystem;

struct Run {
  std::vector<std::string> order;                         ///< job ids in the file's order
  std::unordered_map<std::string, JobFigures> jobs;        ///< by id
  std::unordered_map<std::string, std::string> key_of;     ///< id → what the job ran (MatchKey), "" when unknown
};

// What a job ran, whatever its id: its seed, which genome and which sweep point — ids are zero-padded by the batch's
// size ("job-03" of 8 jobs, "job-003" of 100), so the same seeds in two runs of different sizes share no id.
// "" when the line has no seed (results of another program).
std::string MatchKey(const nlohmann::json& line) {
  if (!line.contains("seed") || !line["seed"].is_number_integer()) return "";
  std::string key = "seed " + line["seed"].dump();
  for (const char* field : {"genome_index", "params"}) {
    if (line.contains(field)) key += std::string(" ") + field + " " + line[field].dump();
  }
  return key;
}

JobFigures FiguresOf(const nlohmann::json& line, const std::string& file, int number,
                     std::vector<std::string>& term_names) {
  JobFigures figures;
  const auto fail = [&](const std::string& what) { throw InputError(file, number, what); };
  if (!line.contains("status") || !line["status"].is_string()) fail("\"status\": missing or not text");
  figures.status = line["status"].get<std::string>();
  if (line.contains("fitness") && line["fitness"].is_number()) figures.fitness = line["fitness"].get<double>();
  if (line.contains("terms")) {
    if (!line["terms"].is_object()) fail("\"terms\": not an object");
    for (auto term = line["terms"].begin(); term != line["terms"].end(); ++term) {
      if (!term->is_number()) fail("\"terms\"." + term.key() + ": not a number");
      figures.terms[term.key()] = term->get<double>();
      if (std::find(term_names.begin(), term_names.end(), term.key()) == term_names.end()) {
        term_names.push_back(term.key());
      }
    }
  }
  return figures;
}

Run ReadRun(const std::string& file, std::vector<std::string>& term_names) {
  std::ifstream in(file);
  if (!in) throw InputError(file, 0, "cannot be read");
  Run run;
  std::string text;
  for (int number = 1; std::getline(in, text); ++number) {
    if (text.empty()) continue;
    nlohmann::json line;
    try {
      line = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception&) {
      throw InputError(file, number, "not a JSON line (a results.jsonl line, docs/batch.md)");
    }
    if (!line.is_object() || !line.contains("id") || !line["id"].is_string()) {
      throw InputError(file, number, "\"id\": missing or not text");
    }
    const std::string id = line["id"].get<std::string>();
    if (run.jobs.count(id) != 0) throw InputError(file, number, "job " + text::Quote(id) + " appears twice");
    run.jobs.emplace(id, FiguresOf(line, file, number, term_names));
    run.key_of.emplace(id, MatchKey(line));
    run.order.push_back(id);
  }
  return run;
}

bool Differ(std::optional<double> a, std::optional<double> b, double tolerance) {
  if (a.has_value() != b.has_value()) return true;
  if (!a) return false;
  return tolerance == 0 ? *a != *b : std::abs(*a - *b) > tolerance;
}

std::optional<double> Term(const JobFigures& figures, const std::string& name) {
  const auto found = figures.terms.find(name);
  return found == figures.terms.end() ? std::nullopt : std::optional<double>(found->second);
}

// A CSV field: quoted when it holds a comma, a quote or a line break (job ids are free text).
std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string Number(std::optional<double> value) { return value ? text::FormatDouble(*value) : "—"; }

// "0.5 → 0.75 (+0.25)".
std::string Change(std::optional<double> a, std::optional<double> b) {
  std::string text = Number(a) + " → " + Number(b);
  if (a && b) {
    char delta[48];
    std::snprintf(delta, sizeof delta, " (%+.6g)", *b - *a);
    text += delta;
  }
  return text;
}

}  // namespace

std::string ResultsFileOf(const std::string& path) {
  std::error_code error;
  if (!fs::is_directory(path, error)) return path;
  for (const char* name : {"results.jsonl", "results.jsonl.partial"}) {
    if (fs::is_regular_file(fs::path(path) / name, error)) return (fs::path(path) / name).string();
  }
  throw InputError(path, 0, "no results.jsonl (nor results.jsonl.partial) in this folder");
}

RunComparison CompareRuns(const std::string& a, const std::string& b) {
  RunComparison comparison;
  comparison.a_path = ResultsFileOf(a);
  comparison.b_path = ResultsFileOf(b);
  const Run run_a = ReadRun(comparison.a_path, comparison.terms);
  const Run run_b = ReadRun(comparison.b_path, comparison.terms);
  // By what each job ran where every line says it and no two jobs of a run ran the same; by id otherwise.
  const auto keyed = [](const Run& run, std::unordered_map<std::string, std::string>& ids) {
    for (const std::string& id : run.order) {
      const std::string& key = run.key_of.at(id);
      if (key.empty() || !ids.emplace(key, id).second) return false;
    }
    return true;
  };
  std::unordered_map<std::string, std::string> a_ids, b_ids;  // key → id
  const bool by_key = keyed(run_a, a_ids) && keyed(run_b, b_ids);
  comparison.matched_by = by_key ? "seed and genome" : "job id";
  const auto partner = [&](const Run& run, const std::unordered_map<std::string, std::string>& other_ids,
                           const Run& other, const std::string& id) -> std::string {
    if (!by_key) return other.jobs.count(id) != 0 ? id : "";
    const auto found = other_ids.find(run.key_of.at(id));
    return found == other_ids.end() ? "" : found->second;
  };
  for (const std::string& id : run_a.order) {
    const std::string in_b = partner(run_a, b_ids, run_b, id);
    if (in_b.empty()) {
      comparison.only_a.push_back(id);
    } else {
      comparison.common.push_back({in_b == id ? id : id + " = " + in_b, run_a.jobs.at(id), run_b.jobs.at(in_b)});
    }
  }
  for (const std::string& id : run_b.order) {
    if (partner(run_b, a_ids, run_a, id).empty()) comparison.only_b.push_back(id);
  }
  return comparison;
}

bool Changed(const JobChange& change, double tolerance) {
  if (change.a.status != change.b.status || Differ(change.a.fitness, change.b.fitness, tolerance)) return true;
  std::vector<std::string> names;
  for (const auto& [name, value] : change.a.terms) names.push_back(name);
  for (const auto& [name, value] : change.b.terms) names.push_back(name);
  return std::any_of(names.begin(), names.end(), [&](const std::string& name) {
    return Differ(Term(change.a, name), Term(change.b, name), tolerance);
  });
}

std::string ComparisonText(const RunComparison& comparison, double tolerance) {
  std::ostringstream out;
  std::size_t changed = 0;
  const JobChange* largest = nullptr;
  double largest_delta = 0;
  for (const JobChange& change : comparison.common) {
    if (!Changed(change, tolerance)) continue;
    ++changed;
    if (change.a.fitness && change.b.fitness && std::abs(*change.b.fitness - *change.a.fitness) >= largest_delta) {
      largest_delta = std::abs(*change.b.fitness - *change.a.fitness);
      largest = &change;
    }
  }
  out << "orcs-batch: A = " << comparison.a_path << ", B = " << comparison.b_path << "\n";
  out << "orcs-batch: " << comparison.common.size() << " jobs in both (matched by " << comparison.matched_by << "), "
      << changed << " changed"
      << (tolerance > 0 ? " by more than " + text::FormatDouble(tolerance) : " (any bit)") << "; "
      << comparison.only_a.size() << " only in A, " << comparison.only_b.size() << " only in B\n";
  if (largest != nullptr) {
    out << "orcs-batch: largest fitness change: " << largest->job << " " << Change(largest->a.fitness, largest->b.fitness)
        << "\n";
  }
  for (const JobChange& change : comparison.common) {
    if (!Changed(change, tolerance)) continue;
    out << "  " << change.job << ":";
    if (change.a.status != change.b.status) out << " status " << change.a.status << " → " << change.b.status << ";";
    if (Differ(change.a.fitness, change.b.fitness, tolerance)) {
      out << " fitness " << Change(change.a.fitness, change.b.fitness) << ";";
    }
    for (const std::string& name : comparison.terms) {
      if (Differ(Term(change.a, name), Term(change.b, name), tolerance)) {
        out << " " << name << " " << Change(Term(change.a, name), Term(change.b, name)) << ";";
      }
    }
    out << "\n";
  }
  for (const std::string& id : comparison.only_a) out << "  " << id << ": only in A\n";
  for (const std::string& id : comparison.only_b) out << "  " << id << ": only in B\n";
  return out.str();
}

void WriteComparisonCsv(const std::string& path, const RunComparison& comparison) {
  AtomicFile file(path);
  std::ostream& out = file.stream();
  const auto cell = [](std::optional<double> value) { return value ? text::FormatDouble(*value) : std::string(); };
  const auto delta = [](std::optional<double> a, std::optional<double> b) {
    return a && b ? text::FormatDouble(*b - *a) : std::string();
  };
  out << "job,status_a,status_b,fitness_a,fitness_b,fitness_delta";
  for (const std::string& name : comparison.terms) out << "," << name << "_a," << name << "_b," << name << "_delta";
  out << "\n";
  for (const JobChange& change : comparison.common) {
    out << CsvField(change.job) << "," << change.a.status << "," << change.b.status << "," << cell(change.a.fitness) << ","
        << cell(change.b.fitness) << "," << delta(change.a.fitness, change.b.fitness);
    for (const std::string& name : comparison.terms) {
      const auto a = Term(change.a, name), b = Term(change.b, name);
      out << "," << cell(a) << "," << cell(b) << "," << delta(a, b);
    }
    out << "\n";
  }
  file.Commit();
}

}  // namespace orcs::batch
