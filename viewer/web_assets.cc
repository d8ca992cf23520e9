#include "viewer/web_assets.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "model/core/error.h"
#include "model/core/text_file.h"

namespace orcs::viewer {
namespace {

std::string Trim(std::string text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

}  // namespace

std::string ContentTypeOf(std::string_view name) {
  const auto ends = [&](std::string_view suffix) { return name.ends_with(suffix); };
  if (ends(".html")) return "text/html; charset=utf-8";
  if (ends(".js") || ends(".mjs")) return "text/javascript; charset=utf-8";
  if (ends(".css")) return "text/css; charset=utf-8";
  if (ends(".json")) return "application/json";
  if (ends(".png")) return "image/png";
  if (ends(".svg")) return "image/svg+xml";
  return "application/octet-stream";
}

WebAssets::WebAssets(const std::string& web_dir) {
  const std::filesystem::path root(web_dir);
  const std::string list = (root / "files.txt").string();
  std::istringstream lines(ReadTextFile(list));
  std::string line;
  int number = 0;
  while (std::getline(lines, line)) {
    ++number;
    line = Trim(line);
    if (line.empty() || line[0] == '#') continue;
    const std::size_t arrow = line.find("->");
    if (arrow == std::string::npos) throw InputError(list, number, "expected 'SOURCE -> NAME', found " + line);
    const std::string source = Trim(line.substr(0, arrow));
    const std::string name = Trim(line.substr(arrow + 2));
    if (name.empty() || name.find('/') != std::string::npos || name.find("..") != std::string::npos) {
      throw InputError(list, number, "the served name must be a plain file name, found '" + name + "'");
    }
    const std::filesystem::path file = root / source;
    std::error_code error;
    if (!std::filesystem::is_regular_file(file, error)) {
      throw InputError(list, number, file.string() + " is missing (run scripts/setup.sh to install the page's "
                                                     "npm packages)");
    }
    assets_[name] = {ReadTextFile(file.string()), ContentTypeOf(name)};
  }
  if (Find("index.html") == nullptr) throw InputError(list, 0, "lists no index.html");
}

const WebAsset* WebAssets::Find(std::string_view name) const {
  const auto it = assets_.find(name);
  return it == assets_.end() ? nullptr : &it->second;
}

}  // namespace orcs::viewer
