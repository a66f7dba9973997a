// `untangle simulate`: a cloth simulation corrected by discrete collision detection after every
// step, on a built-in example scene; writes the cloth of each saved frame and a JSON report.
#pragma once

#include <string>

#include "untangle/fix.h"
#include "untangle/simulate.h"

namespace untangle::app {

// The home of simulate's own defaults; the help text shows these values.
struct SimulateOptions {
  std::string example;     // ball | box | spikes
  std::string output_dir;  // created if missing
  int frames = 60;
  int save_every = 1;  // write every K-th frame (and the last)
  std::string report;  // JSON report, '-' = stdout
  int threads = FixOptions{}.threads;
  bool overwrite = false;  // replace frame files left by an earlier run
  bool quiet = false;
};

// Runs the example, writes DIR/<mesh>.obj (the start) and DIR/<mesh>_<frame>.obj per saved frame,
// each read back and checked. Returns 0 when every written frame is intersection-free, 5
// otherwise. Throws Error(kUsage) for an unknown example, Error(kOutputNotWritten) when a file
// cannot be written or exists without `overwrite`.
int run_simulate(const SimulateOptions& options);

}  // namespace untangle::app
