// libFuzzer target: detection and contour building on small degenerate scenes described by the
// bytes, and contour building from raw crossing sets (see fuzz_entries.h). Build with the `fuzz`
// CMake preset; docs/FUZZING.md has the commands.
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return untangle::fuzz::fuzz_contours_one(data, size);
}
