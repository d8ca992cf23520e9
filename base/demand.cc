#include "base/demand.h"

#include <cstdio>
#include <cstdlib>

namespace orcs::internal {

void DemandFailed(const char* condition, const char* message, const char* file, int line,
                  const char* function) noexcept {
  // stdio, not iostreams: it may run during static destruction or with a stream in a bad state.
  if (message != nullptr && message[0] != '\0') {
    std::fprintf(stderr, "orcs: internal invariant failed: %s (%s) at %s:%d in %s\n", condition, message, file, line,
                 function);
  } else {
    std::fprintf(stderr, "orcs: internal invariant failed: %s at %s:%d in %s\n", condition, file, line, function);
  }
  std::fflush(stderr);
  std::abort();
}

}  // namespace orcs::internal
