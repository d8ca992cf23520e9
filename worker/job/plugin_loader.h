// orcs-worker --plugins DIR (docs/extending.md, "Plug-ins"): loads every lib*.so of a folder into a registry of
// plug-in components, once, before the worker takes its first job — a library that cannot be loaded, lacks the
// entry points, or was built for another plug-in API stops the worker at its start with one line naming the file.
#pragma once

#include <string>

#include "model/script/plugin_registry.h"

namespace orcs::worker {

/// Loads DIR's lib*.so files (sorted by name) into `registry`; each library's components are "<name>/<component>"
/// with <name> its file name without "lib" and ".so". The libraries stay loaded for the life of the process. Throws
/// InputError naming the folder or the file.
void LoadPlugins(const std::string& folder, script::PluginRegistry& registry);

}  // namespace orcs::worker
