// `untangle simulate` (simulate.h): the example scenes, the frame files, the report.
#include "simulate.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenes/random_tangles.h"
#include "scenes/scenes.h"
#include "untangle/error.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"
#include "untangle/report.h"
#include "untangle/write_meshes.h"

namespace untangle::app {
namespace {

namespace fs = std::filesystem;

// The examples: a 21 x 21 sheet (1.6 a side, slightly tilted) dropped from 0.2 above a ball of
// radius 0.5, onto a closed box, or a 25 x 25 sheet onto 4 x 4 cone spikes; metres, y up.
SimulationScene example_scene(const std::string& name) {
  SimulationScene scene;
  if (name == "spikes") {
    scene.meshes.push_back(scenes::grid_sheet(25, 25, {-1.0, 0.45, -1.0}, {2.0, 0.0, 0.017},
                                              {0.013, 0.0, 2.0}, "sheet"));
    Mesh spikes = scenes::cone_spikes({0.0, 0.0, 0.0}, 1.6, 4, 0.4, "spikes");
    for (Vec3& p : spikes.positions) p = Vec3{p[0], p[2], -p[1]};  // tips up (+y)
    scene.meshes.push_back(std::move(spikes));
  } else {
    scene.meshes.push_back(scenes::grid_sheet(21, 21, {-0.8, 0.7, -0.8}, {1.6, 0.013, 0.0},
                                              {0.0, -0.011, 1.6}, "sheet"));
    if (name == "ball")
      scene.meshes.push_back(scenes::uv_sphere({0.01, 0.0, -0.02}, 0.5, 32, 16, "ball"));
    else if (name == "box")
      scene.meshes.push_back(scenes::box_surface({0.0, 0.0, 0.0}, {1.5, 0.5, 1.5}, 8, "box"));
    else
      throw Error(ExitCode::kUsage, "", "unknown example '" + name + "' (ball, box or spikes)");
  }
  scene.meshes.back().role = Role::kObstacle;
  return scene;
}

std::string frame_path(const fs::path& dir, const Mesh& mesh, int frame) {
  char digits[16];
  std::snprintf(digits, sizeof digits, "%04d", frame);
  return (dir / (mesh.name + "_" + digits + ".obj")).string();
}

}  // namespace

int run_simulate(const SimulateOptions& o) {
  SimulationScene scene = example_scene(o.example);
  scene.options.fix.threads = o.threads;
  const fs::path dir = o.output_dir;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw Error(ExitCode::kOutputNotWritten, o.output_dir, "cannot create the output folder");
  // Every file the run will write, checked before any work.
  std::vector<std::string> planned;
  for (const Mesh& mesh : scene.meshes) planned.push_back((dir / (mesh.name + ".obj")).string());
  for (int f = 1; f <= o.frames; ++f)
    if (f % o.save_every == 0 || f == o.frames)
      for (const Mesh& mesh : scene.meshes)
        if (mesh.role == Role::kMovable) planned.push_back(frame_path(dir, mesh, f));
  if (!o.overwrite)
    for (const std::string& path : planned)
      if (fs::exists(path))
        throw Error(ExitCode::kOutputNotWritten, path, "exists (use --overwrite to replace it)");
  if (!o.report.empty() && o.report != "-" && fs::exists(o.report) && !o.overwrite)
    throw Error(ExitCode::kOutputNotWritten, o.report, "exists (use --overwrite to replace it)");

  // The start, as written: the frames are rewritten from these files (only `v` lines change).
  std::vector<std::string> start_files;
  for (const Mesh& mesh : scene.meshes) {
    start_files.push_back((dir / (mesh.name + ".obj")).string());
    scenes::write_obj(mesh, start_files.back());
  }
  std::vector<Mesh> obstacles;
  for (const Mesh& mesh : scene.meshes)
    if (mesh.role == Role::kObstacle) obstacles.push_back(mesh);

  nlohmann::ordered_json report;
  report["schema_version"] = 1;
  report["command"] = "simulate";
  report["untangle_version"] = UNTANGLE_VERSION;
  report["example"] = o.example;
  const ClothOptions& c = scene.options;
  report["options"] = {{"frames", o.frames},          {"time_step", c.time_step},
                       {"substeps", c.substeps},      {"solver_iterations", c.solver_iterations},
                       {"stretch", c.stretch},        {"bend", c.bend},
                       {"damping", c.damping},        {"friction", c.friction},
                       {"clearance", c.fix.clearance}};
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  Simulation sim(std::move(scene));
  const bool progress = !o.quiet && isatty(STDERR_FILENO);
  std::size_t bad_frames = 0;
  double integrate_ms = 0.0, correct_ms = 0.0;
  for (int f = 1; f <= o.frames; ++f) {
    const FrameRecord r = sim.advance();
    integrate_ms += r.integrate_ms;
    correct_ms += r.correct_ms;
    nlohmann::ordered_json row = {{"frame", r.frame},
                                  {"crossings_before", r.crossings_before},
                                  {"crossings_after", r.crossings_after},
                                  {"correction_iterations", r.correction_iterations},
                                  {"uncorrected_steps", r.uncorrected_steps},
                                  {"kinetic_energy", r.kinetic_energy},
                                  {"max_stretch", r.max_stretch}};
    if (f % o.save_every == 0 || f == o.frames) {
      // Written, then read back with the obstacles: the written file is the truth.
      std::vector<Mesh> written = obstacles;
      for (std::size_t m = 0; m < sim.meshes().size(); ++m) {
        const Mesh& mesh = sim.meshes()[m];
        if (mesh.role != Role::kMovable) continue;
        const std::string path = frame_path(dir, mesh, f);
        write_meshes(start_files[m], path, {&mesh});
        for (Mesh& back : read_meshes(path, Role::kMovable)) written.push_back(std::move(back));
      }
      DetectOptions detect;
      detect.threads = o.threads;
      detect.skip_obstacle_pairs = true;
      const std::size_t crossings = find_intersections(written, detect).counts.crossings;
      row["written_crossings"] = crossings;
      if (crossings > 0) ++bad_frames;
    }
    row["timing_ms"] = {{"integrate", r.integrate_ms}, {"correct", r.correct_ms}};
    frames.push_back(row);
    if (progress) std::fprintf(stderr, "\rframe %d of %d", f, o.frames);
  }
  if (progress) std::fprintf(stderr, "\n");
  report["frames"] = frames;
  report["status"] = bad_frames == 0 ? "clean" : "unresolved";
  report["frames_with_crossings"] = bad_frames;
  report["timing_ms"] = {{"integrate", integrate_ms}, {"correct", correct_ms}};
  if (o.report == "-") {
    std::printf("%s\n", report.dump(2).c_str());
  } else {
    if (!o.report.empty()) write_text_file_atomically(o.report, report.dump(2) + "\n");
    if (!o.quiet)
      std::printf("simulated %d frames of '%s': %s (%zu saved frames with crossings); wrote %s\n",
                  o.frames, o.example.c_str(), bad_frames == 0 ? "every frame clean" : "unresolved",
                  bad_frames, o.output_dir.c_str());
  }
  return static_cast<int>(bad_frames == 0 ? ExitCode::kOk : ExitCode::kIntersecting);
}

}  // namespace untangle::app
