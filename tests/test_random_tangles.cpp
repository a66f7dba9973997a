// Random tangles (issue 5): seeded random scenes of sheets, tubes and closed meshes thrown through
// each other (tests/scenes/random_tangles.h), in general position and snapped to a coarse grid.
//
// On every scene:
// - detection agrees with CGAL: the intersecting triangle pairs of untangle::find_intersections
//   equal CGAL's (tests/cgal_reference.h) in general position. Snapped scenes touch exactly
//   (vertex on face, edge on edge, coplanar overlaps), where CGAL's closed sets count a touch and
//   the symbolic perturbation decides each touch one way: there our pairs must be a subset of
//   CGAL's (a perturbation cannot make disjoint closed triangles meet) and every pair only CGAL
//   reports must be such a degenerate contact (a transversal crossing survives any perturbation);
// - `untangle fix` never claims a false "clean": exit 0 means the written files, read back with
//   the obstacles, have no crossing, and CGAL finds no pair on them that is more than a degenerate
//   touch; exit 5 means the report says "unresolved" and lists the contours that an independent
//   detection on the written files finds. Any other exit code fails. The CGAL rule above is checked
//   on the written files too, as are the report's counts of the input, that only positions change
//   and that no two vertices of a written mesh land on one point (they would weld on reading).
//
// Size: UNTANGLE_RANDOM_TANGLES=N runs seeds S .. S+N-1 (default 50, about ten seconds in a
// Release build on a loaded two-core machine), UNTANGLE_RANDOM_TANGLES_SEED=S sets the first seed
// (default 0). A failure names its seed; `UNTANGLE_RANDOM_TANGLES=1 UNTANGLE_RANDOM_TANGLES_SEED=S`
// re-runs just that scene, and UNTANGLE_RANDOM_TANGLES_KEEP=DIR keeps its files (input, outputs,
// report) in DIR/random_tangle_<seed>/ instead of a temporary folder. A summary line (clean and
// unresolved scenes, crossings before and after, time per case) is printed, never asserted.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cgal_reference.h"
#include "scene_files.h"
#include "scenes/random_tangles.h"
#include "test_support.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/read_meshes.h"

namespace untangle {
namespace {

using cgal_reference::TrianglePair;
using testing::quote;
using testing::read_text;
using testing::run_cli;
using testing::TempDir;

constexpr std::uint64_t kDefaultSeeds = 50;

// A non-negative integer from the environment, or `fallback` when unset. Garbage is an error
// (a typo must not silently run the default).
std::uint64_t env_count(const char* name, std::uint64_t fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text, &end, 10);
  if (*end != '\0' || text[0] == '-') {
    ADD_FAILURE() << name << "=" << text << " is not a non-negative integer; using " << fallback;
    return fallback;
  }
  return value;
}

// Seeds of the long run that once failed, run by default too: fix put two vertices of one mesh
// on one point (closest-point and mirrored moves on grid-snapped input); 793 and 1069 wrote a
// state with self crossings the input did not have (numbered by the written positions, the
// verdict decided a degeneracy the other way than the repair): now judged as check judges it and
// reverted to the input.
constexpr std::uint64_t kRegressionSeeds[] = {247, 793, 1069, 1329, 1367, 2450, 2546};

std::vector<std::uint64_t> seeds_to_run() {
  const bool chosen = std::getenv("UNTANGLE_RANDOM_TANGLES_SEED") != nullptr ||
                      std::getenv("UNTANGLE_RANDOM_TANGLES") != nullptr;
  const std::uint64_t first = env_count("UNTANGLE_RANDOM_TANGLES_SEED", 0);
  const std::uint64_t count = env_count("UNTANGLE_RANDOM_TANGLES", kDefaultSeeds);
  std::vector<std::uint64_t> seeds;
  for (std::uint64_t s = first; s < first + count; ++s) seeds.push_back(s);
  if (!chosen)
    for (std::uint64_t s : kRegressionSeeds) seeds.push_back(s);
  return seeds;
}

// ---- detection against CGAL ----

std::string describe_pair(const std::vector<Mesh>& meshes, const TrianglePair& p) {
  std::ostringstream out;
  out.precision(17);
  out << "  (mesh " << p[0] << " tri " << p[1] << ", mesh " << p[2] << " tri " << p[3] << "):";
  for (int side = 0; side < 2; ++side) {
    const Mesh& m = meshes[p[2 * side]];
    out << (side == 0 ? " A" : " B");
    for (std::uint32_t v : m.triangles[p[2 * side + 1]]) {
      const Vec3& q = m.positions[v];
      out << " (" << q[0] << ", " << q[1] << ", " << q[2] << ")";
    }
  }
  return out.str() + "\n";
}

struct CgalComparison {
  std::string problem;        // empty when the rule holds
  std::size_t only_cgal = 0;  // pairs CGAL reports and the perturbation leaves apart
  // CGAL pairs that are more than a degenerate touch, leaving out pairs of two obstacle triangles
  // (fix cannot change those): on a clean result there must be none.
  std::size_t solid_non_obstacle = 0;
};

// Compares find_intersections' triangle pairs on `meshes` with CGAL's. `general_position`: the
// pairs must be equal. Otherwise ours must be a subset of CGAL's and every pair only CGAL reports a
// degenerate contact (see the header comment).
CgalComparison compare_with_cgal(const std::vector<Mesh>& meshes, bool general_position) {
  CgalComparison result;
  std::vector<cgal_reference::ReferenceMesh> reference;
  try {
    reference = cgal_reference::to_reference_meshes(meshes);
  } catch (const std::exception& e) {  // a non-manifold edge: CGAL cannot represent the mesh
    result.problem = e.what();
    return result;
  }
  for (std::size_t i = 0; i < reference.size(); ++i) {
    if (!reference[i].degenerate.empty()) {
      result.problem = "mesh " + std::to_string(i) + " has " +
                       std::to_string(reference[i].degenerate.size()) +
                       " degenerate triangles; CGAL's routines leave them out, so no comparison";
      return result;
    }
  }
  const std::vector<TrianglePair> cgal = cgal_reference::triangle_pairs(reference);
  const std::vector<TrianglePair> ours = find_intersections(meshes).triangle_pairs;
  std::vector<TrianglePair> only_ours, only_cgal;
  std::set_difference(ours.begin(), ours.end(), cgal.begin(), cgal.end(),
                      std::back_inserter(only_ours));
  std::set_difference(cgal.begin(), cgal.end(), ours.begin(), ours.end(),
                      std::back_inserter(only_cgal));
  result.only_cgal = only_cgal.size();
  std::vector<TrianglePair> not_degenerate_only_cgal;
  for (const TrianglePair& p : cgal) {
    if (cgal_reference::degenerate_contact(meshes[p[0]], p[1], meshes[p[2]], p[3])) continue;
    const bool both_obstacles =
        meshes[p[0]].role == Role::kObstacle && meshes[p[2]].role == Role::kObstacle;
    if (!both_obstacles) ++result.solid_non_obstacle;
    if (std::binary_search(only_cgal.begin(), only_cgal.end(), p)) {
      not_degenerate_only_cgal.push_back(p);
    }
  }
  std::ostringstream problem;
  if (!only_ours.empty()) {
    problem << only_ours.size() << " of our pairs are disjoint as closed triangles (CGAL), first:\n"
            << describe_pair(meshes, only_ours.front());
  }
  if (general_position && !only_cgal.empty()) {
    problem << only_cgal.size() << " pairs only CGAL finds in a scene in general position, first:\n"
            << describe_pair(meshes, only_cgal.front());
  } else if (!not_degenerate_only_cgal.empty()) {
    problem << not_degenerate_only_cgal.size()
            << " pairs only CGAL finds cross transversally (no degenerate contact), first:\n"
            << describe_pair(meshes, not_degenerate_only_cgal.front());
  }
  result.problem = problem.str();
  return result;
}

TEST(RandomTangles, DetectionAgreesWithCgal) {
  std::size_t cases = 0, pairs_only_cgal = 0;
  for (std::uint64_t seed : seeds_to_run()) {
    const scenes::RandomTangle tangle = scenes::random_tangle(seed);
    SCOPED_TRACE(tangle.description);
    const CgalComparison comparison =
        compare_with_cgal(scenes::scene_meshes(tangle.scene), !tangle.snapped);
    EXPECT_EQ(comparison.problem, "");
    pairs_only_cgal += comparison.only_cgal;
    ++cases;
  }
  std::cout << "[ random tangles ] " << cases << " scenes agree with CGAL; " << pairs_only_cgal
            << " pairs only CGAL reports, all degenerate touches of snapped scenes\n";
}

// ---- fix: clean on the written files, or exit 5 with the remaining contours ----

std::vector<Mesh> read_all(const std::vector<std::string>& paths, Role role) {
  std::vector<Mesh> meshes;
  for (const auto& path : paths) {
    for (auto& m : read_meshes(path, role)) meshes.push_back(std::move(m));
  }
  return meshes;
}

Intersections detect_as_fix_does(const std::vector<Mesh>& meshes) {
  DetectOptions options;
  options.skip_obstacle_pairs = true;  // fix can change nothing among obstacles
  return find_intersections(meshes, options);
}

// (meshes, types, crossings) of each contour, in order: what the report lists about it.
using ContourKey = std::tuple<std::uint32_t, std::uint32_t, std::string, std::string, std::size_t>;

std::vector<ContourKey> contour_keys(const Intersections& found) {
  std::vector<ContourKey> keys;
  for (const Contour& c : found.contours) {
    keys.emplace_back(c.tracks[0].mesh, c.tracks[1].mesh, to_string(c.tracks[0].type),
                      to_string(c.tracks[1].type), c.crossings.size());
  }
  return keys;
}

std::vector<ContourKey> contour_keys(const nlohmann::json& contours) {
  std::vector<ContourKey> keys;
  for (const auto& c : contours) {
    keys.emplace_back(c["meshes"][0].get<std::uint32_t>(), c["meshes"][1].get<std::uint32_t>(),
                      c["types"][0].get<std::string>(), c["types"][1].get<std::string>(),
                      c["crossings"].get<std::size_t>());
  }
  return keys;
}

// "" when every vertex of `mesh` has a position of its own, else the first two that share one.
// The generated meshes have no such pair, so in a written mesh it means fix put two vertices on one
// point: reading welds them, and the file's surface is no longer the input's (an edge collapsed,
// or two parts of the surface pinched together).
std::string coincident_vertices(const Mesh& mesh) {
  std::map<Vec3, std::uint32_t> vertex_at;
  for (std::uint32_t v = 0; v < mesh.positions.size(); ++v) {
    const auto [it, inserted] = vertex_at.emplace(mesh.positions[v], v);
    if (!inserted) {
      std::ostringstream out;
      out.precision(17);
      const Vec3& p = mesh.positions[v];
      out << "vertices " << it->second << " and " << v << " both at (" << p[0] << ", " << p[1]
          << ", " << p[2] << ")";
      return out.str();
    }
  }
  return "";
}

// Crossings by what they join: [0] a movable mesh and an obstacle, [1] a mesh and itself, [2] two
// movable meshes; [3] movable vertices inside an obstacle.
std::array<std::size_t, 4> crossing_kinds(const std::vector<Mesh>& meshes,
                                          const Intersections& found) {
  std::array<std::size_t, 4> kinds{};
  for (const Crossing& x : found.crossings) {
    if (meshes[x.edge_mesh].role == Role::kObstacle || meshes[x.face_mesh].role == Role::kObstacle)
      ++kinds[0];
    else if (x.edge_mesh == x.face_mesh)
      ++kinds[1];
    else
      ++kinds[2];
  }
  kinds[3] = found.counts.inside_vertices;
  return kinds;
}

// The largest displacement of a vertex of `written[m]` from `input[m]`, in diagonals of the input
// mesh's bounding box, over the movable meshes.
double largest_move_over_diagonal(const std::vector<Mesh>& input, const std::vector<Mesh>& written) {
  double largest = 0.0;
  for (std::size_t m = 0; m < written.size(); ++m) {
    if (input[m].role != Role::kMovable || input[m].positions.empty()) continue;
    Vec3 lo = input[m].positions[0], hi = lo;
    for (const Vec3& p : input[m].positions)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    const double diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    for (std::size_t v = 0; v < written[m].positions.size(); ++v) {
      const Vec3& a = input[m].positions[v];
      const Vec3& b = written[m].positions[v];
      largest = std::max(largest, std::hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]) / diagonal);
    }
  }
  return largest;
}

struct Tally {
  std::size_t cases = 0, tangled = 0, clean = 0, unresolved = 0, reverted = 0;
  std::size_t crossings_before = 0, crossings_after = 0;
  double seconds = 0.0;
};

// Runs fix on one scene and checks the property; adds to `tally`.
void check_fix(const scenes::RandomTangle& tangle, Tally& tally) {
  SCOPED_TRACE(tangle.description);
  const auto start = std::chrono::steady_clock::now();
  // The scene, outputs and report go to a temporary folder, or are kept for a closer look.
  TempDir temp;
  const char* keep = std::getenv("UNTANGLE_RANDOM_TANGLES_KEEP");
  const std::string folder = keep != nullptr && *keep != '\0'
                                 ? std::string(keep) + "/" + tangle.scene.name
                                 : temp.path().string();
  const testing::SceneFiles files = testing::write_scene(tangle.scene, folder);
  const std::string out_dir = folder + "/out", report_path = folder + "/report.json";
  std::filesystem::create_directories(out_dir);
  const auto r = run_cli("fix" + files.inputs_args() + " --output-dir " + quote(out_dir) +
                         " --report " + quote(report_path) + " --overwrite -q");
  ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 5 || r.exit_code == 6)
      << "exit " << r.exit_code << "\nstdout:\n" << r.out << "stderr:\n" << r.err;
  const auto report = nlohmann::json::parse(read_text(report_path));

  // The input as the CLI saw it.
  std::vector<Mesh> input = read_all(files.movable, Role::kMovable);
  const std::vector<Mesh> obstacles = read_all(files.obstacles, Role::kObstacle);
  input.insert(input.end(), obstacles.begin(), obstacles.end());
  const Intersections found_before = detect_as_fix_does(input);
  const std::size_t before = found_before.counts.crossings;
  EXPECT_EQ(report["before"]["crossings"].get<std::size_t>(), before);

  // The written files, read back, with the obstacles.
  std::vector<std::string> outputs;
  for (const auto& in : files.movable) {
    outputs.push_back(out_dir + "/" + std::filesystem::path(in).filename().string());
  }
  std::vector<Mesh> written = read_all(outputs, Role::kMovable);
  ASSERT_EQ(written.size(), files.movable.size());
  bool pinched = false;
  for (std::size_t i = 0; i < written.size(); ++i) {  // fix moves vertices and nothing else
    EXPECT_EQ(written[i].triangles, input[i].triangles) << outputs[i];
    EXPECT_EQ(written[i].positions.size(), input[i].positions.size()) << outputs[i];
    const std::string coincident = coincident_vertices(written[i]);
    EXPECT_EQ(coincident, "") << "fix wrote " << outputs[i]
                              << " with two vertices at one position (they weld on reading)";
    pinched = pinched || !coincident.empty();
  }
  written.insert(written.end(), obstacles.begin(), obstacles.end());
  const Intersections after = detect_as_fix_does(written);
  // CGAL's Surface_mesh cannot take the welded topology of a pinched mesh (degenerate triangles,
  // non-manifold edges); our detection on the written files still decides the property below.
  const CgalComparison cgal = pinched ? CgalComparison{} : compare_with_cgal(written, false);
  EXPECT_EQ(cgal.problem, "") << "on the written files";

  const auto& after_report = report["after"];
  EXPECT_EQ(after_report["crossings"].get<std::size_t>(), after.counts.crossings);
  EXPECT_EQ(after_report["contours"].get<std::size_t>(), report["contours"].size());
  EXPECT_EQ(contour_keys(report["contours"]), contour_keys(after));
  if (testing::intersection_free(r.exit_code)) {
    EXPECT_EQ(report["status"].get<std::string>(), r.exit_code == 0 ? "clean" : "distorted");
    EXPECT_EQ(after.counts.crossings, 0u) << "exit 0, but the written files still cross";
    EXPECT_EQ(after.counts.inside_vertices, 0u) << "exit 0, but vertices lie inside the obstacle";
    EXPECT_EQ(cgal.solid_non_obstacle, 0u)
        << "exit 0, but CGAL finds triangles crossing transversally on the written files";
    ++tally.clean;
  } else {
    EXPECT_EQ(report["status"].get<std::string>(), "unresolved");
    // Exit 5 for vertices left inside the obstacle (winding number), or for crossings.
    EXPECT_GT(after.counts.crossings + after.counts.inside_vertices, 0u)
        << "exit 5, but the written files neither cross nor lie inside the obstacle";
    if (after.counts.crossings > 0) {
      EXPECT_FALSE(report["contours"].empty()) << "exit 5 without a remaining contour listed";
    }
    // Never worse than the input: no kind of crossing and no inside count grows, and no vertex
    // moves beyond FixOptions::max_written_move diagonals of its mesh.
    const auto kinds_before = crossing_kinds(input, found_before);
    const auto kinds_after = crossing_kinds(written, after);
    const char* names[] = {"against obstacles", "self", "between movable meshes", "inside"};
    for (int k = 0; k < 4; ++k) {
      EXPECT_LE(kinds_after[k], kinds_before[k])
          << "unresolved, and the written files have more crossings " << names[k]
          << " than the input";
    }
    EXPECT_LE(largest_move_over_diagonal(input, written), FixOptions{}.max_written_move)
        << "unresolved, and a vertex moved further than max_written_move diagonals";
    if (report["reverted"].get<bool>()) {
      EXPECT_EQ(largest_move_over_diagonal(input, written), 0.0) << "reverted, but moved";
      ++tally.reverted;
    }
    ++tally.unresolved;
  }
  ++tally.cases;
  tally.tangled += before > 0;
  tally.crossings_before += before;
  tally.crossings_after += after.counts.crossings;
  tally.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

TEST(RandomTangles, FixIsCleanOrListsWhatRemains) {
  Tally tally;
  for (std::uint64_t seed : seeds_to_run()) {
    check_fix(scenes::random_tangle(seed), tally);
  }
  std::printf("[ random tangles ] %zu scenes (%zu tangled): %zu clean, %zu unresolved (exit 5, "
              "%zu of them reverted to the input); crossings %zu before, %zu after; %.2f s per "
              "case\n",
              tally.cases, tally.tangled, tally.clean, tally.unresolved, tally.reverted,
              tally.crossings_before, tally.crossings_after,
              tally.cases == 0 ? 0.0 : tally.seconds / tally.cases);
  RecordProperty("clean", static_cast<int>(tally.clean));
  RecordProperty("unresolved", static_cast<int>(tally.unresolved));
}

// The stages alone: a continuation or a layering kept (its history all stage 4 or 5), or pieces
// moved whole before a last repair (which resolve seed 269), would hide them.
FixOptions stages_only() {
  FixOptions options;
  options.continuation = false;
  options.layering = false;
  options.piece_moves = false;
  return options;
}

// Scenes without a self contour whose first stage stalls: the second stage, with only measured
// steps and relaxed neighbourhoods on the contours between movable meshes, resolves them. (The
// second stage once ran only for self contours; 102, 115 and 170 then ended with 12, 9 and 14
// crossings. Seed 107 replaced 106 when the meshes' canonical order became topology only; 104 and
// 118 replaced 102 and 115, which the first stage now resolves, when the vertex order became free
// of half turns: of seeds 0 to 299, 137 show the second stage this way.)
TEST(RandomTangles, SecondStageResolvesWhatTheFirstLeaves) {
  for (std::uint64_t seed : {104u, 107u, 118u, 170u}) {
    const scenes::RandomTangle tangle = scenes::random_tangle(seed);
    SCOPED_TRACE(tangle.description);
    std::vector<Mesh> meshes = scenes::scene_meshes(tangle.scene);
    const Intersections before = detect_as_fix_does(meshes);
    ASSERT_GT(before.counts.crossings, 0u);
    ASSERT_EQ(before.counts.pairs_self, 0u);
    const FixResult result = fix_meshes(meshes, stages_only());
    EXPECT_TRUE(result.clean);
    EXPECT_EQ(detect_as_fix_does(meshes).counts.crossings, 0u);
    std::size_t first_best = before.counts.crossings;
    bool second = false;
    for (const IterationRecord& r : result.history) {
      if (r.stage == 1) first_best = std::min(first_best, r.crossings);
      second = second || r.stage == 2;
    }
    EXPECT_TRUE(second) << "the first stage alone resolves it: the test no longer shows the second";
    EXPECT_GT(first_best, 0u);
  }
}

// Scenes where both stages stall: the third starts from the best state either reached, with the
// second stage's rules, and resolves them. Its first entry is that best count; before the third
// stage 45, 79 and 223 ended with 65, 3 and 10 crossings. (Seed 52 replaced 163 when the meshes'
// canonical order became topology only. When the vertex order became free of half turns 45 and 223
// no longer needed the third stage; 4, 5, 7 and 48 are the first of the 10 seeds below 300 that
// do.)
TEST(RandomTangles, ThirdStageResolvesFromTheBestState) {
  for (std::uint64_t seed : {4u, 5u, 7u, 48u}) {
    const scenes::RandomTangle tangle = scenes::random_tangle(seed);
    SCOPED_TRACE(tangle.description);
    std::vector<Mesh> meshes = scenes::scene_meshes(tangle.scene);
    const FixResult result = fix_meshes(meshes, stages_only());
    EXPECT_TRUE(result.clean);
    EXPECT_EQ(detect_as_fix_does(meshes).counts.crossings, 0u);
    std::size_t best = static_cast<std::size_t>(-1);
    const IterationRecord* third = nullptr;
    for (const IterationRecord& r : result.history) {
      if (r.stage == 3) {
        if (third == nullptr) third = &r;
        continue;
      }
      EXPECT_TRUE(third == nullptr) << "stages come in order";
      best = std::min(best, r.crossings);
    }
    ASSERT_NE(third, nullptr) << "the first two stages resolve it: the test no longer shows the third";
    EXPECT_GT(best, 0u);
    EXPECT_EQ(third->crossings, best) << "the third stage starts from the best state";
  }
}

// An unresolved run relaxes the state it writes around what is left (DESIGN §5, *Relaxation*):
// against the same run with the relaxation off, never a crossing or inside vertex more, never a
// turned face more, and the worst edge nearer its input length. Before, seeds 42, 58 and 269 wrote
// the moves' shape: largest edge ratios 9.41, 4.52 and 3.10 (then 6.08, 2.87 and 1.81). It does
// not hold for every unresolved run: of 17 among seeds 0 to 299 (stages only, one thread) it
// holds for 3 (these); 10 keep their worst edge and flips (the worst edge lies outside what is
// relaxed, or nothing was), 2 lose flips only, and 2 get worse (19: two turned faces more; 155: a
// worst edge of 3.99 where the moves left 1.00). With vertices sorted by position, before
// 2026-12-06: 7, 6, 2, and 2 (75: a turned face more; 116: a worse edge, four flips fewer).
TEST(RandomTangles, UnresolvedRunRelaxesWhatItWrites) {
  for (std::uint64_t seed : {65u, 269u, 299u}) {
    const scenes::RandomTangle tangle = scenes::random_tangle(seed);
    SCOPED_TRACE(tangle.description);
    std::vector<Mesh> relaxed = scenes::scene_meshes(tangle.scene), unrelaxed = relaxed;
    FixOptions options = stages_only();  // the layering resolves seed 42
    options.threads = 1;
    options.retries = 2;  // as measured (four retries, the default since 2026-12-06, resolve 65)
    const FixResult with = fix_meshes(relaxed, options);
    options.relax = false;
    const FixResult without = fix_meshes(unrelaxed, options);
    ASSERT_FALSE(without.clean) << "resolved: the test no longer shows an unresolved run";
    ASSERT_FALSE(with.reverted);
    EXPECT_GT(with.relax_sweeps, 0);
    const Intersections a = detect_as_fix_does(relaxed), b = detect_as_fix_does(unrelaxed);
    EXPECT_LE(a.counts.crossings + a.counts.inside_vertices,
              b.counts.crossings + b.counts.inside_vertices);
    double stretch_with = 1.0, stretch_without = 1.0;
    std::size_t flips_with = 0, flips_without = 0;
    for (const QualityStats& q : with.quality) {
      stretch_with = std::max(stretch_with, q.max_stretch);
      flips_with += q.flipped_faces;
    }
    for (const QualityStats& q : without.quality) {
      stretch_without = std::max(stretch_without, q.max_stretch);
      flips_without += q.flipped_faces;
    }
    EXPECT_LE(flips_with, flips_without);
    EXPECT_LT(stretch_with, stretch_without);
  }
}

// A continuation that cannot clean a step gives up after four unresolved repairs in a row (DESIGN
// §5, *Retries and the continuation*): seed 299 is clean but beyond the bounds (a flipped face),
// so the continuation runs; its first step and the three halvings after it end unresolved. Before
// the rule it ran 14 repairs, none clean, and its time doubled the run's. Given up, it is not
// kept and the obstacles are back: the positions are the same as without it.
TEST(RandomTangles, ContinuationGivesUpAfterFourUnresolvedRepairs) {
  const scenes::RandomTangle tangle = scenes::random_tangle(299);
  SCOPED_TRACE(tangle.description);
  std::vector<Mesh> with = scenes::scene_meshes(tangle.scene), without = with;
  FixOptions options;
  options.threads = 1;
  options.continuation = true;
  const FixResult a = fix_meshes(with, options);
  options.continuation = false;
  const FixResult b = fix_meshes(without, options);
  const ContinuationRecord& c = a.continuation;
  ASSERT_TRUE(c.ran) << "no continuation: the test no longer tests";
  EXPECT_TRUE(c.gave_up);
  EXPECT_FALSE(c.kept);
  ASSERT_EQ(c.runs.size(), 4u);
  for (const ContinuationStep& run : c.runs) EXPECT_FALSE(run.clean);
  EXPECT_EQ(c.runs.front().shrink, 1.0);
  EXPECT_EQ(a.clean, b.clean);
  ASSERT_EQ(with.size(), without.size());
  for (std::size_t m = 0; m < with.size(); ++m) EXPECT_EQ(with[m].positions, without[m].positions);
}

// ---- the generator ----

TEST(RandomTangles, SameSeedSameScene) {
  for (std::uint64_t seed : {0u, 7u, 123456789u}) {
    const scenes::RandomTangle a = scenes::random_tangle(seed), b = scenes::random_tangle(seed);
    const std::vector<Mesh> ma = scenes::scene_meshes(a.scene), mb = scenes::scene_meshes(b.scene);
    ASSERT_EQ(ma.size(), mb.size()) << seed;
    for (std::size_t i = 0; i < ma.size(); ++i) {
      EXPECT_EQ(ma[i].positions, mb[i].positions) << seed;  // bit for bit
      EXPECT_EQ(ma[i].triangles, mb[i].triangles) << seed;
    }
    EXPECT_EQ(a.description, b.description);
  }
  EXPECT_NE(scenes::random_tangle(1).description, scenes::random_tangle(2).description);
}

// The default seeds exercise what the issue asks for: every kind of mesh, scenes with and without
// an obstacle, 2 to 4 meshes, snapped scenes with exact degenerate touches (some of which the
// perturbation leaves apart), and tangled scenes.
TEST(RandomTangles, DefaultSeedsCoverTheIntendedCases) {
  std::size_t with_obstacle = 0, all_movable = 0, snapped = 0, degenerate_touches = 0, tangled = 0;
  std::size_t perturbed_apart = 0;  // pairs CGAL reports and the perturbation leaves apart
  std::array<std::size_t, 5> mesh_counts{};
  std::string descriptions;
  for (std::uint64_t seed = 0; seed < kDefaultSeeds; ++seed) {
    const scenes::RandomTangle tangle = scenes::random_tangle(seed);
    descriptions += tangle.description + "\n";
    const std::vector<Mesh> meshes = scenes::scene_meshes(tangle.scene);
    ++mesh_counts[std::min<std::size_t>(meshes.size(), 4)];
    (tangle.scene.obstacles.empty() ? all_movable : with_obstacle) += 1;
    EXPECT_LE(tangle.scene.obstacles.size(), 1u);
    const std::vector<TrianglePair> pairs = cgal_reference::triangle_pairs(meshes);
    tangled += !pairs.empty();
    if (!tangle.snapped) continue;
    ++snapped;
    for (const TrianglePair& p : pairs) {
      degenerate_touches +=
          cgal_reference::degenerate_contact(meshes[p[0]], p[1], meshes[p[2]], p[3]);
    }
    const std::vector<TrianglePair> ours = find_intersections(meshes).triangle_pairs;
    for (const TrianglePair& p : pairs) {
      perturbed_apart += !std::binary_search(ours.begin(), ours.end(), p);
    }
  }
  SCOPED_TRACE(descriptions);
  for (const char* kind : {"sheet", "tube", "sphere", "box", "torus"}) {
    EXPECT_NE(descriptions.find(kind), std::string::npos) << "no " << kind;
  }
  EXPECT_GT(with_obstacle, 0u);
  EXPECT_GT(all_movable, 0u);
  EXPECT_GT(mesh_counts[2], 0u);
  EXPECT_GT(mesh_counts[3] + mesh_counts[4], 0u);
  EXPECT_GT(snapped, 0u);
  EXPECT_GT(degenerate_touches, 0u) << "snapped scenes without a single exact touch";
  EXPECT_GT(perturbed_apart, 0u) << "no touch the perturbation resolves as apart: the subset rule "
                                    "of DetectionAgreesWithCgal is never exercised";
  EXPECT_GT(tangled, kDefaultSeeds / 2) << "most scenes should start tangled";
}

}  // namespace
}  // namespace untangle
