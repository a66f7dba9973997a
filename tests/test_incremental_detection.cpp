// Incremental re-detection (issue 6): after some vertices move, update_crossings on the refitted
// or rebuilt hierarchies gives exactly what a full detect_crossings gives on the new positions.
// Measured moves (issue 4): MeasuredMoves' count of a move equals the change of a full detection.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "detect/detect_crossings.h"
#include "detect/pair_list.h"
#include "detect/triangle_bvh.h"
#include "resolve/measured_move.h"
#include "scenes/scenes.h"
#include "topology/scene_topology.h"

namespace untangle {
namespace {

// Crossings as comparable tuples (the point included, bit for bit).
void expect_same(const CrossingSet& got, const CrossingSet& want, const std::string& where) {
  ASSERT_EQ(got.items.size(), want.items.size()) << where;
  for (std::size_t i = 0; i < got.items.size(); ++i) {
    EXPECT_EQ(got.items[i].edge, want.items[i].edge) << where << " #" << i;
    EXPECT_EQ(got.items[i].face, want.items[i].face) << where << " #" << i;
    EXPECT_EQ(got.items[i].point, want.items[i].point) << where << " #" << i;
  }
}

// Moves a random subset of the movable vertices (a random patch grown from a seed, or scattered
// vertices) by a random offset up to `reach`; with `snap`, new coordinates are rounded to a grid
// of 1/64 so exact degeneracies (vertex on face, coplanar pairs) arise.
std::vector<std::uint8_t> random_moves(SceneTopology& topo, const std::vector<bool>& fixed,
                                       std::mt19937& random, double reach, bool snap) {
  const std::size_t nv = topo.points.size();
  std::vector<std::uint8_t> moved(nv, 0);
  auto unit = [&] { return static_cast<double>(random() % 2001) / 1000.0 - 1.0; };
  const bool patch = random() % 2 == 0;
  std::vector<std::uint32_t> chosen;
  if (patch) {
    std::uint32_t seed = static_cast<std::uint32_t>(random() % nv);
    for (int tries = 0; tries < 100 && fixed[topo.vertex_mesh[seed]]; ++tries)
      seed = static_cast<std::uint32_t>(random() % nv);
    if (fixed[topo.vertex_mesh[seed]]) return moved;
    chosen.push_back(seed);
    moved[seed] = 1;
    const std::size_t size = 1 + random() % 60;
    for (std::size_t i = 0; i < chosen.size() && chosen.size() < size; ++i) {
      const std::uint32_t v = chosen[i];
      for (std::uint32_t k = topo.vertex_edge_begin[v]; k < topo.vertex_edge_begin[v + 1]; ++k) {
        const auto& e = topo.edges[topo.vertex_edges[k]];
        const std::uint32_t w = e[0] == v ? e[1] : e[0];
        if (!moved[w] && chosen.size() < size) {
          moved[w] = 1;
          chosen.push_back(w);
        }
      }
    }
  } else {
    const std::size_t count = 1 + random() % 40;
    for (std::size_t i = 0; i < count; ++i) {
      const std::uint32_t v = static_cast<std::uint32_t>(random() % nv);
      if (fixed[topo.vertex_mesh[v]] || moved[v]) continue;
      moved[v] = 1;
      chosen.push_back(v);
    }
  }
  const Vec3 offset{unit() * reach, unit() * reach, unit() * reach};
  for (std::uint32_t v : chosen) {
    for (int k = 0; k < 3; ++k) {
      double x = topo.points[v][k] + offset[k] + 0.1 * reach * unit();
      if (snap) x = std::round(x * 64.0) / 64.0;
      topo.points[v][k] = x;
    }
  }
  return moved;
}

struct DetectSetup {
  const char* name;
  bool self_pairs;
  bool skip_obstacles;
  bool obstacle_tree;  // the skipped meshes' tree given once (as fix does)
};

// A scene's topology and the detection settings of a setup (the obstacles' tree, when given once,
// kept here).
struct SetUp {
  SceneTopology topo;
  DetectSettings settings;
  std::vector<bool> fixed;  // per mesh: an obstacle
  std::unique_ptr<TriangleBvh> obstacle_tree;
};

std::unique_ptr<SetUp> set_up(const scenes::Scene& scene, const DetectSetup& setup) {
  auto out = std::make_unique<SetUp>();
  const std::vector<Mesh> meshes = scenes::scene_meshes(scene);
  out->topo = build_topology(meshes);
  out->settings.self_pairs = setup.self_pairs;
  for (const Mesh& m : meshes) out->fixed.push_back(m.role == Role::kObstacle);
  if (setup.skip_obstacles) {
    out->settings.skip_among = out->fixed;
    if (setup.obstacle_tree) {
      out->obstacle_tree = std::make_unique<TriangleBvh>(out->topo, out->fixed);
      out->settings.skipped_bvh = out->obstacle_tree.get();
    }
  }
  return out;
}

void run_rounds(const scenes::Scene& scene, const DetectSetup& setup, std::uint32_t seed) {
  const std::unique_ptr<SetUp> up = set_up(scene, setup);
  SceneTopology& topo = up->topo;
  const DetectSettings& settings = up->settings;
  const std::vector<bool>& fixed = up->fixed;
  SceneHierarchy hierarchy(topo, settings);
  CrossingSet current = detect_crossings(topo, settings);
  std::mt19937 random(seed);
  const double size = 0.1;
  for (int round = 0; round < 25; ++round) {
    const bool snap = round % 3 == 2;
    const std::vector<std::uint8_t> moved = random_moves(topo, fixed, random, size, snap);
    hierarchy.update(topo, moved);
    current = update_crossings(topo, settings, hierarchy, current, moved);
    const CrossingSet full = detect_crossings(topo, settings);
    expect_same(current, full,
                scene.name + " " + setup.name + " round " + std::to_string(round));
    if (::testing::Test::HasFailure()) return;
  }
}

constexpr DetectSetup kSetups[] = {{"all pairs", true, false, false},
                             {"no self pairs", false, false, false},
                             {"obstacles skipped", true, true, false},
                             {"obstacles skipped, one tree", true, true, true}};

class IncrementalDetection : public ::testing::TestWithParam<std::string> {};

TEST_P(IncrementalDetection, EqualsFullDetectionAfterRandomMoves) {
  for (const auto& scene : scenes::named_scenes()) {
    if (scene.name != GetParam()) continue;
    std::uint32_t seed = 7;
    for (const DetectSetup& setup : kSetups) run_rounds(scene, setup, seed++);
    return;
  }
  FAIL() << "no scene " << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Scenes, IncrementalDetection,
                         ::testing::Values("sheet_through_sphere", "sheets_corner", "folded_sheet",
                                           "tube_around_body", "garment_four_loops",
                                           "sheet_on_spikes"),
                         [](const auto& info) { return info.param; });

// The relaxation's list of candidate pairs (pair_list.h): a part of the movable vertices moves
// round after round, by less than the list's reach, by about it and far beyond it (the listed
// triangles at the corners that went beyond it are listed again); the update over the list gives
// exactly what a full detection gives.
void run_listed_rounds(const scenes::Scene& scene, const DetectSetup& setup, std::uint32_t seed) {
  const std::unique_ptr<SetUp> up = set_up(scene, setup);
  SceneTopology& topo = up->topo;
  const DetectSettings& settings = up->settings;
  const std::vector<bool>& fixed = up->fixed;
  std::mt19937 random(seed);
  // The part: a patch grown over the edges from a movable seed, as the relaxation's rings grow.
  std::vector<std::uint8_t> in_part(topo.points.size(), 0);
  std::vector<std::uint32_t> part;
  for (int tries = 0; tries < 100 && part.empty(); ++tries) {
    const auto v = static_cast<std::uint32_t>(random() % topo.points.size());
    if (!fixed[topo.vertex_mesh[v]]) part.push_back(v), in_part[v] = 1;
  }
  ASSERT_FALSE(part.empty()) << scene.name;
  for (std::size_t i = 0; i < part.size() && part.size() < 400; ++i)
    for (std::uint32_t k = topo.vertex_edge_begin[part[i]]; k < topo.vertex_edge_begin[part[i] + 1];
         ++k) {
      const std::uint32_t w = topo.vertex_neighbors[k];
      if (!in_part[w] && !fixed[topo.vertex_mesh[w]]) part.push_back(w), in_part[w] = 1;
    }
  std::vector<std::uint32_t> listed;
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
    for (std::uint32_t v : topo.tris[t])
      if (in_part[v]) {
        listed.push_back(t);
        break;
      }
  const double reach = 0.02;
  PairList list(listed, reach);
  SceneHierarchy hierarchy(topo, settings);
  CrossingSet current = detect_crossings(topo, settings);
  auto unit = [&] { return static_cast<double>(random() % 2001) / 1000.0 - 1.0; };
  std::size_t refreshed_rounds = 0;
  for (int round = 0; round < 30; ++round) {
    // Within the reach, about it, or far beyond it; every third round on a grid of 1/64.
    const double amount = reach * (round % 3 == 0 ? 0.4 : round % 3 == 1 ? 1.3 : 6.0);
    const bool snap = round % 4 == 3;
    std::vector<std::uint8_t> moved(topo.points.size(), 0);
    for (std::uint32_t v : part) {
      if (random() % 3 == 0) continue;
      for (int k = 0; k < 3; ++k) {
        double x = topo.points[v][k] + amount * unit();
        if (snap) x = std::round(x * 64.0) / 64.0;
        topo.points[v][k] = x;
      }
      moved[v] = 1;
    }
    const bool held = list.holds(topo);
    hierarchy.update(topo, moved);
    list.prepare(topo, settings, hierarchy);
    ASSERT_TRUE(list.holds(topo)) << scene.name;
    refreshed_rounds += round > 0 && !held;
    current = update_crossings(topo, settings, list, current, moved);
    expect_same(current, detect_crossings(topo, settings),
                scene.name + " " + setup.name + " listed, round " + std::to_string(round));
    if (::testing::Test::HasFailure()) return;
  }
  EXPECT_GE(refreshed_rounds, 10u) << "the rounds beyond the reach list triangles again";
}

TEST_P(IncrementalDetection, ListedPairsEqualFullDetectionAfterRandomMoves) {
  for (const auto& scene : scenes::named_scenes()) {
    if (scene.name != GetParam()) continue;
    std::uint32_t seed = 23;
    for (const DetectSetup& setup : kSetups) run_listed_rounds(scene, setup, seed++);
    return;
  }
  FAIL() << "no scene " << GetParam();
}

// A step of fix measures candidate moves against the positions at its start, plus the moves it
// already committed: after - before of every count must equal the change of the crossing count
// of a full detection, between the committed state and that state with the candidate applied.
// The hierarchy and the crossing set stay those of the step's start, as in fix.
void run_trials(const scenes::Scene& scene, std::uint32_t seed) {
  const std::vector<Mesh> meshes = scenes::scene_meshes(scene);
  SceneTopology topo = build_topology(meshes);  // the step's start
  DetectSettings settings;
  std::vector<bool> fixed;
  for (const Mesh& m : meshes) fixed.push_back(m.role == Role::kObstacle);
  settings.skip_among = fixed;
  const TriangleBvh obstacle_tree(topo, fixed);
  settings.skipped_bvh = &obstacle_tree;
  const SceneHierarchy hierarchy(topo, settings);
  const CrossingSet start = detect_crossings(topo, settings);
  MeasuredMoves trial(topo);
  trial.start_step(start, hierarchy, topo.tris.size());
  SceneTopology state = topo;  // the start with the committed moves
  std::size_t state_count = start.items.size();
  std::mt19937 random(seed);
  for (int round = 0; round < 40; ++round) {
    SceneTopology next = state;
    const std::vector<std::uint8_t> moved = random_moves(next, fixed, random, 0.1, round % 3 == 2);
    std::vector<std::uint32_t> vertices;
    std::vector<Vec3> at;
    for (std::uint32_t v = 0; v < moved.size(); ++v)
      if (moved[v]) {
        vertices.push_back(v);
        at.push_back(next.points[v]);
      }
    if (vertices.empty()) continue;
    const std::size_t next_count = detect_crossings(next, settings).items.size();
    const std::string where = scene.name + " round " + std::to_string(round);
    const MoveCount exact = trial.count(settings, start, vertices, at);
    ASSERT_EQ(static_cast<long long>(exact.after) - static_cast<long long>(exact.before),
              static_cast<long long>(next_count) - static_cast<long long>(state_count))
        << where;
    // Stopping early changes only how far above `before` a worse move's count is.
    const MoveCount early = trial.count(settings, start, vertices, at, true);
    EXPECT_EQ(early.before, exact.before) << where;
    if (exact.after <= exact.before) EXPECT_EQ(early.after, exact.after) << where;
    else EXPECT_GT(early.after, early.before) << where;
    // Moves taken by a committed one are not moved again in fix: commit only fresh vertices.
    if (random() % 2 == 0) {
      bool fresh = true;
      for (std::uint32_t v : vertices) fresh = fresh && state.points[v] == topo.points[v];
      if (!fresh) continue;
      trial.commit(vertices, at);
      state = std::move(next);
      state_count = next_count;
    }
  }
}

TEST_P(IncrementalDetection, MeasuredMoveCountsEqualFullDetection) {
  for (const auto& scene : scenes::named_scenes()) {
    if (scene.name != GetParam()) continue;
    run_trials(scene, 11);
    return;
  }
  FAIL() << "no scene " << GetParam();
}

}  // namespace
}  // namespace untangle
