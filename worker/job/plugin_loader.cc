#include "worker/job/plugin_loader.h"

#include <dlfcn.h>

#include <algorithm>
#include <filesystem>
#include <vector>

#include "model/core/error.h"

namespace orcs::worker {
namespace {

namespace fs = std::filesystem;

// The plug-in's name: "libexample.so" → "example"; "" for a file that is no plug-in library.
std::string PluginName(const fs::path& file) {
  const std::string name = file.filename().string();
  if (!name.starts_with("lib") || !name.ends_with(".so") || name.size() <= 6) return "";
  return name.substr(3, name.size() - 6);
}

void LoadOne(const fs::path& file, const std::string& name, script::PluginRegistry& registry) {
  void* library = ::dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);  // kept open: its factories run until the end
  if (library == nullptr) throw InputError(file.string(), 0, std::string("cannot be loaded: ") + ::dlerror());
  using Version = int (*)();
  using Register = void (*)(plugin::Registrar&);
  const auto version = reinterpret_cast<Version>(::dlsym(library, "orcs_plugin_api_version"));
  const auto add = reinterpret_cast<Register>(::dlsym(library, "orcs_plugin_register"));
  if (version == nullptr || add == nullptr) {
    throw InputError(file.string(), 0,
                     "is no orcs plug-in: it lacks extern \"C\" orcs_plugin_api_version() or orcs_plugin_register() "
                     "(model/script/plugin_api.h)");
  }
  if (version() != plugin::kApiVersion) {
    throw InputError(file.string(), 0,
                     "was built for plug-in API " + std::to_string(version()) + "; this worker has " +
                         std::to_string(plugin::kApiVersion) + ": rebuild it against this orcs's model/script/plugin_api.h");
  }
  registry.BeginPlugin(name);
  add(registry);
}

}  // namespace

void LoadPlugins(const std::string& folder, script::PluginRegistry& registry) {
  std::error_code error;
  if (!fs::is_directory(folder, error)) throw InputError("--plugins", 0, "expected a folder, found " + folder);
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    if (entry.is_regular_file() && !PluginName(entry.path()).empty()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) LoadOne(file, PluginName(file), registry);
}

}  // namespace orcs::worker
