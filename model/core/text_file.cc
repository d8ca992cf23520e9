#include "model/core/text_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "model/core/error.h"

namespace orcs {

std::string ReadTextFile(const std::string& path) {
  std::error_code error;
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path, error)) throw InputError(path, 0, "cannot read the file");
  std::ostringstream content;
  content << in.rdbuf();
  if (in.bad()) throw InputError(path, 0, "cannot read the file");
  return content.str();
}

}  // namespace orcs
