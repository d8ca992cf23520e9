// libFuzzer target: view_request inputs through orcs::fuzz::FeedViewRequest (tests/fuzz/fuzz_entries.h).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "tests/fuzz/fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  orcs::fuzz::FeedViewRequest(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
