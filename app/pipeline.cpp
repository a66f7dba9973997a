// The repair pipeline shared by `untangle fix` and `untangle bench`: load -> fix -> write -> verify.
#include "pipeline.h"

#include <cctype>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "untangle/error.h"
#include "untangle/read_meshes.h"
#include "untangle/write_meshes.h"

#include "output_plan.h"

namespace untangle::app {

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::vector<Mesh> load_all(const CommonOptions& o, std::vector<std::size_t>* file_of) {
  std::vector<Mesh> meshes;
  for (std::size_t k = 0; k < o.inputs.size(); ++k) {
    for (auto& m : read_meshes(o.inputs[k], Role::kMovable)) {
      meshes.push_back(std::move(m));
      if (file_of != nullptr) file_of->push_back(k);
    }
  }
  for (const std::string& path : o.obstacles) {
    for (auto& m : read_meshes(path, Role::kObstacle)) meshes.push_back(std::move(m));
  }
  // What a reader skipped, once per mesh, on stderr (also with --report -: stdout carries data).
  if (!o.quiet)
    for (const Mesh& m : meshes)
      for (const std::string& w : m.warnings)
        std::fprintf(stderr, "warning: %s: %s\n", m.path.c_str(), w.c_str());
  return meshes;
}

NamePatterns name_patterns(const CommonOptions& o) {
  NamePatterns patterns;
  patterns.obstacle = o.obstacle_names;
  patterns.movable = o.movable_names;
  return patterns;
}

namespace {

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw Error(ExitCode::kOutputNotWritten, path, why);
}

// Output paths, checked before any work: one per movable input, in a format we can write, and
// (check_written_files) never a file read or written otherwise, never an existing file without
// --overwrite, in a writable folder.
std::vector<std::string> plan_outputs(const CommonOptions& o) {
  namespace fs = std::filesystem;
  std::vector<std::string> outputs = o.outputs;
  if (!o.output_dir.empty()) {
    for (const std::string& in : o.inputs) outputs.push_back((fs::path(o.output_dir) / fs::path(in).filename()).string());
  }
  if (outputs.size() != o.inputs.size()) {
    throw Error(ExitCode::kUsage, "",
                          "fix needs one -o per movable input (" + std::to_string(o.inputs.size()) +
                              " inputs, " + std::to_string(outputs.size()) + " outputs) or --output-dir");
  }
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const std::string& out = outputs[k];
    if (out == "-") refuse(out, "meshes are written to files, not to stdout");
    auto ext = [](const std::string& p) {
      std::string e = fs::path(p).extension().string();
      for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return e;
    };
    // Before can_write, which loads the assimp module for formats other than OBJ and OFF: an OBJ
    // input is refused any other output whether or not assimp could write it.
    if (ext(o.inputs[k]) == ".obj" && ext(out) != ".obj")
      refuse(out, "an OBJ input is written as OBJ (its lines are kept as they are)");
    if (!can_write(out)) refuse(out, "no writer for this file extension (`untangle formats` lists those it writes)");
    if (ext(out) == ".off") {
      std::ifstream in(o.inputs[k]);
      std::string keyword;
      in >> keyword;
      if (ext(o.inputs[k]) != ".off" || keyword != "OFF")
        refuse(out, "OFF is written only from a plain OFF input (its lines are kept as they are)");
    }
  }
  // What the output's format (or assimp's reader) cannot carry: refused unless accepted.
  for (std::size_t k = 0; k < outputs.size() && !o.allow_loss; ++k) {
    const std::string lost = export_loss(o.inputs[k], outputs[k]);
    if (!lost.empty())
      refuse(outputs[k], "would lose " + lost + " of " + o.inputs[k] +
                             " (not carried by this format or by assimp); --allow-loss writes it anyway");
  }
  // Outputs, their side files, --report and --contours against every file read and each other.
  check_written_files(o, outputs);
  return outputs;
}

// --pin files: one 0-based vertex index per line (of the first movable input), or
// "INPUT VERTEX" with the 0-based movable input number; '#' starts a comment.
PinMask read_pins(const CommonOptions& o, const std::vector<Mesh>& meshes,
                            const std::vector<std::size_t>& file_of) {
  PinMask pins(meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) pins[m].assign(meshes[m].positions.size(), 0);
  auto pin = [&](std::size_t file, long long index, const std::string& path, std::size_t line) {
    long long offset = index;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      if (m >= file_of.size() || file_of[m] != file) continue;
      if (offset < static_cast<long long>(meshes[m].positions.size())) {
        pins[m][static_cast<std::size_t>(offset)] = 1;
        return;
      }
      offset -= static_cast<long long>(meshes[m].positions.size());
    }
    throw Error(ExitCode::kUnreadableInput, path,
                          "line " + std::to_string(line) + ": vertex " + std::to_string(index) +
                              " is not in input " + std::to_string(file));
  };
  for (const std::string& path : o.pin_files) {
    std::ifstream in(path);
    if (!in) throw Error(ExitCode::kUnreadableInput, path, "cannot open pin file");
    std::string text;
    std::size_t line = 0;
    while (std::getline(in, text)) {
      ++line;
      text = text.substr(0, text.find('#'));
      std::istringstream fields(text);
      std::vector<long long> numbers;
      long long value = 0;
      while (fields >> value) numbers.push_back(value);
      if (!fields.eof()) throw Error(ExitCode::kUnreadableInput, path, "line " + std::to_string(line) + ": not a number");
      if (numbers.empty()) continue;
      if (numbers.size() > 2 || numbers.back() < 0 || (numbers.size() == 2 && numbers[0] < 0))
        throw Error(ExitCode::kUnreadableInput, path, "line " + std::to_string(line) + ": expected VERTEX or INPUT VERTEX");
      const std::size_t file = numbers.size() == 2 ? static_cast<std::size_t>(numbers[0]) : 0;
      pin(file, numbers.back(), path, line);
    }
  }
  for (const std::string& group : o.pin_groups) {
    bool found = false;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      const Mesh& mesh = meshes[m];
      if (mesh.role != Role::kMovable) continue;
      const bool whole = mesh.name == group && mesh.group_names.empty();
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const bool in_group = whole || (!mesh.group_names.empty() && mesh.group_names[mesh.triangle_group[t]] == group);
        if (!in_group) continue;
        found = true;
        for (std::uint32_t v : mesh.triangles[t]) pins[m][v] = 1;
      }
    }
    if (!found) throw Error(ExitCode::kUsage, "", "--pin-group " + group + ": no mesh or group of that name");
  }
  return pins;
}


// Whether `a` and `b` are the same meshes for detection: in the same order, the same roles and
// triangles, and positions equal bit for bit (memcmp: 0.0 and -0.0, or two NaNs, count as
// different). Detection reads nothing else of a mesh.
bool same_geometry(const std::vector<Mesh>& a, const std::vector<Mesh>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t m = 0; m < a.size(); ++m) {
    const Mesh &x = a[m], &y = b[m];
    if (x.role != y.role || x.triangles != y.triangles || x.positions.size() != y.positions.size())
      return false;
    if (!x.positions.empty() &&
        std::memcmp(x.positions.data(), y.positions.data(), x.positions.size() * sizeof(Vec3)) != 0)
      return false;
  }
  return true;
}

}  // namespace

PipelineRun run_pipeline(const CommonOptions& o, const FixProgress& progress) {
  PipelineRun run;
  const auto start = std::chrono::steady_clock::now();
  run.outputs = plan_outputs(o);
  std::vector<std::size_t> file_of;
  // The meshes as in the files (written from), and as split by role (repaired and reported).
  std::vector<Mesh> file_meshes = load_all(o, &file_of);
  RoleSplit split = split_by_name(file_meshes, read_pins(o, file_meshes, file_of), name_patterns(o));
  run.meshes = split.meshes;
  for (const auto& m : run.meshes) run.input.push_back(m.positions);
  run.timings.load = ms_since(start);

  FixOptions& options = run.options;
  options.method = o.method == "paper" ? FixMethod::kPaper : FixMethod::kRegion;
  options.max_iterations = o.max_iterations;
  options.clearance = o.clearance;
  options.step = o.step;
  options.outside_closed_obstacles = o.outside_closed;
  options.relax = o.relax;
  options.relax_sweeps = o.relax_sweeps;
  options.retries = o.retries;
  options.continuation = o.continuation;
  options.layering = o.layering;
  options.piece_moves = o.piece_moves;
  options.bounds = o.bounds;
  options.threads = o.threads;
  std::function<Vec3(const Vec3&)> rounding;
  for (const std::string& out : run.outputs)
    if (auto r = output_rounding(out)) rounding = r;
  const auto resolve_start = std::chrono::steady_clock::now();
  run.result = fix_meshes(run.meshes, options, split.pins, rounding, progress);
  run.infos = run.result.inputs;  // described from the repair's topology of the input
  split.meshes = run.meshes;
  merge_positions(split, file_meshes);
  run.timings.detect = run.result.detect_ms;
  run.timings.contours = run.result.contours_ms;
  run.timings.resolve = ms_since(resolve_start) - run.result.detect_ms - run.result.contours_ms;

  const auto write_start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < o.inputs.size(); ++k) {
    std::vector<const Mesh*> of_file;
    for (std::size_t m = 0; m < file_meshes.size(); ++m)
      if (m < file_of.size() && file_of[m] == k) of_file.push_back(&file_meshes[m]);
    write_meshes(o.inputs[k], run.outputs[k], of_file);
  }
  run.timings.write = ms_since(write_start);

  // The written files are the truth: read them back with the obstacles and detect again.
  const auto verify_start = std::chrono::steady_clock::now();
  std::vector<Mesh> read_back;
  for (const std::string& out : run.outputs)
    for (auto& m : read_meshes(out, Role::kMovable)) read_back.push_back(std::move(m));
  for (std::size_t m = file_of.size(); m < file_meshes.size(); ++m) read_back.push_back(file_meshes[m]);
  // The parts that are obstacles by name are checked as obstacles, like those of --obstacle.
  // Without patterns the read-back meshes are taken as they come (an exporter may regroup them).
  run.written = name_patterns(o).empty() ? std::move(read_back) : apply_split(split, read_back);
  const std::vector<Mesh>& written = run.written;
  if (run.result.clean_verdict && same_geometry(written, run.meshes)) {
    // The same roles, triangles and positions, bit for bit, as the repair's final detection saw:
    // the same detection (it is deterministic), found clean; not run a second time.
    run.verified = std::move(*run.result.clean_verdict);
  } else {
    DetectOptions detect;
    detect.threads = o.threads;
    detect.skip_obstacle_pairs = true;
    run.verified = find_intersections(written, detect);
  }
  run.result.clean_verdict.reset();
  // Quality too is judged on what was written (rounded as the format stores it).
  std::vector<Mesh> as_read = run.meshes;
  for (std::size_t m = 0; m < as_read.size(); ++m) as_read[m].positions = run.input[m];
  run.result.quality = measure_quality(as_read, written);
  run.timings.verify = ms_since(verify_start);
  run.timings.total = ms_since(start);
  return run;
}

}  // namespace untangle::app
