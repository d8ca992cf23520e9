#include "viewer/clip_renderer.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <thread>
#include <vector>

#include "model/core/error.h"
#include "viewer/render_sink.h"
#include "viewer/view_catalog.h"
#include "viewer/view_server.h"
#include "viewer/web_assets.h"
#include "net/cli_style.h"

namespace orcs::viewer {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxFrames = 3000;  // 2 min at 25 frames/s

// Starts `arguments` with stdout and stderr into `log`; returns the child's pid, or -1.
pid_t Spawn(const std::vector<std::string>& arguments, const std::string& log) {
  std::vector<char*> pointers;
  for (const std::string& argument : arguments) pointers.push_back(const_cast<char*>(argument.c_str()));
  pointers.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0600);
    if (fd >= 0) {
      dup2(fd, STDOUT_FILENO);
      dup2(fd, STDERR_FILENO);
    }
    setpgid(0, 0);  // its own group: the browser's helpers end with it
    execvp(pointers[0], pointers.data());
    _exit(127);
  }
  return pid;
}

int WaitExit(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

void StopGroup(pid_t pid) {
  kill(-pid, SIGTERM);
  kill(pid, SIGTERM);
  WaitExit(pid);
}

// The last lines of a log file, for an error message.
std::string Tail(const std::string& log) {
  std::ifstream in(log);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  std::string tail;
  for (std::size_t i = lines.size() > 3 ? lines.size() - 3 : 0; i < lines.size(); ++i) tail += "\n  " + lines[i];
  return tail;
}

std::vector<std::string> EncoderArguments(const std::string& extension, double fps, const std::string& frames,
                                          const std::string& out) {
  std::vector<std::string> arguments = {"ffmpeg", "-y", "-loglevel", "error", "-framerate", std::to_string(fps),
                                        "-i", frames};
  if (extension == ".gif") {
    arguments.insert(arguments.end(), {"-vf", "split[a][b];[a]palettegen=stats_mode=diff[p];[b][p]paletteuse=dither=bayer",
                                       "-loop", "0", "-f", "gif"});
  } else if (extension == ".mp4") {
    arguments.insert(arguments.end(), {"-c:v", "libx264", "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4"});
  } else {
    arguments.insert(arguments.end(), {"-c:v", "libvpx-vp9", "-b:v", "0", "-crf", "36", "-f", "webm"});
  }
  arguments.push_back(out);
  return arguments;
}

// What a --render call draws: which recording, over which times, how many frames, into which kind of file.
struct ClipPlan {
  std::string item;       ///< the catalog id of the recording drawn
  std::string extension;  ///< ".png", ".gif", ".mp4" or ".webm"
  bool still = false;     ///< one frame, written as PNG
  double from = 0.0;      ///< first frame's simulated time, s
  double to = 0.0;        ///< last frame's simulated time, s
  int frames = 1;         ///< frames drawn
};

// --out's extension, checked before anything is read.
std::string OutputExtension(const RenderOptions& r) {
  const std::string extension = fs::path(r.out).extension().string();
  if (extension != ".png" && extension != ".gif" && extension != ".mp4" && extension != ".webm") {
    throw InputError("--out", 0, "expected a .png, .gif, .mp4 or .webm file, found '" + r.out + "'");
  }
  return extension;
}

ClipPlan PlanClip(const RenderOptions& r, const std::string& extension, ViewCatalog& catalog) {
  ClipPlan plan;
  plan.extension = extension;
  plan.still = extension == ".png";
  for (const ViewItem& candidate : catalog.Items()) {
    if (candidate.kind == "recording") {
      plan.item = candidate.id;
      break;
    }
  }
  if (plan.item.empty()) throw InputError(r.run, 0, "holds no recording to draw");
  const double duration = catalog.Recording(plan.item)->times.back();
  plan.from = plan.still ? (r.at >= 0 ? r.at : duration / 2) : r.from;
  plan.to = plan.still ? plan.from : (r.to >= 0 ? std::min(r.to, duration) : duration);
  plan.frames = plan.still ? 1 : static_cast<int>(std::floor((plan.to - plan.from) * r.fps)) + 1;
  if (plan.frames > kMaxFrames) {
    throw InputError("--fps", 0, std::to_string(plan.frames) + " frames asked; at most " +
                                     std::to_string(kMaxFrames) + ": shorten --from/--to or lower --fps");
  }
  return plan;
}

// Headless chromium on the page's render mode for `plan`, its profile in `folder`.
std::vector<std::string> BrowserArguments(const RenderOptions& r, const ClipPlan& plan, int port,
                                          const std::string& folder) {
  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/?render=1&item=" + plan.item +
                          "&fps=" + std::to_string(r.fps) + "&from=" + std::to_string(plan.from) + "&to=" +
                          std::to_string(plan.to) + "&width=" + std::to_string(r.width) + "&height=" +
                          std::to_string(r.height);
  std::vector<std::string> browser = {r.chromium, "--headless=new", "--use-angle=swiftshader",
                                      "--enable-unsafe-swiftshader", "--hide-scrollbars", "--mute-audio",
                                      "--no-first-run", "--window-size=" + std::to_string(r.width) + "," +
                                      std::to_string(r.height), "--user-data-dir=" + folder + "/profile"};
  if (geteuid() == 0) browser.push_back("--no-sandbox");  // chromium refuses to run as root with its sandbox
  browser.push_back(url);
  return browser;
}

// Serves the catalog on loopback while chromium draws every frame into `sink`; true when the page said done.
bool DrawFrames(const ViewOptions& options, ViewCatalog& catalog, const ClipPlan& plan, const std::string& folder,
                RenderSink& sink) {
  const RenderOptions& r = options.render_options;
  WebAssets assets(options.web_dir);
  ViewServer server(assets, &catalog, nullptr, &sink);
  const int port = server.Bind("127.0.0.1", 0);
  std::thread serving([&server] { server.Serve(); });
  const pid_t chromium = Spawn(BrowserArguments(r, plan, port, folder), folder + "/render.log");
  std::cerr << "orcs-view: drawing " << plan.frames << (plan.frames == 1 ? " frame" : " frames") << " of " << r.run
            << " in " << r.chromium << "\n";
  const bool done = chromium > 0 && sink.WaitDone(std::chrono::seconds(60 + 2 * plan.frames));
  if (chromium > 0) StopGroup(chromium);
  server.Stop();
  serving.join();
  return done;
}

// The drawn frames into r.out: the one PNG copied, or the frames encoded by ffmpeg.
int WriteClip(const RenderOptions& r, const ClipPlan& plan, const std::string& folder) {
  const std::string log = folder + "/render.log";
  if (plan.still) {
    fs::copy_file(fs::path(folder) / "frame-00000.png", r.out, fs::copy_options::overwrite_existing);
    return cli::kExitOk;
  }
  const std::string temporary = r.out + ".tmp" + plan.extension;
  const pid_t encoder = Spawn(EncoderArguments(plan.extension, r.fps, folder + "/frame-%05d.png", temporary), log);
  if (encoder < 0 || WaitExit(encoder) != 0) {
    std::cerr << "orcs-view: ffmpeg could not encode " << r.out << Tail(log) << "\n";
    fs::remove(temporary);
    return cli::kExitRunFailed;
  }
  fs::rename(temporary, r.out);
  return cli::kExitOk;
}

}  // namespace

int RenderClip(const ViewOptions& options) {
  const RenderOptions& r = options.render_options;
  const std::string extension = OutputExtension(r);
  ViewCatalog catalog({r.run});
  const ClipPlan plan = PlanClip(r, extension, catalog);
  char folder_template[] = "/tmp/orcs-render-XXXXXX";
  const char* made = mkdtemp(folder_template);
  if (made == nullptr) throw InputError("/tmp", 0, "cannot make a temporary folder");
  const std::string folder = made;
  RenderSink sink(folder, plan.frames);
  const bool done = DrawFrames(options, catalog, plan, folder, sink);
  int code = cli::kExitRunFailed;
  if (!done || !sink.error().empty() || sink.frames() != plan.frames) {
    std::cerr << "orcs-view: the page drew " << sink.frames() << " of " << plan.frames << " frames"
              << (sink.error().empty() ? (done ? "" : " before the time limit") : ": " + sink.error())
              << Tail(folder + "/render.log") << "\n";
  } else {
    code = WriteClip(r, plan, folder);
  }
  std::error_code ignored;
  fs::remove_all(folder, ignored);
  if (code == cli::kExitOk) {
    std::cout << "orcs-view: wrote " << r.out << " (" << plan.frames << (plan.frames == 1 ? " frame)\n" : " frames)\n");
  }
  return code;
}

}  // namespace orcs::viewer
