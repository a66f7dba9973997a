// The one repair pipeline of the CLI: load -> fix -> write -> verify. `untangle fix` prints its
// result; `untangle bench` times it on many scenes. Never prints.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/mesh.h"
#include "untangle/mesh_info.h"
#include "untangle/report.h"
#include "untangle/roles_by_name.h"

namespace untangle::app {

// Options shared by the commands (as parsed by CLI11). Every default is read from the library's
// options struct that holds it (FixOptions), never written here a second time; the help text shows
// these values.
struct CommonOptions {
  std::vector<std::string> inputs;
  std::vector<std::string> obstacles;
  // --obstacle-name / --movable-name: roles by name inside the movable inputs (check, fix).
  std::vector<std::string> obstacle_names;
  std::vector<std::string> movable_names;
  std::string report;
  std::string contours;
  int threads = FixOptions{}.threads;  // check sets DetectOptions{}.threads (main.cpp)
  bool quiet = false;
  bool verbose = false;
  // fix
  std::vector<std::string> outputs;
  std::string output_dir;
  std::vector<std::string> pin_files;
  std::vector<std::string> pin_groups;
  std::string method = to_string(FixOptions{}.method);
  int max_iterations = FixOptions{}.max_iterations;
  double clearance = FixOptions{}.clearance;
  double step = FixOptions{}.step;  // not a fix option (yet), varied by bench
  bool outside_closed = FixOptions{}.outside_closed_obstacles;
  bool relax = FixOptions{}.relax;
  int relax_sweeps = FixOptions{}.relax_sweeps;
  int retries = FixOptions{}.retries;
  bool continuation = FixOptions{}.continuation;
  bool layering = FixOptions{}.layering;
  bool piece_moves = FixOptions{}.piece_moves;
  QualityBounds bounds;
  bool overwrite = false;
  bool allow_loss = false;  // fix --allow-loss: write although the output drops what export_loss names
  std::string preview_png;  // fix --preview: the picture to write (planned with the outputs)
  std::string preview_size;  // fix --preview-size WxH, each panel; empty = RenderOptions' size
};

double ms_since(std::chrono::steady_clock::time_point start);

// Reads the positional inputs (movable) and the obstacles, in that order. `file_of` (optional)
// receives, per movable mesh, the index of its input file.
std::vector<Mesh> load_all(const CommonOptions& o, std::vector<std::size_t>* file_of = nullptr);

// The --obstacle-name and --movable-name patterns of `o`.
NamePatterns name_patterns(const CommonOptions& o);

// What one run of the pipeline produced.
struct PipelineRun {
  std::vector<std::string> outputs;      // one per movable input
  std::vector<Mesh> meshes;              // movable then obstacles, positions as fixed, with the
                                         // roles by name (a split OBJ is two meshes here)
  std::vector<std::vector<Vec3>> input;  // per mesh, the positions as read
  std::vector<MeshInfo> infos;           // of the inputs
  FixOptions options;
  FixResult result;
  std::vector<Mesh> written;  // the written files read back, then the obstacles
  Intersections verified;     // detected on `written`, obstacle pairs left out
  FixTimingsMs timings;    // load, detect, contours, resolve, write, verify, total
};

// Plans and checks the outputs (throws Error(kOutputNotWritten) or Error(kUsage) before any
// work), reads inputs, obstacles and pins, runs fix_meshes, writes the outputs and reads them
// back for the verdict. `progress` is passed to fix_meshes.
PipelineRun run_pipeline(const CommonOptions& o, const FixProgress& progress = {});

}  // namespace untangle::app
