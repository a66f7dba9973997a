// libFuzzer target: the loader (read_meshes) on every format, then find_intersections on what
// loads. The first byte of an input picks the file extension, the rest is the file (see
// fuzz_entries.h). Build with the `fuzz` CMake preset; docs/FUZZING.md has the commands.
#include <cstddef>
#include <cstdint>

#include "fuzz_entries.h"

// Debian's assimp 5.2 leaks what an importer allocated when it throws on a corrupt file; those
// leaks are assimp's (scripts/test.sh suppresses them the same way), leaks of untangle's own code
// are still reported. Built in, so that a plain `untangle_fuzz_load CORPUS` works without
// LSAN_OPTIONS.
extern "C" const char* __lsan_default_suppressions() { return "leak:libassimp.so\n"; }
// One suppression report per input would drown libFuzzer's own output.
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return untangle::fuzz::fuzz_load_one(data, size);
}
