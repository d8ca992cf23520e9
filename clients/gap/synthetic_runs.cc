#include "clients/gap/synthetic_runs.h"

#include <filesystem>

#include "model/control/keyframe_record.h"
#include "model/core/atomic_file.h"
#include "model/core/error.h"
#include "model/core/text.h"
#include "model/core/text_file.h"
#include "model/scene/scenario.h"
#include "model/evaluation/evaluation.h"

namespace orcs::gap {

using namespace identify;  // the analysis this command drives (model/identify/)
namespace {

namespace fs = std::filesystem;

nlohmann::json SynthScenario(const Rig& rig, const std::vector<ValueAssignment>& model, const std::string& motion,
                             double duration, bool accelerometers) {
  const std::string record_text = ReadTextFile(motion);
  if (duration <= 0.0) {
    const control::KeyframeRecord record =
        control::ParseKeyframeRecord(record_text, motion, static_cast<int>(rig.motors.size()));
    duration = record.frames.back().time_ms / 1000.0;
  }
  nlohmann::json values = nlohmann::json::object();
  for (const ValueAssignment& assignment : model) values[assignment.path] = assignment.value;
  nlohmann::json scenario = {
      {"name", fs::path(motion).stem().string()},
      {"agent", rig.agent},
      {"duration", duration},
      {"controller", {{"type", "keyframes"}, {"record", {{"file", motion}, {"text", record_text}}}}},
      {"fitness", {{"terms", nlohmann::json::array({{{"type", "energy"}}})}}},
      {"values", values},
      {"log", {"/Sim/" + rig.agent + "/.*/(DesiredAngle|DesiredTorque|JointAngle)"}},
  };
  // Under the servo model the firmware gain is an input of each run (docs/gap_measured_data.md): it is logged.
  if (UsesServo(rig, model)) scenario["log"].push_back("/Servo/FirmwareKp");
  if (accelerometers) scenario["log"].push_back("/Sim/" + rig.agent + "/[^/]+/(AccelAxis1|AccelAxis2)");
  if (!rig.environment_xml.empty()) {
    scenario["environment"] = {{"file", rig.environment_name}, {"xml", rig.environment_xml}};
  }
  return scenario;
}

}  // namespace

std::vector<std::string> WriteSyntheticRuns(const Rig& rig, const std::vector<ValueAssignment>& model,
                                            const SynthOptions& options) {
  std::error_code error;
  fs::create_directories(options.out, error);
  if (error) throw InputError(options.out + ": cannot create the output folder: " + error.message());
  std::vector<std::string> written;
  for (std::size_t k = 0; k < options.motions.size(); ++k) {
    const std::string& motion = options.motions[k];
    evaluation::EvaluationRequest request;
    request.scenario = scene::ParseScenario(SynthScenario(rig, model, motion, options.duration, options.accelerometers), motion);
    request.seed = options.seed + k;
    for (const Override& value : options.hidden) request.overrides.push_back({value.first, value.second, "--set", 0});
    const evaluation::EvaluationOutcome outcome = evaluation::Evaluate(request);
    if (outcome.status != evaluation::EvaluationStatus::kOk) {
      throw InputError(motion + ": the synthetic run failed: " + outcome.message);
    }
    const std::string path = (fs::path(options.out) / (fs::path(motion).stem().string() + ".csv")).string();
    AtomicFile file(path);
    file.stream() << outcome.sets.at(0).log_csv;
    file.Commit();
    written.push_back(path);
  }
  return written;
}

}  // namespace orcs::gap
