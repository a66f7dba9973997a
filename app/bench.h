// `untangle bench`: times the repair pipeline on a built-in suite of generated scenes and on
// garment/body pairs found in a data folder; prints one table (or JSON), writes speed-vs-error
// plots. Lives in the CLI: the library never prints.
#pragma once

#include <string>

#include "untangle/fix.h"

namespace untangle::app {

// The home of bench's own defaults; the help text shows these values.
struct BenchOptions {
  int repeat = 3;                // runs per scene and method (best and median)
  std::string method = "both";   // region | paper | both
  std::string plot_dir;          // per scene <name>.csv and <name>.svg when set
  std::string data_dir;          // garments/*.obj against bodies/<prefix>_generic.obj
  bool json = false;             // JSON on stdout instead of the tables
  bool quick = false;            // the small suite (for tests)
  int threads = FixOptions{}.threads;
};

// Runs the benchmark and prints its result. Returns the exit code: 0 when it ran (unresolved
// scenes are data, not failure). Throws Error(kUnreadableInput) for a data folder without
// garment/body pairs, Error(kOutputNotWritten) when a plot cannot be written.
int run_bench(const BenchOptions& options);

}  // namespace untangle::app
