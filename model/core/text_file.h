// Reading a whole input file, with the project's error convention.
#pragma once

#include <string>

namespace orcs {

/// The whole content of `path`. Throws InputError "path: cannot read the file" when it does not exist, is a
/// directory or cannot be read.
std::string ReadTextFile(const std::string& path);

}  // namespace orcs
