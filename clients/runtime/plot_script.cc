#include "clients/runtime/plot_script.h"

#include <spawn.h>
#include <sys/wait.h>

#include <filesystem>

extern char** environ;

namespace orcs::runtime {

bool RunPlotScript(const std::string& script, const std::vector<std::string>& arguments, std::ostream& out) {
  const std::string path = std::string(ORCS_SCRIPTS_DIR) + "/" + script;
  std::string by_hand = path;
  for (const std::string& argument : arguments) by_hand += " " + argument;
  if (!std::filesystem::exists(path) || !std::filesystem::exists("/usr/bin/python3")) {
    out << "orcs-batch: no plot (needs /usr/bin/python3 and " << path << ")\n";
    return false;
  }
  out.flush();  // what was said before the picture comes before what the script says
  std::vector<std::string> words = {"/usr/bin/python3", path};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  pid_t pid = -1;
  int status = -1;
  if (posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0 || waitpid(pid, &status, 0) != pid ||
      !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    out << "orcs-batch: the plot failed; run " << by_hand << "\n";
    return false;
  }
  return true;
}

}  // namespace orcs::runtime
