// Flat patches (TriangleBvh::mark_flat_patches): the self pairs detection skips must hold no
// crossing. A patch whose triangles all face one way along a direction (the normal-cone test
// alone) can still cut through itself when it winds round more than once; only the boundary test
// tells.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "detect/detect_crossings.h"
#include "detect/triangle_bvh.h"
#include "geometry/vec3.h"
#include "scenes/scenes.h"
#include "topology/scene_topology.h"

namespace untangle {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool has(const std::array<std::uint32_t, 3>& tri, std::uint32_t v) {
  return tri[0] == v || tri[1] == v || tri[2] == v;
}

// Every crossing, by testing every edge against every triangle that shares no vertex with it.
std::set<std::pair<std::uint32_t, std::uint32_t>> brute_force(const SceneTopology& topo) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> found;
  for (std::uint32_t e = 0; e < topo.edges.size(); ++e)
    for (std::uint32_t f = 0; f < topo.tris.size(); ++f) {
      const auto& tri = topo.tris[f];
      if (has(tri, topo.edges[e][0]) || has(tri, topo.edges[e][1])) continue;
      if (edge_crosses_triangle(topo.points, topo.edges[e][0], topo.edges[e][1], tri[0], tri[1], tri[2]))
        found.insert({e, f});
    }
  return found;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> detected(const SceneTopology& topo) {
  DetectSettings settings;
  settings.threads = 1;
  std::set<std::pair<std::uint32_t, std::uint32_t>> found;
  for (const RawCrossing& c : detect_crossings(topo, settings).items) found.insert({c.edge, c.face});
  return found;
}

void finish(Mesh& m) {
  m.polygon.resize(m.triangles.size());
  for (std::uint32_t t = 0; t < m.polygon.size(); ++t) m.polygon[t] = t;
  m.source_faces = m.triangles.size();
}

// A strip wound round the z axis from angle 0 to `turn` (radii 1 to 2): seen along z every
// triangle turns the same way. Its height is 0 up to angle 1.2 and then (angle - turn + 0.5) / 2,
// so when `turn` exceeds 2 pi its end, lying over its start, passes through it.
Mesh spiral(double turn, int steps) {
  Mesh m;
  m.name = "spiral";
  for (int s = 0; s <= steps; ++s) {
    const double a = turn * s / steps;
    const double h = a <= 1.2 ? 0.0 : 0.5 * (a - turn + 0.5);
    for (const double r : {1.0, 2.0}) m.positions.push_back({r * std::cos(a), r * std::sin(a), h});
  }
  for (std::uint32_t s = 0; s < static_cast<std::uint32_t>(steps); ++s) {
    const std::uint32_t a = 2 * s, b = a + 1, c = a + 2, d = a + 3;
    m.triangles.push_back({a, c, b});
    m.triangles.push_back({b, c, d});
  }
  finish(m);
  return m;
}

std::size_t flat_triangles(const SceneTopology& topo) {
  TriangleBvh tree(topo, std::vector<bool>{true});
  tree.mark_flat_patches(topo);
  return tree.flat_patch_triangles();
}

std::size_t flat_patches(const SceneTopology& topo) {
  TriangleBvh tree(topo, std::vector<bool>{true});
  tree.mark_flat_patches(topo);
  return tree.flat_patch_count();
}

// Turns a mesh so that its z axis points along `axis` (unit), about the origin.
void turn_to(Mesh& m, const Vec3& axis) {
  const Vec3 z{0.0, 0.0, 1.0};
  Vec3 u = cross(z, axis);
  const double s = std::sqrt(dot(u, u)), c = dot(z, axis);  // sine and cosine of the angle
  if (s == 0.0) return;
  u = scale(u, 1.0 / s);
  for (Vec3& p : m.positions) {
    // Rodrigues: p cos + (u x p) sin + u (u . p)(1 - cos)
    p = add(add(scale(p, c), scale(cross(u, p), s)), scale(u, dot(u, p) * (1.0 - c)));
  }
}

TEST(FlatPatches, SpiralThroughItselfKeepsItsCrossings) {
  const SceneTopology topo = build_topology({spiral(2 * kPi + 1.0, 64)});
  const auto brute = brute_force(topo);
  ASSERT_GT(brute.size(), 0u);  // the end passes through the start
  EXPECT_EQ(detected(topo), brute);
  // The whole strip is not one flat patch: its end and start lie in different ones, or none.
  EXPECT_TRUE(flat_triangles(topo) < topo.tris.size() || flat_patches(topo) > 1);
}

// A spherical cap of half-angle 50 degrees around (1, 1, 1): some of its normals point against
// each coordinate axis, so no axis sees it one to one, while the diagonals see large parts of it.
// Jittered (real cloth is never exact), it must still hold no crossing.
TEST(FlatPatches, CapAroundAnObliqueDirectionIsSkipped) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.002, 0.002);
  Mesh cap;
  cap.name = "cap";
  const int rings = 12, around = 48;
  const double half_angle = 50.0 * kPi / 180.0;
  cap.positions.push_back({0.0, 0.0, 1.0});
  for (int r = 1; r <= rings; ++r) {
    const double polar = half_angle * r / rings;
    for (int a = 0; a < around; ++a) {
      const double azimuth = 2 * kPi * a / around;
      cap.positions.push_back({std::sin(polar) * std::cos(azimuth) + jitter(rng),
                               std::sin(polar) * std::sin(azimuth) + jitter(rng),
                               std::cos(polar) + jitter(rng)});
    }
  }
  auto ring = [&](int r, int a) { return static_cast<std::uint32_t>(1 + (r - 1) * around + (a % around)); };
  for (int a = 0; a < around; ++a) cap.triangles.push_back({0u, ring(1, a), ring(1, a + 1)});
  for (int r = 1; r < rings; ++r)
    for (int a = 0; a < around; ++a) {
      cap.triangles.push_back({ring(r, a), ring(r + 1, a), ring(r + 1, a + 1)});
      cap.triangles.push_back({ring(r, a), ring(r + 1, a + 1), ring(r, a + 1)});
    }
  const double third = 1.0 / std::sqrt(3.0);
  turn_to(cap, {third, third, third});
  finish(cap);
  const SceneTopology topo = build_topology({cap});
  // Most of it in patches (which ones, and how many, is a matter of seeds and only speed depends
  // on it), and the pairs skipped hold no crossing.
  EXPECT_GE(10 * flat_triangles(topo), 9 * topo.tris.size());
  EXPECT_TRUE(brute_force(topo).empty());
  EXPECT_TRUE(detected(topo).empty());
}

// The spirals of the tests above turned to lie along body diagonals: the open one is skipped
// whole, the wound one keeps every crossing.
TEST(FlatPatches, ObliqueSpirals) {
  const double third = 1.0 / std::sqrt(3.0);
  Mesh open = spiral(2 * kPi - 0.5, 64);
  turn_to(open, {third, third, third});
  const SceneTopology open_topo = build_topology({open});
  EXPECT_EQ(flat_triangles(open_topo), open_topo.tris.size());
  EXPECT_TRUE(brute_force(open_topo).empty());
  EXPECT_TRUE(detected(open_topo).empty());
  Mesh wound = spiral(2 * kPi + 1.0, 64);
  turn_to(wound, {third, -third, third});
  const SceneTopology wound_topo = build_topology({wound});
  const auto brute = brute_force(wound_topo);
  ASSERT_GT(brute.size(), 0u);
  EXPECT_EQ(detected(wound_topo), brute);
}

TEST(FlatPatches, OpenSpiralIsOneFlatPatch) {
  // Less than a full turn: its projection is one to one, the root qualifies.
  const SceneTopology topo = build_topology({spiral(2 * kPi - 0.5, 64)});
  EXPECT_EQ(flat_triangles(topo), topo.tris.size());
  EXPECT_TRUE(brute_force(topo).empty());
  EXPECT_TRUE(detected(topo).empty());
}

TEST(FlatPatches, JitteredSheetIsOneFlatPatchAndFoldedOneIsNot) {
  std::mt19937 rng(24);
  std::uniform_real_distribution<double> jitter(-0.2, 0.2);
  Mesh sheet = scenes::grid_sheet(40, 30, {0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, "sheet");
  for (Vec3& p : sheet.positions)
    for (double& c : p) c += jitter(rng) / 40.0;
  finish(sheet);
  const SceneTopology flat = build_topology({sheet});
  EXPECT_EQ(flat_triangles(flat), flat.tris.size());
  // The folded sheet of the named scenes cuts through itself: some of it still gets tested.
  std::vector<Mesh> folded = scenes::folded_sheet().movable;
  const SceneTopology fold = build_topology(folded);
  const auto brute = brute_force(fold);
  ASSERT_GT(brute.size(), 0u);
  EXPECT_EQ(detected(fold), brute);
}

// Random wavy and crumpled sheets and spirals: detection with the skipped pairs equals the
// brute force.
TEST(FlatPatches, RandomSheetsAgreeWithBruteForce) {
  std::mt19937 rng(2024);
  std::size_t total = 0, flat = 0, tris = 0;
  for (int round = 0; round < 300; ++round) {
    std::uniform_int_distribution<int> size(3, 12);
    const int nu = size(rng), nv = size(rng);
    Mesh m = scenes::grid_sheet(nu, nv, {0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, "sheet");
    const double amount = (round % 4 == 3 ? 1.5 : 0.4 * (round % 4)) / std::max(nu, nv);
    std::uniform_real_distribution<double> jitter(-amount, amount);
    for (Vec3& p : m.positions)
      for (double& c : p) c += jitter(rng);
    finish(m);
    std::vector<Mesh> meshes{m};
    if (round % 5 == 0) meshes.push_back(spiral(2 * kPi * (0.5 + 0.01 * round), 8 + round % 40));
    // Every other round turned to a random direction: patches seen along the diagonals.
    if (round % 2 == 1) {
      std::normal_distribution<double> gauss(0.0, 1.0);
      Vec3 axis{gauss(rng), gauss(rng), gauss(rng)};
      axis = scale(axis, 1.0 / std::sqrt(dot(axis, axis)));
      for (Mesh& mesh : meshes) turn_to(mesh, axis);
    }
    const SceneTopology topo = build_topology(meshes);
    const auto brute = brute_force(topo);
    ASSERT_EQ(detected(topo), brute) << "round " << round;
    total += brute.size();
    TriangleBvh tree(topo, std::vector<bool>(meshes.size(), true));
    tree.mark_flat_patches(topo);
    flat += tree.flat_patch_triangles();
    tris += topo.tris.size();
  }
  EXPECT_GT(total, 100u);       // crumpled sheets and wound spirals do cut through themselves
  EXPECT_GT(flat, tris / 4);    // and the wavy ones are skipped whole
  EXPECT_LT(flat, tris);
}

}  // namespace
}  // namespace untangle
