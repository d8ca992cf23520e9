#include "base/run_program.h"

#include <exception>
#include <iostream>

#include "base/input_error.h"

namespace orcs::cli {

int RunProgram(std::string_view program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const InputError& error) {
    std::cerr << program << ": " << error.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& error) {
    std::cerr << program << ": internal error: " << error.what() << "\n";
    return kExitRunFailed;
  }
}

}  // namespace orcs::cli
