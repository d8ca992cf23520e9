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

}  // namespace

int RenderClip(const ViewOptions& options) {
  const RenderOptions& r = options.render_options;
  const std::string extension = fs::path(r.out).extension().string();
  const bool still = extension == ".png";
  if (!still && extension != ".gif" && extension != ".mp4" && extension != ".webm") {
    throw InputError("--out", 0, "expected a .png, .gif, .mp4 or .webm file, found '" + r.out + "'");
  }
  ViewCatalog catalog({r.run});
  std::string item;
  for (const ViewItem& candidate : catalog.items()) {
    if (candidate.kind == "recording") {
      item = candidate.id;
      break;
    }
  }
  if (item.empty()) throw InputError(r.run, 0, "holds no recording to draw");
  const double duration = catalog.Recording(item)->times.back();
  const double from = still ? (r.at >= 0 ? r.at : duration / 2) : r.from;
  const double to = still ? from : (r.to >= 0 ? std::min(r.to, duration) : duration);
  const int frames = still ? 1 : static_cast<int>(std::floor((to - from) * r.fps)) + 1;
  if (frames > kMaxFrames) {
    throw InputError("--fps", 0, std::to_string(frames) + " frames asked; at most " + std::to_string(kMaxFrames) +
                                     ": shorten --from/--to or lower --fps");
  }

  char folder_template[] = "/tmp/orcs-render-XXXXXX";
  const char* folder = mkdtemp(folder_template);
  if (folder == nullptr) throw InputError("/tmp", 0, "cannot make a temporary folder");
  RenderSink sink(folder, frames);
  WebAssets assets(options.web_dir);
  ViewServer server(assets, &catalog, nullptr, &sink);
  const int port = server.Bind("127.0.0.1", 0);
  std::thread serving([&server] { server.Serve(); });

  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/?render=1&item=" + item +
                          "&fps=" + std::to_string(r.fps) + "&from=" + std::to_string(from) + "&to=" +
                          std::to_string(to) + "&width=" + std::to_string(r.width) + "&height=" +
                          std::to_string(r.height);
  std::vector<std::string> browser = {r.chromium, "--headless=new", "--use-angle=swiftshader",
                                      "--enable-unsafe-swiftshader", "--hide-scrollbars", "--mute-audio",
                                      "--no-first-run", "--window-size=" + std::to_string(r.width) + "," +
                                      std::to_string(r.height), std::string("--user-data-dir=") + folder + "/profile"};
  if (geteuid() == 0) browser.push_back("--no-sandbox");  // chromium refuses to run as root with its sandbox
  browser.push_back(url);
  const std::string log = std::string(folder) + "/render.log";
  const pid_t chromium = Spawn(browser, log);
  std::cerr << "orcs-view: drawing " << frames << (frames == 1 ? " frame" : " frames") << " of " << r.run << " in "
            << r.chromium << "\n";
  const bool done = chromium > 0 && sink.WaitDone(std::chrono::seconds(60 + 2 * frames));
  if (chromium > 0) StopGroup(chromium);
  server.Stop();
  serving.join();

  int code = cli::kExitOk;
  if (!done || !sink.error().empty() || sink.frames() != frames) {
    std::cerr << "orcs-view: the page drew " << sink.frames() << " of " << frames << " frames"
              << (sink.error().empty() ? (done ? "" : " before the time limit") : ": " + sink.error())
              << Tail(log) << "\n";
    code = cli::kExitRunFailed;
  } else if (still) {
    fs::copy_file(fs::path(folder) / "frame-00000.png", r.out, fs::copy_options::overwrite_existing);
  } else {
    const std::string temporary = r.out + ".tmp" + extension;
    const pid_t encoder = Spawn(EncoderArguments(extension, r.fps, std::string(folder) + "/frame-%05d.png", temporary),
                                log);
    if (encoder < 0 || WaitExit(encoder) != 0) {
      std::cerr << "orcs-view: ffmpeg could not encode " << r.out << Tail(log) << "\n";
      fs::remove(temporary);
      code = cli::kExitRunFailed;
    } else {
      fs::rename(temporary, r.out);
    }
  }
  std::error_code ignored;
  fs::remove_all(folder, ignored);
  if (code == cli::kExitOk) std::cout << "orcs-view: wrote " << r.out << " (" << frames << (frames == 1 ? " frame)\n" : " frames)\n");
  return code;
}

}  // namespace orcs::viewer
