// Benchmark of untangle::fix_meshes on real MakeHuman garments against their bodies (issue 3).
//
// Usage: untangle_bench_fix [--data DIR] [--method region|paper|both] [--only NAME]
//   --data DIR  folder with garments/<sex>_*.obj and bodies/<sex>_generic.obj
//               (default: ../shared/data/makehuman, relative to the current directory;
//               when it is missing the benchmark prints "skipped" and exits 0)
//   --method    which FixMethod to run (default: both)
//   --only NAME run one garment (file name with or without ".obj")
// Exit status: 0 ran (whatever the outcome of each case) or skipped; 1 unreadable data; 2 usage.
//
// Each garment (movable) is fixed against its body (obstacle) twice: the body as shipped, and the
// body scaled by 1.02 about its bounding-box centre, which makes it poke through deeper. FixOptions
// are the defaults except the method. The result is verified as DESIGN §6 asks: the garment is
// written to a temporary OBJ with write_meshes, read back, and find_intersections (obstacle pairs
// skipped: the body's own self-intersections are not the garment's problem) must find nothing
// between the re-read garment and the body. The in-memory positions are detected too; any
// disagreement between FixResult, memory and file is listed after the table.
// Times are wall-clock (std::chrono::steady_clock); "total" is the whole fix_meshes call, the
// stage columns are FixResult's own sums over the iterations.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "untangle/error.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/mesh.h"
#include "untangle/mesh_info.h"
#include "untangle/read_meshes.h"
#include "untangle/write_meshes.h"

namespace {

namespace fs = std::filesystem;
using untangle::FixMethod;
using untangle::Mesh;

constexpr double kBodyScale = 1.02;

struct Garment {
  std::string name;  // file stem, e.g. male_casualsuit01
  std::string path;
  std::string body_path;
};

struct Case {
  std::string garment;
  std::string body;  // "shipped" or "x1.02"
  FixMethod method = FixMethod::kRegion;
  std::size_t vertices = 0;
  std::size_t crossings_before = 0;
  int iterations = 0;
  double detect_ms = 0.0, contours_ms = 0.0, resolve_ms = 0.0, total_ms = 0.0;
  std::size_t crossings_after = 0;  // detected on the re-read written file
  double max_over_mean_edge = 0.0, mean_over_mean_edge = 0.0;
  std::size_t moved_vertices = 0;
  std::string status;  // clean | unresolved | stalled | error
};

double elapsed_ms(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since)
      .count();
}

// Scales every position by `factor` about the centre of the bounding box of all meshes.
std::vector<Mesh> scaled_about_centre(std::vector<Mesh> meshes, double factor) {
  untangle::Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Mesh& m : meshes) {
    for (const untangle::Vec3& p : m.positions) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    }
  }
  for (Mesh& m : meshes) {
    for (untangle::Vec3& p : m.positions) {
      for (int k = 0; k < 3; ++k) {
        const double centre = 0.5 * (lo[k] + hi[k]);
        p[k] = centre + factor * (p[k] - centre);
      }
    }
  }
  return meshes;
}

// Mean edge length over all meshes, each mesh's mean weighted by its triangle count (the meshes of
// one garment file share a scale, so this only matters if a file holds several meshes).
double mean_edge_length(const std::vector<Mesh>& meshes) {
  double sum = 0.0, weight = 0.0;
  for (const Mesh& m : meshes) {
    const untangle::MeshInfo info = untangle::describe_mesh(m);
    sum += info.mean_edge_length * static_cast<double>(info.triangles);
    weight += static_cast<double>(info.triangles);
  }
  return weight > 0.0 ? sum / weight : 0.0;
}

// Crossings between `garment` and `body` (and within the garment), obstacle pairs left out.
std::size_t garment_crossings(const std::vector<Mesh>& garment, const std::vector<Mesh>& body) {
  std::vector<Mesh> scene = garment;
  scene.insert(scene.end(), body.begin(), body.end());
  untangle::DetectOptions options;
  options.skip_obstacle_pairs = true;
  return untangle::find_intersections(scene, options).counts.crossings;
}

// Fixes one garment against one body with one method, writes, re-reads and verifies.
Case run_case(const Garment& garment, const std::vector<Mesh>& garment_meshes,
              const std::vector<Mesh>& body, const std::string& body_label, FixMethod method,
              const fs::path& tmp_output, std::vector<std::string>& notes) {
  Case c;
  c.garment = garment.name;
  c.body = body_label;
  c.method = method;
  const std::string where =
      garment.name + " / " + body_label + " / " + untangle::to_string(method) + ": ";

  std::vector<Mesh> scene = garment_meshes;
  scene.insert(scene.end(), body.begin(), body.end());
  const std::size_t garment_count = garment_meshes.size();
  for (std::size_t i = 0; i < garment_count; ++i) c.vertices += scene[i].positions.size();

  untangle::FixOptions options;
  options.method = method;
  const auto start = std::chrono::steady_clock::now();
  const untangle::FixResult result =
      untangle::fix_meshes(scene, options, {}, untangle::output_rounding(tmp_output.string()));
  c.total_ms = elapsed_ms(start);

  c.crossings_before = result.before.crossings;
  c.iterations = result.iterations;
  c.detect_ms = result.detect_ms;
  c.contours_ms = result.contours_ms;
  c.resolve_ms = result.resolve_ms;
  c.max_over_mean_edge = result.displacement.max_over_mean_edge;
  const double mean_edge = mean_edge_length(garment_meshes);
  c.mean_over_mean_edge = mean_edge > 0.0 ? result.displacement.mean / mean_edge : 0.0;
  c.moved_vertices = result.displacement.moved_vertices;

  const std::vector<Mesh> fixed(scene.begin(), scene.begin() + garment_count);
  const std::size_t in_memory = garment_crossings(fixed, body);

  std::vector<const Mesh*> to_write;
  for (const Mesh& m : fixed) to_write.push_back(&m);
  untangle::write_meshes(garment.path, tmp_output.string(), to_write);
  const std::vector<Mesh> reread =
      untangle::read_meshes(tmp_output.string(), untangle::Role::kMovable);
  fs::remove(tmp_output);
  c.crossings_after = garment_crossings(reread, body);

  if (c.crossings_after == 0) {
    c.status = "clean";
  } else {
    c.status = result.stalled ? "stalled" : "unresolved";
  }
  if (result.clean != (c.crossings_after == 0)) {
    notes.push_back(where + "FixResult says " + (result.clean ? "clean" : "not clean") +
                    " but the written file has " + std::to_string(c.crossings_after) +
                    " crossings");
  }
  if (result.after.crossings != in_memory || in_memory != c.crossings_after) {
    notes.push_back(where + "crossings after: FixResult " + std::to_string(result.after.crossings) +
                    ", in memory " + std::to_string(in_memory) + ", written file " +
                    std::to_string(c.crossings_after));
  }
  if (c.status != "clean") {
    const untangle::IntersectionCounts& a = result.after;
    notes.push_back(where + c.status + ": " + std::to_string(a.contours) + " contours left (CL " +
                    std::to_string(a.tracks[0]) + ", BB " + std::to_string(a.tracks[1]) + ", BI " +
                    std::to_string(a.tracks[2]) + ", II " + std::to_string(a.tracks[3]) +
                    " tracks), contour length " + std::to_string(a.contour_length));
  }
  return c;
}

void print_header() {
  std::printf("%-20s %-7s %-6s %6s %7s %5s %9s %9s %9s %9s %6s %8s %9s %6s  %s\n", "garment",
              "body", "method", "verts", "before", "iter", "detect", "contours", "resolve", "total",
              "after", "max/edge", "mean/edge", "moved", "status");
  std::printf("%-20s %-7s %-6s %6s %7s %5s %9s %9s %9s %9s %6s %8s %9s %6s\n", "", "", "", "", "",
              "", "ms", "ms", "ms", "ms", "", "", "", "");
}

void print_row(const Case& c) {
  std::printf("%-20s %-7s %-6s %6zu %7zu %5d %9.1f %9.1f %9.1f %9.1f %6zu %8.2f %9.2f %6zu  %s\n",
              c.garment.c_str(), c.body.c_str(), untangle::to_string(c.method), c.vertices,
              c.crossings_before, c.iterations, c.detect_ms, c.contours_ms, c.resolve_ms,
              c.total_ms, c.crossings_after, c.max_over_mean_edge, c.mean_over_mean_edge,
              c.moved_vertices, c.status.c_str());
  std::fflush(stdout);
}

int usage_error(const char* program, const std::string& message) {
  std::fprintf(stderr,
               "error: %s\nusage: %s [--data DIR] [--method region|paper|both] [--only NAME]\n",
               message.c_str(), program);
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string data_dir = "../shared/data/makehuman";
  std::string method_arg = "both";
  std::string only;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::printf(
          "usage: %s [--data DIR] [--method region|paper|both] [--only NAME]\n"
          "  --data DIR   garments/<sex>_*.obj and bodies/<sex>_generic.obj "
          "(default ../shared/data/makehuman)\n"
          "  --method M   region, paper or both (default both)\n"
          "  --only NAME  run one garment, e.g. male_casualsuit01\n",
          argv[0]);
      return 0;
    }
    if (arg == "--data" || arg == "--method" || arg == "--only") {
      if (i + 1 >= argc) return usage_error(argv[0], arg + " needs a value");
      const std::string value = argv[++i];
      if (arg == "--data") data_dir = value;
      if (arg == "--method") method_arg = value;
      if (arg == "--only") only = value;
    } else {
      return usage_error(argv[0], "unknown argument '" + arg + "'");
    }
  }
  std::vector<FixMethod> methods;
  if (method_arg == "region" || method_arg == "both") methods.push_back(FixMethod::kRegion);
  if (method_arg == "paper" || method_arg == "both") methods.push_back(FixMethod::kPaper);
  if (methods.empty()) {
    return usage_error(argv[0], "--method must be region, paper or both, not '" + method_arg + "'");
  }
  if (only.size() > 4 && only.compare(only.size() - 4, 4, ".obj") == 0)
    only.resize(only.size() - 4);

  const fs::path garments_dir = fs::path(data_dir) / "garments";
  const fs::path bodies_dir = fs::path(data_dir) / "bodies";
  if (!fs::is_directory(garments_dir) || !fs::is_directory(bodies_dir)) {
    std::printf(
        "%s: no garments/ and bodies/ folders there (MakeHuman data, see issue 3); "
        "pass --data DIR: skipped\n",
        data_dir.c_str());
    return 0;
  }

  std::vector<Garment> garments;
  for (const fs::directory_entry& entry : fs::directory_iterator(garments_dir)) {
    const fs::path& p = entry.path();
    if (!entry.is_regular_file() || p.extension() != ".obj") continue;
    const std::string stem = p.stem().string();
    const std::size_t underscore = stem.find('_');
    if (underscore == std::string::npos) continue;
    if (!only.empty() && stem != only) continue;
    const fs::path body = bodies_dir / (stem.substr(0, underscore) + "_generic.obj");
    if (!fs::is_regular_file(body)) {
      std::printf("note: %s: no body %s, left out\n", p.string().c_str(), body.string().c_str());
      continue;
    }
    garments.push_back({stem, p.string(), body.string()});
  }
  std::sort(garments.begin(), garments.end(),
            [](const Garment& a, const Garment& b) { return a.name < b.name; });
  if (garments.empty()) {
    if (!only.empty())
      return usage_error(argv[0], "no garment named '" + only + "' in " + data_dir);
    std::printf("%s: no <sex>_*.obj garment with a matching body: skipped\n", data_dir.c_str());
    return 0;
  }

  const fs::path tmp_output =
      fs::temp_directory_path() / ("untangle_bench_fix_" + std::to_string(getpid()) + ".obj");
  std::map<std::string, std::vector<Mesh>> bodies;  // keyed by path: each body is read once
  std::vector<Case> cases;
  std::vector<std::string> notes;
  print_header();
  for (const Garment& garment : garments) {
    std::vector<Mesh> garment_meshes;
    try {
      garment_meshes = untangle::read_meshes(garment.path, untangle::Role::kMovable);
      if (bodies.count(garment.body_path) == 0) {
        bodies[garment.body_path] =
            untangle::read_meshes(garment.body_path, untangle::Role::kObstacle);
      }
    } catch (const untangle::Error& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return 1;
    }
    const std::vector<Mesh>& shipped = bodies[garment.body_path];
    const std::vector<std::pair<std::string, std::vector<Mesh>>> body_cases = {
        {"shipped", shipped}, {"x1.02", scaled_about_centre(shipped, kBodyScale)}};
    for (const auto& [body_label, body] : body_cases) {
      for (FixMethod method : methods) {
        Case c;
        try {
          c = run_case(garment, garment_meshes, body, body_label, method, tmp_output, notes);
        } catch (const std::exception& e) {
          c.garment = garment.name;
          c.body = body_label;
          c.method = method;
          c.status = "error";
          notes.push_back(garment.name + " / " + body_label + " / " + untangle::to_string(method) +
                          ": " + e.what());
          std::error_code ignored;
          fs::remove(tmp_output, ignored);
        }
        print_row(c);
        cases.push_back(c);
      }
    }
  }

  if (!notes.empty()) {
    std::printf("\nnotes:\n");
    for (const std::string& note : notes) std::printf("  %s\n", note.c_str());
  }
  std::printf("\nsummary:\n");
  for (FixMethod method : methods) {
    int clean = 0, total = 0, iterations = 0;
    double total_ms = 0.0, worst_ms = 0.0, detect_ms = 0.0, contours_ms = 0.0, resolve_ms = 0.0;
    for (const Case& c : cases) {
      if (c.method != method) continue;
      ++total;
      if (c.status == "clean") ++clean;
      iterations += c.iterations;
      total_ms += c.total_ms;
      worst_ms = std::max(worst_ms, c.total_ms);
      detect_ms += c.detect_ms;
      contours_ms += c.contours_ms;
      resolve_ms += c.resolve_ms;
    }
    std::printf(
        "  %-6s clean %d / %d, total %.1f ms (detect %.1f, contours %.1f, resolve %.1f), "
        "mean %.1f ms per case, slowest %.1f ms, %d iterations\n",
        untangle::to_string(method), clean, total, total_ms, detect_ms, contours_ms, resolve_ms,
        total > 0 ? total_ms / total : 0.0, worst_ms, iterations);
  }
  return 0;
}
