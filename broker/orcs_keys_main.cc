// orcs-keys: makes CURVE key pairs for the broker, workers and clients (docs/security.md).
//
//   orcs-keys generate DIR NAME...   writes DIR/NAME.key (secret, mode 0600) and DIR/NAME.pub for each NAME
//
// Prints each new public key as "NAME.pub KEY". Never overwrites a key file. Exit 0, or 2 with one line on stderr.
#include <CLI/CLI.hpp>
#include <iostream>
#include <string>
#include <vector>

#include "net/curve_keys.h"

namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 2;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"orcs-keys: makes CURVE key pairs for --curve-keys (docs/security.md)", "orcs-keys"};
  app.require_subcommand(1);
  std::string dir;
  std::vector<std::string> names;
  CLI::App* generate = app.add_subcommand("generate", "write DIR/NAME.key (secret, mode 0600) and DIR/NAME.pub");
  generate->add_option("dir", dir, "the folder (made, mode 0700, when missing)")->required();
  generate->add_option("names", names, "key names: broker, worker, client, or any name for allowed_*/ files")
      ->required();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& error) {
    if (error.get_exit_code() == 0) return app.exit(error);  // --help
    std::cerr << "orcs-keys: " << error.what() << " (see orcs-keys --help)\n";
    return kExitBadInput;
  }
  try {
    for (const std::string& name : names) {
      const orcs::net::CurveKeyPair pair = orcs::net::GenerateCurveKeyPair();
      orcs::net::WriteCurveKeyPair(dir, name, pair);
      std::cout << name << ".pub " << pair.public_key << "\n";
    }
  } catch (const orcs::net::CurveKeyError& error) {
    std::cerr << "orcs-keys: " << error.what() << "\n";
    return kExitBadInput;
  }
  return kExitOk;
}
