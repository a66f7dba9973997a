// `untangle simulate`: a cloth simulation corrected by discrete collision detection after every
// step, on a built-in example scene; writes the cloth of each saved frame and a JSON report.
#pragma once

#include <string>

#include "untangle/fix.h"
#include "untangle/simulate.h"

namespace untangle::app {

// The home of simulate's own defaults; the help text shows these values.
struct SimulateOptions {
  std::string scene_file;  // SCENE.json (or `example`)
  std::string example;     // ball | box | spikes
  std::string output_dir;  // created if missing
  int frames = 60;
  bool frames_given = false;  // --frames was given: it wins over the scene file's
  int save_every = 1;  // write every K-th frame (and the last)
  std::string report;  // JSON report, '-' = stdout
  std::string preview;  // DIR for a PNG per saved frame and a contact sheet (empty: none)
  int threads = FixOptions{}.threads;
  bool overwrite = false;  // replace frame files left by an earlier run
  bool quiet = false;
};

// Runs the scene file or the example. An example is first written as DIR/<mesh>.obj (the start);
// per saved frame every cloth file is rewritten from its input as DIR/<name>_<frame>.obj (name:
// the input's file stem), read back and checked. Returns 0 when every written frame is intersection-free, 5
// otherwise. Throws Error(kUsage) for an unknown example, Error(kUnreadableInput) for a bad scene
// file (naming the key), Error(kOutputNotWritten) when a file cannot be written or exists without
// `overwrite`.
int run_simulate(const SimulateOptions& options);

}  // namespace untangle::app
