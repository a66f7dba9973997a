// `untangle bench` (see bench.h): built-in generated scenes and garment/body pairs, each run
// through the same pipeline as `untangle fix`, timed with the monotonic clock.
#include "bench.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "best_median.h"
#include "pipeline.h"
#include "plot.h"
#include "scenes/scenes.h"
#include "untangle/error.h"
#include "untangle/read_meshes.h"
#include "untangle/report.h"
#include "untangle/version.h"

namespace untangle::app {
namespace {

namespace fs = std::filesystem;

// A scene as files: what the pipeline reads.
struct BenchCase {
  std::string name;
  std::string source;  // "generated" or "data"
  std::vector<std::string> movable, obstacles;
};

// A folder under the system temp folder, removed with everything in it on destruction.
class ScratchDir {
 public:
  ScratchDir() {
    std::random_device seed;
    path_ = fs::temp_directory_path() /
            ("untangle-bench-" + std::to_string(getpid()) + "-" + std::to_string(seed()));
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

// The built-in suite, written as OBJ so that `load` reads real files.
std::vector<BenchCase> generated_cases(bool quick, const fs::path& folder) {
  std::vector<scenes::Scene> suite = scenes::named_scenes();
  if (quick) {
    const std::set<std::string> keep = {"sheet_through_sphere", "strip_through_sheet",
                                        "sheets_corner", "tube_around_body"};
    suite.erase(std::remove_if(suite.begin(), suite.end(),
                               [&](const scenes::Scene& s) { return keep.count(s.name) == 0; }),
                suite.end());
  } else {
    suite.push_back(scenes::sheet_through_capsule(161));
  }
  std::vector<BenchCase> cases;
  for (const scenes::Scene& scene : suite) {
    const scenes::SceneFiles files = scenes::write_scene_files(scene, (folder / scene.name).string());
    cases.push_back({scene.name, "generated", files.movable, files.obstacles});
  }
  return cases;
}

constexpr double kBodyScale = 1.02;

// Every garment/body pair of a MakeHuman-style folder: DIR/garments/<prefix>_*.obj against
// DIR/bodies/<prefix>_generic.obj, once with the body as shipped and once scaled by 1.02 about its
// centre (deeper penetrations; written under `folder`), sorted by garment name; then every two
// garments for one body worn together on it.
std::vector<BenchCase> data_cases(const std::string& dir, const fs::path& folder,
                                  std::vector<std::string>& notes) {
  const std::vector<std::pair<std::string, std::string>> pairs = scenes::garment_body_pairs(dir, notes);
  std::map<std::string, std::vector<std::string>> scaled;  // body path -> its scaled meshes
  std::vector<BenchCase> cases;
  for (const auto& [garment, body] : pairs) {
    if (scaled.count(body) == 0) {
      const std::vector<Mesh> meshes = scenes::scaled_about_centre(read_meshes(body, Role::kObstacle), kBodyScale);
      const fs::path out = folder / (fs::path(body).stem().string() + "_x1.02");
      scaled[body] = scenes::write_scene_files({"", {}, meshes}, out.string()).obstacles;
    }
    const std::string name = fs::path(garment).stem().string();
    cases.push_back({name, "data", {garment}, {body}});
    cases.push_back({name + "_x1.02", "data", {garment}, scaled[body]});
  }
  // Layers: every two garments made for one body, worn together on it (the first in name order
  // listed first), with the body as shipped.
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    for (std::size_t j = i + 1; j < pairs.size(); ++j) {
      if (pairs[i].second != pairs[j].second) continue;
      cases.push_back({fs::path(pairs[i].first).stem().string() + "+" +
                           fs::path(pairs[j].first).stem().string(),
                       "data", {pairs[i].first, pairs[j].first}, {pairs[i].second}});
    }
  }
  return cases;
}

const char* const kStages[] = {"load", "detect", "contours", "regions", "displace", "write", "verify", "total"};
constexpr std::size_t kStageCount = 8;

std::array<double, kStageCount> stage_times(const PipelineRun& run) {
  const FixTimingsMs& t = run.timings;
  const FixResult& r = run.result;
  return {t.load, r.detect_ms, r.contours_ms, r.regions_ms, r.displace_ms, t.write, t.verify, t.total};
}

// Mean edge length of the movable meshes, each mesh's mean weighted by its triangle count.
double movable_mean_edge(const PipelineRun& run) {
  double sum = 0.0, weight = 0.0;
  for (std::size_t m = 0; m < run.meshes.size(); ++m) {
    if (run.meshes[m].role != Role::kMovable) continue;
    sum += run.infos[m].mean_edge_length * static_cast<double>(run.infos[m].triangles);
    weight += static_cast<double>(run.infos[m].triangles);
  }
  return weight > 0.0 ? sum / weight : 0.0;
}

// Mean over the distinct edges of the movable meshes of |length after - length before| / length
// before (edges of zero length before left out).
double mean_edge_change(const PipelineRun& run) {
  double sum = 0.0;
  std::size_t count = 0;
  auto length = [](const Vec3& a, const Vec3& b) {
    return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
  };
  for (std::size_t m = 0; m < run.meshes.size(); ++m) {
    const Mesh& mesh = run.meshes[m];
    if (mesh.role != Role::kMovable) continue;
    std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
    for (const Triangle& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
    for (const auto& [a, b] : edges) {
      const double before = length(run.input[m][a], run.input[m][b]);
      if (before <= 0.0) continue;
      sum += std::fabs(length(mesh.positions[a], mesh.positions[b]) - before) / before;
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

// One scene under one method and one setting: the table row.
struct Row {
  std::string scene, source, method;
  double clearance = 0.0, step = 0.0;
  std::size_t vertices = 0;  // of the movable meshes
  std::size_t before = 0, after = 0;
  int iterations = 0;
  bool stalled = false;
  std::array<Stat, kStageCount> stages{};
  double max_rel = 0.0, mean_rel = 0.0, edge_change = 0.0;
  std::size_t moved = 0;
  // Of the written files: vertices inside an obstacle, the largest edge stretch and the flipped
  // faces over the movable meshes, and whether every movable mesh is within the default bounds.
  std::size_t inside_after = 0, flips = 0;
  double stretch = 1.0;
  bool within = true;
  std::vector<IterationRecord> history;  // of the run with the median total time
};

// The history of the repeat with the median total time, so that the plot shows a typical run.
void keep_median_history(Row& row, const std::vector<std::vector<IterationRecord>>& histories,
                         const std::vector<double>& totals) {
  std::vector<std::size_t> order(totals.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return totals[a] < totals[b]; });
  if (!order.empty()) row.history = histories[order[(order.size() - 1) / 2]];
}

Row run_case(const BenchCase& c, const std::string& method, double clearance, double step,
             int repeat, int threads, const fs::path& scratch, std::vector<std::string>& notes) {
  CommonOptions o;
  o.inputs = c.movable;
  o.obstacles = c.obstacles;
  o.method = method;
  o.clearance = clearance;
  o.step = step;
  o.threads = threads;
  o.overwrite = true;
  o.output_dir = (scratch / "out" / c.name).string();
  fs::create_directories(o.output_dir);
  Row row;
  row.scene = c.name;
  row.source = c.source;
  row.method = method;
  row.clearance = clearance;
  row.step = step;
  std::vector<std::array<double, kStageCount>> times;
  std::vector<std::vector<IterationRecord>> histories;
  PipelineRun run;  // every repeat gives the same positions (deterministic): keep the last
  for (int r = 0; r < repeat; ++r) {
    run = run_pipeline(o);
    times.push_back(stage_times(run));
    histories.push_back(run.result.history);
  }
  std::vector<double> totals;
  for (std::size_t s = 0; s < kStageCount; ++s) {
    std::vector<double> v;
    for (const auto& t : times) v.push_back(t[s]);
    row.stages[s] = stat_of(v);
    if (s + 1 == kStageCount) totals = v;
  }
  for (std::size_t m = 0; m < run.meshes.size(); ++m)
    if (run.meshes[m].role == Role::kMovable) row.vertices += run.meshes[m].positions.size();
  row.before = run.result.before.crossings;
  row.after = run.verified.counts.crossings;
  row.iterations = run.result.iterations;
  row.stalled = run.result.stalled;
  row.max_rel = run.result.displacement.max_over_mean_edge;
  const double edge = movable_mean_edge(run);
  row.mean_rel = edge > 0.0 ? run.result.displacement.mean / edge : 0.0;
  row.edge_change = mean_edge_change(run);
  row.moved = run.result.displacement.moved_vertices;
  row.inside_after = run.verified.counts.inside_vertices;
  for (std::size_t m = 0; m < run.result.quality.size(); ++m) {
    if (run.meshes[m].role != Role::kMovable) continue;
    const QualityStats& q = run.result.quality[m];
    row.stretch = std::max(row.stretch, q.max_stretch);
    row.flips += q.flipped_faces;
    row.within = row.within && within_bounds(q, o.bounds);
  }
  keep_median_history(row, histories, totals);
  if (run.result.clean != (row.after == 0)) {
    notes.push_back(c.name + " (" + method + "): the repair ended " +
                    (run.result.clean ? "clean" : "unresolved") + " but the written files have " +
                    std::to_string(row.after) + " crossings");
  }
  return row;
}

std::string status_of(const Row& r) {
  if (r.after > 0 || r.inside_after > 0) return r.stalled ? "stalled" : "unresolved";
  return r.within ? "clean" : "distorted";
}

nlohmann::ordered_json row_json(const Row& r, bool with_history) {
  nlohmann::ordered_json j;
  j["scene"] = r.scene;
  j["source"] = r.source;
  j["method"] = r.method;
  j["clearance"] = r.clearance;
  j["step"] = r.step;
  j["vertices"] = r.vertices;
  j["crossings_before"] = r.before;
  j["iterations"] = r.iterations;
  j["crossings_after"] = r.after;
  j["status"] = status_of(r);
  j["displacement_max_over_mean_edge"] = r.max_rel;
  j["displacement_mean_over_mean_edge"] = r.mean_rel;
  j["moved_vertices"] = r.moved;
  j["edge_length_change"] = r.edge_change;
  j["inside_after"] = r.inside_after;
  j["max_stretch"] = r.stretch;
  j["flipped_faces"] = r.flips;
  if (with_history) {
    nlohmann::ordered_json stages;
    for (std::size_t s = 0; s < kStageCount; ++s)
      stages[kStages[s]] = {{"best", r.stages[s].best}, {"median", r.stages[s].median}};
    j["timing_ms"] = stages;
    nlohmann::ordered_json history = nlohmann::ordered_json::array();
    for (const IterationRecord& h : r.history) {
      history.push_back({{"iteration", h.iteration}, {"elapsed_ms", h.elapsed_ms},
                         {"crossings", h.crossings}, {"contour_length", h.contour_length}});
    }
    j["history"] = history;
  }
  return j;
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      return line.substr(line.find(':') + 2);
    }
  }
  return "unknown CPU";
}

void print_main_table(const std::vector<Row>& rows) {
  std::printf("%-28s %-6s %7s %6s %4s %8s %8s %8s %8s %8s %8s %8s %19s %6s %6s %8s %8s %8s %7s "
              "%5s  %s\n",
              "scene", "method", "verts", "before", "iter", "load", "detect", "contours",
              "regions", "displace", "write", "verify", "total best/median", "after", "inside",
              "max/edge", "mean/edge", "edge chg", "stretch", "flips", "status");
  for (const Row& r : rows) {
    std::printf("%-28s %-6s %7zu %6zu %4d", r.scene.c_str(), r.method.c_str(), r.vertices, r.before,
                r.iterations);
    for (std::size_t s = 0; s + 1 < kStageCount; ++s) std::printf(" %8.1f", r.stages[s].median);
    std::printf(" %9.1f/%9.1f %6zu %6zu %8.3f %8.3f %8.4f %7.3f %5zu  %s\n",
                r.stages[kStageCount - 1].best, r.stages[kStageCount - 1].median, r.after,
                r.inside_after, r.max_rel, r.mean_rel, r.edge_change, r.stretch, r.flips,
                status_of(r).c_str());
  }
}

void print_accuracy_table(const std::vector<Row>& rows) {
  std::printf("%-28s %-6s %9s %6s %4s %6s %8s %9s %8s %6s\n", "scene", "method", "clearance",
              "step", "iter", "after", "max/edge", "mean/edge", "edge chg", "moved");
  for (const Row& r : rows) {
    std::printf("%-28s %-6s %9.3g %6.3g %4d %6zu %8.3f %9.3f %8.4f %6zu\n", r.scene.c_str(),
                r.method.c_str(), r.clearance, r.step, r.iterations, r.after, r.max_rel,
                r.mean_rel, r.edge_change, r.moved);
  }
}

}  // namespace

int run_bench(const BenchOptions& options) {
  std::vector<std::string> methods;
  if (options.method != "paper") methods.push_back("region");
  if (options.method != "region") methods.push_back("paper");
  const FixOptions defaults;
  ScratchDir scratch;
  std::vector<std::string> notes;
  std::vector<BenchCase> cases = generated_cases(options.quick, scratch.path() / "scenes");
  if (!options.data_dir.empty()) {
    for (BenchCase& c : data_cases(options.data_dir, scratch.path() / "bodies", notes))
      cases.push_back(std::move(c));
  }
  if (!options.plot_dir.empty()) {
    std::error_code ec;
    fs::create_directories(options.plot_dir, ec);
    if (!fs::is_directory(options.plot_dir))
      throw Error(ExitCode::kOutputNotWritten, options.plot_dir, "cannot create the plot folder");
  }
  auto progress = [&](const std::string& what) {
    if (!options.json) std::fprintf(stderr, "bench: %s\n", what.c_str());
  };

  std::vector<Row> rows;
  for (const BenchCase& c : cases) {
    std::vector<HistorySeries> series;
    for (const std::string& method : methods) {
      progress(c.name + " (" + method + ")");
      rows.push_back(run_case(c, method, defaults.clearance, defaults.step, options.repeat,
                              options.threads, scratch.path(), notes));
      series.push_back({method, rows.back().history});
    }
    if (!options.plot_dir.empty()) {
      const fs::path base = fs::path(options.plot_dir) / c.name;
      write_text_file_atomically(base.string() + ".csv", history_csv(series));
      write_text_file_atomically(base.string() + ".svg", history_svg(c.name, series));
    }
  }

  // Accuracy: how far the result moves from the input, for a few clearance and step settings.
  std::vector<Row> accuracy;
  std::vector<std::string> accuracy_scenes = {"sheet_through_sphere"};
  if (!options.quick) accuracy_scenes.push_back("tube_around_body");
  for (const BenchCase& c : cases) {
    if (std::find(accuracy_scenes.begin(), accuracy_scenes.end(), c.name) == accuracy_scenes.end()) continue;
    for (const std::string& method : methods) {
      progress(c.name + " (" + method + ", clearance and step)");
      for (double clearance : {0.02, 0.05, 0.1})
        for (double step : {0.1, 0.25, 0.5})
          accuracy.push_back(run_case(c, method, clearance, step, 1, options.threads, scratch.path(), notes));
    }
  }

  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  if (options.json) {
    nlohmann::ordered_json j;
    j["schema_version"] = kReportSchemaVersion;
    j["untangle_version"] = untangle::untangle_version();
    j["command"] = "bench";
    j["repeat"] = options.repeat;
    j["threads"] = options.threads;
    j["machine"] = {{"cores", cores}, {"cpu", cpu_model()}};
    j["defaults"] = {{"clearance", defaults.clearance}, {"step", defaults.step},
                     {"max_iterations", defaults.max_iterations}};
    nlohmann::ordered_json table = nlohmann::ordered_json::array();
    for (const Row& r : rows) table.push_back(row_json(r, true));
    j["scenes"] = table;
    nlohmann::ordered_json acc = nlohmann::ordered_json::array();
    for (const Row& r : accuracy) acc.push_back(row_json(r, false));
    j["accuracy"] = acc;
    j["notes"] = notes;
    const std::string text = j.dump(2) + "\n";
    std::fwrite(text.data(), 1, text.size(), stdout);
    return 0;
  }
  std::printf("untangle bench: %zu scenes, %d repeats (stage columns: median ms; total: best/median "
              "ms), threads %d, %u cores, %s\n\n",
              cases.size(), options.repeat, options.threads, cores, cpu_model().c_str());
  print_main_table(rows);
  std::printf("\naccuracy: displacement and edge-length change for clearance x step (in mean edge "
              "lengths; step: per-crossing step, of the local edge length)\n\n");
  print_accuracy_table(accuracy);
  if (!notes.empty()) {
    std::printf("\nnotes:\n");
    for (const std::string& n : notes) std::printf("  %s\n", n.c_str());
  }
  if (!options.plot_dir.empty()) {
    std::printf("\nplots: %s/<scene>.svg and .csv (crossings and contour length per iteration "
                "against elapsed ms)\n", options.plot_dir.c_str());
  }
  return 0;
}

}  // namespace untangle::app
