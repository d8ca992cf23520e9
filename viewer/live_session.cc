#include "viewer/live_session.h"

#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <future>
#include <iostream>

#include "model/core/error.h"
#include "model/core/text.h"
#include "model/core/value_file.h"
#include "model/scene/world_setup.h"
#include "proto/secure_random.h"
#include "worker/osp/protocol_values.h"

namespace orcs::viewer {
namespace {

using Clock = std::chrono::steady_clock;

constexpr auto kFastSlice = std::chrono::milliseconds(15);  // as fast as possible: steps between publications
constexpr auto kLoggerCheck = std::chrono::milliseconds(200);  // paused with a log open: how often its bounds are read

Clock::duration Seconds(double seconds) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

std::string Mebibytes(std::size_t bytes) {
  const double mib = static_cast<double>(bytes) / (1 << 20);
  return text::FormatDouble(mib) + " MiB";
}

// 128 bits from the OS, as hex: the control token.
std::string NewToken() { return proto::SecureRandomHex(16); }

}  // namespace

bool IsSafeFileName(const std::string& file, const char* extension) {
  if (file.empty() || file.size() > 64 || !file.ends_with(extension) || file.find("..") != std::string::npos) {
    return false;
  }
  return std::all_of(file.begin(), file.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-';
  });
}

// --osp: the posted commands, served in the gateway's thread when the eventfd says there are some.
class LiveSession::CommandService : public osp::DatagramService {
 public:
  CommandService(int fd, std::function<void()> run) : fd_(fd), run_(std::move(run)) {}
  int fd() const override { return fd_; }
  void OnReadable() override { run_(); }

 private:
  int fd_;
  std::function<void()> run_;
};

LiveSession::LiveSession(const LiveOptions& options) : options_(options) {
  // The original's port values, so that a value file can set them as it could there (orcs-osp does the same).
  if (options.osp.enabled) osp::AddProtocolValues(simulation_.repository());
  const IgnoredValues ignored = scene::SetUpWorld(simulation_, options.environment, options.initial_value_files,
                                                  options.value_files, options.strict ? UnknownPaths::kRefuse : UnknownPaths::kIgnore);
  if (!ignored.empty()) std::cerr << "orcs-view: " << ignored.Warning() << "\n";
  simulation_.Reset(options.seed);
  LayOut();
  running_ = options.start_running;
  run_start_wall_ = Clock::now();
  real_since_ = run_start_wall_;
  if (options.osp.enabled) {
    StartOsp();
    return;
  }
  Publish();
  thread_ = std::jthread([this](std::stop_token stop) { Loop(stop); });
}

// The gateway binds its sockets here, so that a port in use is an InputError from the constructor; then its
// thread steps the simulation as the clients ask, and runs the pages' commands between datagrams.
void LiveSession::StartOsp() {
  running_ = false;
  const LiveOspOptions& o = options_.osp;
  if (!o.record.empty()) {
    recorder_ = std::make_unique<osp::EpisodeRecorder>(
        simulation_, osp::EpisodeRecorderOptions{.folder = o.record,
                                                 .environment = options_.environment,
                                                 .log = [](std::string_view line) {
                                                   std::cerr << "orcs-view: " << line << std::endl;
                                                 }});
  }
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) throw std::runtime_error("LiveSession: eventfd failed");
  command_service_ = std::make_unique<CommandService>(wake_fd_, [this] { OnOspCommands(); });
  osp::OspGatewayOptions gateway;
  gateway.port = o.port;
  gateway.odcp_port = o.odcp_port;
  gateway.bind_address = o.bind_address;
  gateway.client_timeout_seconds = o.client_timeout_seconds;
  gateway.log = [](std::string_view line) { std::cerr << "orcs-view: OSP: " << line << std::endl; };
  gateway.after_step = [this] { OnOspStep(); };
  gateway.after_reset = [this] { OnOspReset(); };
  gateway_ = std::make_unique<osp::OspGateway>(simulation_, std::move(gateway));
  gateway_->AddService(command_service_.get());
  osp_endpoint_ = gateway_->server().endpoint().ToString();
  Publish();
  thread_ = std::jthread([this] { gateway_->Run(); });  // stopped by gateway_->Stop()
}

std::string LiveSession::Title() const {
  const std::string world = options_.environment.empty()
                                ? "one A-Series"
                                : std::filesystem::path(options_.environment).filename().string();
  return "live: " + world + (gateway_ ? " · driven over OSP at " + osp_endpoint_ : "");
}

std::vector<std::string> LiveSession::OspEndpointLines() const {
  return gateway_ ? gateway_->EndpointLines("orcs-view") : std::vector<std::string>{};
}

void LiveSession::OnOspCommands() {
  std::uint64_t posted = 0;
  [[maybe_unused]] const ssize_t read_bytes = read(wake_fd_, &posted, sizeof posted);  // resets the eventfd
  std::unique_lock lock(command_mutex_);
  RunCommands(lock);
  lock.unlock();
  if (logger_) CheckLogger();
}

void LiveSession::OnOspStep() {
  if (logger_) {
    logger_->Sample(simulation_.time());
    CheckLogger();
  }
  if (recorder_) recorder_->Sample();
  Publish();
}

void LiveSession::OnOspReset() {
  if (simulation_.shared_model() != laid_out_) LayOut();
  if (recorder_) recorder_->NextEpisode();
  {
    std::lock_guard lock(command_mutex_);
    real_since_ = Clock::now();
  }
  Publish();
}

LiveSession::~LiveSession() {
  thread_.request_stop();  // wakes Loop()'s waits
  if (gateway_) gateway_->Stop();
  thread_.join();  // before the log, the recorder and the simulation go
  if (logger_) logger_->Finish();
  recorder_.reset();  // writes the last episode, before the gateway and the simulation go
  if (wake_fd_ >= 0) close(wake_fd_);
}

template <typename Task>
auto LiveSession::OnSimulationThread(Task task) -> decltype(task()) {
  auto job = std::make_shared<std::packaged_task<decltype(task())()>>(std::move(task));
  std::future<decltype(task())> result = job->get_future();
  {
    std::lock_guard lock(command_mutex_);
    commands_.push_back([job] { (*job)(); });
  }
  command_posted_.notify_all();
  if (wake_fd_ >= 0) {  // --osp: the gateway's poll runs the commands
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t written = write(wake_fd_, &one, sizeof one);
  }
  return result.get();
}

// The stepping thread: carries out commands, runs while running_ (paced to the wall clock in real time), does
// single steps on request, and publishes a frame after each slice.
void LiveSession::Loop(std::stop_token stop) {
  std::unique_lock lock(command_mutex_);
  while (!stop.stop_requested()) {
    RunCommands(lock);
    if (stop.stop_requested()) break;
    if (logger_) {
      lock.unlock();
      CheckLogger();
      lock.lock();
    }
    const bool ok = simulation_.status() == scene::SimulationStatus::kOk;
    if (pending_steps_ > 0) {
      --pending_steps_;
      lock.unlock();
      StepOnce();
      Publish();
      lock.lock();
      continue;
    }
    if (!running_ || !ok) {
      const auto woken = [this] { return !commands_.empty() || pending_steps_ > 0 || running_; };
      if (logger_) {
        command_posted_.wait_for(lock, stop, kLoggerCheck, woken);  // a paused log still ends when control lapses
      } else {
        command_posted_.wait(lock, stop, woken);
      }
      if (!running_ || simulation_.status() != scene::SimulationStatus::kOk) continue;
    }
    if (realtime_) {
      // Step when the wall clock has caught up with the next step's simulated time.
      const double ahead = simulation_.time() + simulation_.StepDuration() - run_start_time_;
      const Clock::time_point due =
          run_start_wall_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(ahead));
      if (Clock::now() < due) {
        command_posted_.wait_until(lock, stop, due, [this] { return !commands_.empty() || !running_; });
        continue;
      }
      lock.unlock();
      StepOnce();
    } else {
      lock.unlock();
      const Clock::time_point until = Clock::now() + kFastSlice;
      while (Clock::now() < until && simulation_.status() == scene::SimulationStatus::kOk && running_) StepOnce();
    }
    Publish();
    lock.lock();
  }
}

// Carries out the posted commands, without the command lock (a command may post nothing, but takes time).
void LiveSession::RunCommands(std::unique_lock<std::mutex>& lock) {
  while (!commands_.empty()) {
    std::vector<std::function<void()>> commands;
    commands.swap(commands_);
    lock.unlock();
    for (std::function<void()>& command : commands) command();
    lock.lock();
  }
}

void LiveSession::StepOnce() {
  try {
    simulation_.Step();
  } catch (const InputError& error) {  // a value set since the last step is out of range
    std::lock_guard lock(command_mutex_);
    running_ = false;
    last_error_ = error.what();
    return;
  }
  if (logger_) logger_->Sample(simulation_.time());
}

// The stepping thread's view of the simulation, for the pages.
void LiveSession::Publish() {
  nlohmann::json state;
  {
    std::lock_guard lock(command_mutex_);
    // Driven over OSP, the clients pace it: the real time is all of it since the reset.
    const bool clock_runs = running_ || gateway_ != nullptr;
    const double running_for = clock_runs ? std::chrono::duration<double>(Clock::now() - real_since_).count() : 0.0;
    state = {{"running", running_}, {"realtime", realtime_}, {"real_time", real_seconds_before_ + running_for}};
  }
  state["osp"] = gateway_ ? nlohmann::json(osp_endpoint_) : nlohmann::json(nullptr);
  state["time"] = simulation_.time();
  state["step"] = simulation_.steps();
  state["status"] = scene::SimulationStatusName(simulation_.status());
  state["message"] = !last_error_.empty() ? last_error_ : simulation_.message();
  state["logging"] = logger_ ? nlohmann::json(logger_file_) : nlohmann::json(nullptr);
  state["logger"] = {
      {"file", logger_ ? nlohmann::json(logger_file_) : nlohmann::json(nullptr)},
      {"bytes", logger_ ? logger_->bytes() : 0},
      {"seconds", logger_ ? std::chrono::duration<double>(Clock::now() - logger_start_).count() : 0.0},
      {"max_bytes", options_.log_max_bytes},
      {"max_seconds", options_.log_max_seconds},
      {"stopped", logger_stopped_}};
  std::lock_guard lock(frame_mutex_);
  frame_.step = simulation_.steps();
  frame_.time = simulation_.time();
  ++frame_.serial;
  layout_->ReadValues(frame_.values.data());
  layout_->ReadContacts(frame_.contacts);
  state_ = std::move(state);
  frame_published_.notify_all();
}

// The recording layout of the world as compiled now; again after a reset that compiled it anew.
void LiveSession::LayOut() {
  auto layout = std::make_unique<evaluation::RecordingLayout>(
      simulation_,
      evaluation::RecordingSource{"orcs-view --live", options_.environment, "", options_.seed, 0, nullptr});
  std::lock_guard lock(frame_mutex_);
  layout_ = std::move(layout);
  laid_out_ = simulation_.shared_model();
  world_ = layout_->header();
  frame_.values.resize(layout_->channel_count());
  ++frame_.world_revision;
}

nlohmann::json LiveSession::world() {
  std::lock_guard lock(frame_mutex_);
  return world_;
}

LiveFrame LiveSession::FrameAfter(std::int64_t serial, std::chrono::milliseconds wait) {
  std::unique_lock lock(frame_mutex_);
  frame_published_.wait_for(lock, wait, [&] { return frame_.serial > serial; });
  return frame_;
}

nlohmann::json LiveSession::State() {
  std::lock_guard lock(frame_mutex_);
  return state_;
}

std::string LiveSession::Claim() {
  std::lock_guard lock(token_mutex_);
  if (!token_.empty() && Clock::now() - token_seen_ < Seconds(options_.control_timeout)) return "";
  token_ = NewToken();
  token_seen_ = Clock::now();
  return token_;
}

bool LiveSession::Controls(const std::string& token) {
  std::lock_guard lock(token_mutex_);
  if (token_.empty() || token != token_ || Clock::now() - token_seen_ >= Seconds(options_.control_timeout)) return false;
  token_seen_ = Clock::now();
  return true;
}

bool LiveSession::HeldBy(const std::string& token) {
  std::lock_guard lock(token_mutex_);
  return !token_.empty() && token == token_ && Clock::now() - token_seen_ < Seconds(options_.control_timeout);
}

void LiveSession::Control(const std::string& action, bool realtime, int steps) {
  if (action != "run" && action != "pause" && action != "step" && action != "reset") {
    throw InputError("action", 0, "expected run, pause, step or reset, found " + text::Quote(action));
  }
  if (gateway_) {
    throw InputError("action", 0, "OSP clients step and reset this simulation (orcs-osp -gui, at " + osp_endpoint_ +
                                      "): the page watches, sets values and logs");
  }
  OnSimulationThread([&] {
    {
      std::lock_guard lock(command_mutex_);
      const Clock::time_point now = Clock::now();
      if (running_) real_seconds_before_ += std::chrono::duration<double>(now - real_since_).count();
      if (action == "reset") real_seconds_before_ = 0.0;
      real_since_ = now;
      realtime_ = realtime;
      running_ = action == "run";
      if (action == "step") pending_steps_ += std::clamp(steps, 1, kMaxStepsAtOnce);
    }
    if (action == "run") {
      last_error_.clear();
      run_start_wall_ = Clock::now();
      run_start_time_ = simulation_.time();
    } else if (action == "reset") {
      simulation_.Reset(options_.seed);  // applies the structure values written since (throws if one cannot)
      if (simulation_.shared_model() != laid_out_) LayOut();
      last_error_.clear();
    }
    Publish();
  });
}

nlohmann::json LiveSession::Values(const std::string& pattern, std::size_t limit) {
  return OnSimulationThread([&] {
    const VariableRepository& repository = simulation_.repository();
    nlohmann::json rows = nlohmann::json::array();
    for (int id : repository.Match(pattern)) {
      if (rows.size() >= limit) break;
      const Value& value = repository.value(id);
      rows.push_back({{"id", id},
                      {"path", repository.path(id)},
                      {"type", ValueTypeName(value.type())},
                      {"value", value.ToString()}});
    }
    return rows;
  });
}

std::string LiveSession::SetValue(const std::string& path, const std::string& text) {
  if (const std::size_t at = FindControlCharacter(text); at != std::string::npos) {
    throw InputError(path, 0,
                     "the value holds control character " + ControlCharacterName(text[at]) + " at byte " +
                         std::to_string(at + 1) + ": a value is one line of text");
  }
  return OnSimulationThread([&] {
    simulation_.repository().Set(path, text);
    Publish();  // a paused page sees the change
    return simulation_.repository().Get(path).ToString();
  });
}

void LiveSession::KeepPoseAsStart(const std::string& name) {
  OnSimulationThread([&] { simulation_.KeepPoseAsStart(name); });
}

std::string LiveSession::FilePath(const std::string& file, const char* extension) const {
  if (!IsSafeFileName(file, extension)) {
    throw InputError("file", 0, "expected a name of letters, digits, '_', '.' or '-' ending in " +
                                    std::string(extension) + ", found " + text::Quote(file));
  }
  std::filesystem::create_directories(options_.files_dir);
  const std::filesystem::path path = std::filesystem::path(options_.files_dir) / file;
  // A symbolic link could name any file on the machine: reading through it (load, whose errors quote lines) would
  // serve a file from outside the files folder. Only the folder's own files are used.
  std::error_code error;
  if (std::filesystem::is_symlink(path, error)) {
    throw InputError("file", 0,
                     text::Quote(file) + " is a symbolic link: only files in the files folder itself are used");
  }
  return path.string();
}

void LiveSession::Save(const std::string& file, const std::string& pattern) {
  const std::string path = FilePath(file, ".val");
  OnSimulationThread([&] {
    ValueFile::Save(path, simulation_.repository(),
                    "orcs-view, simulated time " + std::to_string(simulation_.time()) + " s", pattern);
  });
}

void LiveSession::Load(const std::string& file) {
  const std::string path = FilePath(file, ".val");
  OnSimulationThread([&] {
    ValueFile::Apply(path, simulation_.repository());
    Publish();
  });
}

nlohmann::json LiveSession::Files() {
  nlohmann::json files = nlohmann::json::array();
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(options_.files_dir, error)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_symlink(error) && entry.is_regular_file(error) &&
        (IsSafeFileName(name, ".val") || IsSafeFileName(name, ".csv"))) {
      files.push_back(name);
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

void LiveSession::StartLogger(const std::string& pattern, const std::string& file) {
  const std::string path = FilePath(file, ".csv");
  std::string token;
  {
    std::lock_guard lock(token_mutex_);
    token = token_;  // the caller holds control (a Controlled route): the log lives as long as that control
  }
  OnSimulationThread([&] {
    auto logger = std::make_unique<ValueLogger>(simulation_.repository(), std::vector<std::string>{pattern});
    if (logger_) logger_->Finish();
    logger_.reset();
    logger->Open(path, {"orcs-view live log", "environment: " + options_.environment}, options_.log_max_bytes,
                 "it reached its bound of " + Mebibytes(options_.log_max_bytes) + " (orcs-view --log-max-mib)");
    logger->Sample(simulation_.time());
    logger_ = std::move(logger);
    logger_file_ = file;
    logger_token_ = token;
    logger_start_ = Clock::now();
    logger_stopped_.clear();
    Publish();
  });
}

void LiveSession::StopLogger() {
  OnSimulationThread([&] {
    if (logger_) logger_->Finish();
    logger_.reset();
    logger_file_.clear();
    Publish();
  });
}

void LiveSession::CheckLogger() {
  if (!logger_) return;
  if (logger_->truncated()) {
    EndLogger("it reached its bound of " + Mebibytes(options_.log_max_bytes) + " (--log-max-mib)");
  } else if (Clock::now() - logger_start_ >= Seconds(options_.log_max_seconds)) {
    EndLogger("it ran for its bound of " + text::FormatDouble(options_.log_max_seconds) + " s (--log-max-seconds)");
  } else if (!HeldBy(logger_token_)) {
    EndLogger("control lapsed: the page that started it was silent for " +
              text::FormatDouble(options_.control_timeout) + " s or another page took control");
  }
}

void LiveSession::EndLogger(const std::string& why) {
  logger_stopped_ = logger_file_ + " stopped: " + why;
  try {
    logger_->Finish();
  } catch (const InputError& error) {
    logger_stopped_ += "; " + std::string(error.what());
  }
  logger_.reset();
  logger_file_.clear();
  Publish();
}

}  // namespace orcs::viewer
