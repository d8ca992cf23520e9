// The page's files: exactly those viewer/web/files.txt names ("SOURCE -> NAME" per line, SOURCE relative to the
// web folder), read into memory at start-up. Requests name a file by NAME only, so nothing else can be served.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <string_view>

namespace orcs::viewer {

struct WebAsset {
  std::string content;       ///< the file's bytes
  std::string content_type;  ///< from the extension
};

class WebAssets {
 public:
  /// Reads `web_dir`/files.txt and every file it lists. Throws InputError naming files.txt and its line when a
  /// line is malformed or a file is missing — usually `scripts/setup.sh` (npm packages) was not run.
  explicit WebAssets(const std::string& web_dir);

  /// The asset served as `name` ("index.html", "three.module.js"), or nullptr.
  const WebAsset* Find(std::string_view name) const;

 private:
  std::map<std::string, WebAsset, std::less<>> assets_;
};

/// The content type of a file name by its extension.
std::string ContentTypeOf(std::string_view name);

}  // namespace orcs::viewer
