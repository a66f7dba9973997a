// The untangle command line: parses (CLI11), calls the library, maps results to exit codes.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <iostream>
#include <string>
#include <vector>

#include "untangle/error.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/mesh_info.h"
#include "untangle/read_meshes.h"
#include "untangle/report.h"
#include "untangle/version.h"
#include "untangle/write_meshes.h"

namespace {

using untangle::ExitCode;

constexpr const char* kExitCodes =
    "Exit codes:\n"
    "  0  success: nothing intersects (check), or the command did its job\n"
    "  1  internal error\n"
    "  2  usage error (bad command line)\n"
    "  3  unreadable input (missing, empty, unknown format, corrupt, no triangles,\n"
    "     NaN or infinite coordinates, face indices out of range)\n"
    "  4  output not written\n"
    "  5  intersections found (check) or remaining in the written output (fix)\n";

struct CommonOptions {
  std::vector<std::string> inputs;
  std::vector<std::string> obstacles;
  std::string report;
  std::string contours;
  int threads = 0;
  bool quiet = false;
  bool verbose = false;
  // fix
  std::vector<std::string> outputs;
  std::string output_dir;
  std::vector<std::string> pin_files;
  std::vector<std::string> pin_groups;
  std::string method = "region";
  int max_iterations = 200;
  double clearance = 0.05;
  bool outside_closed = true;
  bool overwrite = false;
};

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::vector<untangle::Mesh> load_all(const CommonOptions& o, std::vector<std::size_t>* file_of = nullptr) {
  std::vector<untangle::Mesh> meshes;
  for (std::size_t k = 0; k < o.inputs.size(); ++k) {
    for (auto& m : untangle::read_meshes(o.inputs[k], untangle::Role::kMovable)) {
      meshes.push_back(std::move(m));
      if (file_of != nullptr) file_of->push_back(k);
    }
  }
  for (const std::string& path : o.obstacles) {
    for (auto& m : untangle::read_meshes(path, untangle::Role::kObstacle)) meshes.push_back(std::move(m));
  }
  return meshes;
}

// Labels name the mesh inside its file only when the file holds several.
std::vector<std::string> labels_of(const std::vector<untangle::Mesh>& meshes) {
  std::vector<std::string> labels;
  for (const auto& m : meshes) {
    std::size_t same_file = 0;
    for (const auto& other : meshes) same_file += other.path == m.path ? 1 : 0;
    labels.push_back(untangle::mesh_label(m, same_file > 1));
  }
  return labels;
}

void emit_report(const std::string& target, const std::string& json) {
  if (target.empty()) return;
  if (target == "-") {
    std::fwrite(json.data(), 1, json.size(), stdout);
    std::fflush(stdout);
  } else {
    untangle::write_text_file_atomically(target, json);
  }
}

int run_info(const CommonOptions& o) {
  const std::vector<untangle::Mesh> meshes = load_all(o);
  std::vector<untangle::MeshInfo> infos;
  for (const auto& m : meshes) infos.push_back(untangle::describe_mesh(m));
  const bool human = !o.quiet && o.report != "-";
  if (human) {
    const std::vector<std::string> labels = labels_of(meshes);
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      const auto& in = infos[i];
      std::printf("%s (%s)\n", labels[i].c_str(), untangle::to_string(meshes[i].role));
      std::printf("  vertices %zu, faces %zu, triangles %zu, welded vertices %zu\n", in.vertices,
                  in.faces, in.triangles, in.welded_vertices);
      std::printf("  components %zu, boundary loops %zu, non-manifold edges %zu, %s\n",
                  in.components, in.boundary_loops, in.non_manifold_edges,
                  in.closed ? "closed" : "open");
      std::printf("  zero-area triangles %zu, degenerate triangles %zu\n", in.zero_area_triangles,
                  in.degenerate_triangles);
      if (o.verbose) {
        std::printf("  boundary edges %zu, area %.6g, mean edge length %.6g\n", in.boundary_edges,
                    in.area, in.mean_edge_length);
      }
    }
  }
  emit_report(o.report, untangle::info_report_json(meshes, infos));
  return 0;
}

int run_check(const CommonOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<untangle::Mesh> meshes = load_all(o);
  std::vector<untangle::MeshInfo> infos;
  for (const auto& m : meshes) infos.push_back(untangle::describe_mesh(m));
  untangle::CheckTimingsMs timings;
  timings.load = ms_since(start);

  untangle::DetectOptions options;
  options.threads = o.threads;
  untangle::DetectTimings detect;
  const untangle::Intersections found = untangle::find_intersections(meshes, options, &detect);
  timings.detect = detect.detect_ms;
  timings.contours = detect.contours_ms;

  if (!o.contours.empty()) {
    untangle::write_text_file_atomically(o.contours, untangle::contours_obj(found));
  }
  timings.total = ms_since(start);

  const auto& c = found.counts;
  const bool clean = c.crossings == 0;
  if (!o.quiet && o.report != "-") {
    const std::vector<std::string> labels = labels_of(meshes);
    if (o.verbose) {
      for (std::size_t i = 0; i < meshes.size(); ++i) {
        std::printf("mesh %zu: %s (%s), %zu vertices, %zu faces, %zu boundary loops\n", i,
                    labels[i].c_str(), untangle::to_string(meshes[i].role), infos[i].vertices,
                    infos[i].faces, infos[i].boundary_loops);
      }
    }
    std::printf("crossings %zu, intersecting triangle pairs %zu, contours %zu (length %.6g)\n",
                c.crossings, c.triangle_pairs, c.contours, c.contour_length);
    if (c.contours > 0) {
      std::printf("pairs: CL/CL %zu, BB/II %zu, BI/BI %zu, self %zu, other %zu; "
                  "loop vertices %zu, non-separating tracks %zu\n",
                  c.pairs_cl_cl, c.pairs_bb_ii, c.pairs_bi_bi, c.pairs_self, c.pairs_other,
                  c.loop_vertices, c.non_separating);
    }
    if (o.verbose) {
      for (std::size_t k = 0; k < found.contours.size(); ++k) {
        const auto& ct = found.contours[k];
        std::printf("  contour %zu: %s %s/%s %s, %zu crossings, length %.6g\n", k,
                    labels[ct.tracks[0].mesh].c_str(), untangle::to_string(ct.tracks[0].type),
                    untangle::to_string(ct.tracks[1].type), labels[ct.tracks[1].mesh].c_str(),
                    ct.crossings.size(), ct.length);
      }
    }
    std::printf("status: %s\n", clean ? "clean" : "intersecting");
  }
  emit_report(o.report, untangle::check_report_json(meshes, infos, found, timings));
  return clean ? 0 : static_cast<int>(ExitCode::kIntersecting);
}


[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw untangle::Error(ExitCode::kOutputNotWritten, path, why);
}

// Output paths, checked before any work: one per movable input, never an input, never an
// existing file without --overwrite, in an existing folder, in a format we can write.
std::vector<std::string> plan_outputs(const CommonOptions& o) {
  namespace fs = std::filesystem;
  std::vector<std::string> outputs = o.outputs;
  if (!o.output_dir.empty()) {
    for (const std::string& in : o.inputs) outputs.push_back((fs::path(o.output_dir) / fs::path(in).filename()).string());
  }
  if (outputs.size() != o.inputs.size()) {
    throw untangle::Error(ExitCode::kUsage, "",
                          "fix needs one -o per movable input (" + std::to_string(o.inputs.size()) +
                              " inputs, " + std::to_string(outputs.size()) + " outputs) or --output-dir");
  }
  auto same_file = [](const std::string& a, const std::string& b) {
    std::error_code ec;
    if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
    return fs::weakly_canonical(a, ec) == fs::weakly_canonical(b, ec);
  };
  for (std::size_t k = 0; k < outputs.size(); ++k) {
    const std::string& out = outputs[k];
    std::vector<std::string> all_inputs = o.inputs;
    all_inputs.insert(all_inputs.end(), o.obstacles.begin(), o.obstacles.end());
    for (const std::string& in : all_inputs)
      if (same_file(out, in)) refuse(out, "is an input; untangle never overwrites its inputs");
    for (std::size_t j = 0; j < k; ++j)
      if (same_file(out, outputs[j])) refuse(out, "named twice as output");
    const fs::path parent = fs::path(out).has_parent_path() ? fs::path(out).parent_path() : fs::path(".");
    std::error_code ec;
    if (!fs::is_directory(parent, ec)) refuse(out, "folder " + parent.string() + " does not exist");
    if (fs::exists(out, ec) && !o.overwrite) refuse(out, "exists; pass --overwrite to replace it");
    if (!untangle::can_write(out)) refuse(out, "no writer for this file extension");
    auto ext = [](const std::string& p) {
      std::string e = fs::path(p).extension().string();
      for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      return e;
    };
    if (ext(o.inputs[k]) == ".obj" && ext(out) != ".obj")
      refuse(out, "an OBJ input is written as OBJ (its lines are kept as they are)");
    if (ext(out) == ".off") {
      std::ifstream in(o.inputs[k]);
      std::string keyword;
      in >> keyword;
      if (ext(o.inputs[k]) != ".off" || keyword != "OFF")
        refuse(out, "OFF is written only from a plain OFF input (its lines are kept as they are)");
    }
  }
  return outputs;
}

// --pin files: one 0-based vertex index per line (of the first movable input), or
// "INPUT VERTEX" with the 0-based movable input number; '#' starts a comment.
untangle::PinMask read_pins(const CommonOptions& o, const std::vector<untangle::Mesh>& meshes,
                            const std::vector<std::size_t>& file_of) {
  untangle::PinMask pins(meshes.size());
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
    throw untangle::Error(ExitCode::kUnreadableInput, path,
                          "line " + std::to_string(line) + ": vertex " + std::to_string(index) +
                              " is not in input " + std::to_string(file));
  };
  for (const std::string& path : o.pin_files) {
    std::ifstream in(path);
    if (!in) throw untangle::Error(ExitCode::kUnreadableInput, path, "cannot open pin file");
    std::string text;
    std::size_t line = 0;
    while (std::getline(in, text)) {
      ++line;
      text = text.substr(0, text.find('#'));
      std::istringstream fields(text);
      std::vector<long long> numbers;
      long long value = 0;
      while (fields >> value) numbers.push_back(value);
      if (!fields.eof()) throw untangle::Error(ExitCode::kUnreadableInput, path, "line " + std::to_string(line) + ": not a number");
      if (numbers.empty()) continue;
      if (numbers.size() > 2 || numbers.back() < 0 || (numbers.size() == 2 && numbers[0] < 0))
        throw untangle::Error(ExitCode::kUnreadableInput, path, "line " + std::to_string(line) + ": expected VERTEX or INPUT VERTEX");
      const std::size_t file = numbers.size() == 2 ? static_cast<std::size_t>(numbers[0]) : 0;
      pin(file, numbers.back(), path, line);
    }
  }
  for (const std::string& group : o.pin_groups) {
    bool found = false;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      const untangle::Mesh& mesh = meshes[m];
      if (mesh.role != untangle::Role::kMovable) continue;
      const bool whole = mesh.name == group && mesh.group_names.empty();
      for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const bool in_group = whole || (!mesh.group_names.empty() && mesh.group_names[mesh.triangle_group[t]] == group);
        if (!in_group) continue;
        found = true;
        for (std::uint32_t v : mesh.triangles[t]) pins[m][v] = 1;
      }
    }
    if (!found) throw untangle::Error(ExitCode::kUsage, "", "--pin-group " + group + ": no mesh or group of that name");
  }
  return pins;
}

int run_fix(const CommonOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<std::string> outputs = plan_outputs(o);
  std::vector<std::size_t> file_of;
  std::vector<untangle::Mesh> meshes = load_all(o, &file_of);
  std::vector<untangle::MeshInfo> infos;
  for (const auto& m : meshes) infos.push_back(untangle::describe_mesh(m));
  const untangle::PinMask pins = read_pins(o, meshes, file_of);
  untangle::FixTimingsMs timings;
  timings.load = ms_since(start);

  untangle::FixOptions options;
  options.method = o.method == "paper" ? untangle::FixMethod::kPaper : untangle::FixMethod::kRegion;
  options.max_iterations = o.max_iterations;
  options.clearance = o.clearance;
  options.outside_closed_obstacles = o.outside_closed;
  options.threads = o.threads;
  std::function<untangle::Vec3(const untangle::Vec3&)> rounding;
  for (const std::string& out : outputs)
    if (auto r = untangle::output_rounding(out)) rounding = r;
  const bool show = !o.quiet && o.report != "-";
  untangle::FixProgress progress;
  if (o.verbose && show) {
    progress = [](const untangle::IterationRecord& r) {
      std::fprintf(stderr, "iteration %d: %zu crossings, contour length %.6g, %.1f ms\n", r.iteration,
                   r.crossings, r.contour_length, r.elapsed_ms);
      return true;
    };
  }
  const auto resolve_start = std::chrono::steady_clock::now();
  const untangle::FixResult result = untangle::fix_meshes(meshes, options, pins, rounding, progress);
  timings.detect = result.detect_ms;
  timings.contours = result.contours_ms;
  timings.resolve = ms_since(resolve_start) - result.detect_ms - result.contours_ms;

  const auto write_start = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < o.inputs.size(); ++k) {
    std::vector<const untangle::Mesh*> of_file;
    for (std::size_t m = 0; m < meshes.size(); ++m)
      if (m < file_of.size() && file_of[m] == k) of_file.push_back(&meshes[m]);
    untangle::write_meshes(o.inputs[k], outputs[k], of_file);
  }
  timings.write = ms_since(write_start);

  // The written files are the truth: read them back with the obstacles and detect again.
  const auto verify_start = std::chrono::steady_clock::now();
  std::vector<untangle::Mesh> written;
  for (const std::string& out : outputs)
    for (auto& m : untangle::read_meshes(out, untangle::Role::kMovable)) written.push_back(std::move(m));
  for (const auto& m : meshes)
    if (m.role == untangle::Role::kObstacle) written.push_back(m);
  untangle::DetectOptions detect;
  detect.threads = o.threads;
  detect.skip_obstacle_pairs = true;
  const untangle::Intersections verified = untangle::find_intersections(written, detect);
  timings.verify = ms_since(verify_start);
  timings.total = ms_since(start);

  if (!o.contours.empty()) {
    untangle::write_text_file_atomically(o.contours, untangle::contours_obj(verified));
  }
  const bool clean = verified.counts.crossings == 0;
  if (show) {
    std::printf("before: %zu crossings, %zu contours; after %d iterations: %zu crossings, %zu contours\n",
                result.before.crossings, result.before.contours, result.iterations,
                verified.counts.crossings, verified.counts.contours);
    std::printf("moved %zu vertices, max %.6g (%.3g mean edge lengths), mean %.6g\n",
                result.displacement.moved_vertices, result.displacement.max,
                result.displacement.max_over_mean_edge, result.displacement.mean);
    for (std::size_t k = 0; k < outputs.size(); ++k) std::printf("wrote %s\n", outputs[k].c_str());
    if (!clean) {
      const std::vector<std::string> labels = labels_of(written);
      for (std::size_t k = 0; k < verified.contours.size(); ++k) {
        const auto& ct = verified.contours[k];
        std::printf("  remaining contour %zu: %s %s/%s %s, %zu crossings\n", k,
                    labels[ct.tracks[0].mesh].c_str(), untangle::to_string(ct.tracks[0].type),
                    untangle::to_string(ct.tracks[1].type), labels[ct.tracks[1].mesh].c_str(),
                    ct.crossings.size());
      }
    }
    std::printf("status: %s%s\n", clean ? "clean" : "unresolved", result.stalled && !clean ? " (stalled)" : "");
  }
  emit_report(o.report, untangle::fix_report_json(meshes, infos, outputs, options, result, verified, timings));
  return clean ? 0 : static_cast<int>(ExitCode::kIntersecting);
}

void add_common(CLI::App& cmd, CommonOptions& o, bool with_check_options) {
  cmd.add_option("meshes", o.inputs, "Mesh files (every format assimp reads)")->required();
  cmd.add_option("--report", o.report, "Write a JSON report to FILE ('-' = stdout, which then carries nothing else)")
      ->option_text("FILE");
  cmd.add_flag("-q,--quiet", o.quiet, "Print nothing but errors");
  cmd.add_flag("-v,--verbose", o.verbose, "Print more detail");
  if (with_check_options) {
    cmd.add_option("--obstacle", o.obstacles, "A mesh that never moves (repeatable)")
        ->allow_extra_args(false)
        ->option_text("MESH");
    cmd.add_option("--contours", o.contours, "Write the contour polylines as OBJ to FILE")
        ->option_text("FILE");
    cmd.add_option("--threads", o.threads, "Worker threads, 0 = all cores (same result for every N)")
        ->check(CLI::NonNegativeNumber)
        ->option_text("N");
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"untangle: find and repair intersecting triangle meshes (garments, bodies, cloth)",
               "untangle"};
  app.footer(kExitCodes);
  app.set_version_flag("--version", untangle::version_text(), "Print the versions of untangle, CGAL, assimp and Eigen");
  app.require_subcommand(1);

  CommonOptions info_options, check_options;
  CLI::App* info = app.add_subcommand("info", "Describe each mesh: counts, boundary loops, closedness");
  add_common(*info, info_options, false);
  info->footer(kExitCodes);
  CLI::App* check = app.add_subcommand(
      "check", "Find every crossing between and within meshes; build and classify contours");
  add_common(*check, check_options, true);
  check->footer(kExitCodes);
  CommonOptions fix_options;
  CLI::App* fix = app.add_subcommand(
      "fix", "Move vertices of the movable meshes until nothing intersects; write the result");
  add_common(*fix, fix_options, true);
  fix->add_option("-o,--output", fix_options.outputs, "Output file, once per movable input, in order")
      ->allow_extra_args(false)
      ->option_text("OUT");
  fix->add_option("--output-dir", fix_options.output_dir, "Write each output under DIR with its input's file name")
      ->option_text("DIR");
  fix->add_option("--pin", fix_options.pin_files,
                  "File of vertex indices that must not move (0-based, file order; 'INPUT VERTEX' for other inputs)")
      ->allow_extra_args(false)
      ->option_text("FILE");
  fix->add_option("--pin-group", fix_options.pin_groups, "Pin every vertex of the named group or mesh (repeatable)")
      ->allow_extra_args(false)
      ->option_text("NAME");
  fix->add_option("--method", fix_options.method,
                  "region: move whole illegal regions (default); paper: Eq. 1 on crossing edges only")
      ->check(CLI::IsMember({"region", "paper"}))
      ->option_text("region|paper");
  fix->add_option("--max-iterations", fix_options.max_iterations, "Iteration cap (default 200)")
      ->check(CLI::NonNegativeNumber)
      ->option_text("N");
  fix->add_option("--clearance", fix_options.clearance,
                  "Gap left between surfaces, in mean edge lengths of the moving mesh (default 0.05)")
      ->check(CLI::NonNegativeNumber)
      ->option_text("X");
  fix->add_flag("--outside-closed-obstacles,!--orientation-free", fix_options.outside_closed,
                "A closed obstacle's inside decides the illegal side (default); --orientation-free: "
                "the smaller region is illegal everywhere (the paper's rule)");
  fix->add_flag("--overwrite", fix_options.overwrite, "Replace existing output files (never an input)");
  fix->footer(kExitCodes);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "error: %s (run 'untangle --help' for usage)\n", e.what());
    return static_cast<int>(ExitCode::kUsage);
  }

  try {
    if (info->parsed()) return run_info(info_options);
    if (check->parsed()) return run_check(check_options);
    if (fix->parsed()) return run_fix(fix_options);
  } catch (const untangle::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory\n");
    return static_cast<int>(ExitCode::kInternal);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: internal: %s\n", e.what());
    return static_cast<int>(ExitCode::kInternal);
  }
  return static_cast<int>(ExitCode::kUsage);
}
