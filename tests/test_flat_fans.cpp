// Flat fans (detection skips the pairs around a vertex whose flat fan winds once): detection's
// crossings equal those of every edge tested against every face that shares no vertex with it
// (edge_crosses_triangle, no pruning), for fans that wind once, twice, or fold over, and flat
// grids, in planes normal to each axis, with permuted triangle and corner order.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "detect/detect_crossings.h"
#include "topology/scene_topology.h"
#include "untangle/mesh.h"

namespace untangle {
namespace {

// A fan of triangles around vertex 0, its rim vertex k at angles[k] degrees and radius
// 1 + 0.05 k (distinct points even where the angles repeat), in the plane normal to `axis` at
// `level`; triangles (0, k, k + 1), the last one closing to vertex 1, turn counter-clockwise where
// the angles increase. `flip` reverses the corner order of that triangle (it runs the other way).
Mesh fan(const std::vector<double>& angles, int axis, double level, int flip = -1) {
  const int sectors = static_cast<int>(angles.size());
  Mesh mesh;
  mesh.name = "fan";
  auto place = [&](double u, double v) {
    Vec3 p{};
    const int i = axis == 0 ? 1 : 0, j = axis == 2 ? 1 : 2;
    p[axis] = level;
    p[i] = u;
    p[j] = v;
    return p;
  };
  mesh.positions.push_back(place(0.125, -0.375));
  for (int k = 0; k < sectors; ++k) {
    const double angle = angles[k] * 3.14159265358979323846 / 180.0, radius = 1.0 + 0.05 * k;
    mesh.positions.push_back(place(0.125 + radius * std::cos(angle), -0.375 + radius * std::sin(angle)));
  }
  for (int k = 0; k < sectors; ++k) {
    const std::uint32_t a = 1 + k, b = 1 + (k + 1) % sectors;
    if (k == flip) mesh.triangles.push_back({0, b, a});
    else mesh.triangles.push_back({0, a, b});
  }
  return mesh;
}

// A regular fan: `sectors` steps of `step` degrees.
Mesh fan(int sectors, double step, int axis, double level, int flip = -1) {
  std::vector<double> angles;
  for (int k = 0; k < sectors; ++k) angles.push_back(k * step);
  return fan(angles, axis, level, flip);
}

using Found = std::vector<std::array<std::uint32_t, 2>>;  // (edge, face)

Found brute_force(const SceneTopology& topo) {
  Found found;
  for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
    const auto [p, q] = topo.edges[e];
    for (std::uint32_t f = 0; f < topo.tris.size(); ++f) {
      const auto& tri = topo.tris[f];
      if (std::count(tri.begin(), tri.end(), p) + std::count(tri.begin(), tri.end(), q) > 0) continue;
      if (edge_crosses_triangle(topo.points, p, q, tri[0], tri[1], tri[2])) found.push_back({e, f});
    }
  }
  return found;
}

// expect_crossings: 0 none, 1 some, -1 either (coplanar overlaps cross only where the perturbation
// makes them).
void expect_brute_force(Mesh mesh, const std::string& what, int expect_crossings) {
  for (int order = 0; order < 3; ++order) {
    // Rotate the corners and reverse the triangle order: the same surface, other ids.
    if (order > 0) {
      for (auto& t : mesh.triangles) std::rotate(t.begin(), t.begin() + 1, t.end());
      std::reverse(mesh.triangles.begin(), mesh.triangles.end());
    }
    const SceneTopology topo = build_topology({mesh});
    const Found want = brute_force(topo);
    if (expect_crossings >= 0) {
      EXPECT_EQ(want.empty() ? 0 : 1, expect_crossings) << what;
    }
    for (int threads : {1, 2}) {
      DetectSettings settings;
      settings.threads = threads;
      Found got;
      for (const RawCrossing& c : detect_crossings(topo, settings).items) got.push_back({c.edge, c.face});
      EXPECT_EQ(got, want) << what << ", order " << order << ", threads " << threads;
    }
  }
}

// An n x n flat grid in the plane normal to `axis`, diagonals alternating; with `fold`, its
// middle vertex moved in the plane across its neighbours (the fans around it fold).
Mesh grid(int n, int axis, double level, bool fold) {
  Mesh mesh;
  mesh.name = "grid";
  const int i = axis == 0 ? 1 : 0, j = axis == 2 ? 1 : 2;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      Vec3 p{};
      p[axis] = level;
      p[i] = -0.3 + x / (n - 1.0);
      p[j] = 0.2 + y / (n - 1.0);
      mesh.positions.push_back(p);
    }
  if (fold) mesh.positions[(n / 2) * n + n / 2][i] += 2.5 / (n - 1.0);
  for (int y = 0; y + 1 < n; ++y)
    for (int x = 0; x + 1 < n; ++x) {
      const std::uint32_t a = y * n + x, b = a + 1, c = a + n + 1, d = a + n;
      if ((x + y) % 2 == 0) {
        mesh.triangles.push_back({a, b, c});
        mesh.triangles.push_back({a, c, d});
      } else {
        mesh.triangles.push_back({a, b, d});
        mesh.triangles.push_back({b, c, d});
      }
    }
  return mesh;
}

TEST(FlatFans, CrossingsAroundFlatVerticesEqualBruteForce) {
  for (int axis = 0; axis < 3; ++axis) {
    const double level = 0.3 * (axis + 1);
    const std::string where = " (axis " + std::to_string(axis) + ")";
    // Winds once: no two triangles overlap.
    expect_brute_force(fan(6, 60.0, axis, level), "hexagon" + where, 0);
    expect_brute_force(fan(7, 360.0 / 7.0, axis, level), "heptagon" + where, 0);
    // Winds twice (ten sectors of 72 degrees, every corner ray turning counter-clockwise): each
    // triangle overlaps the ones half a fan away.
    expect_brute_force(fan(10, 72.0, axis, level), "fan winding twice" + where, 1);
    // Winds once in all but one sector, which is folded back over its neighbours.
    expect_brute_force(fan(8, 45.0, axis, level, 3), "folded sector" + where, -1);
    // Winds once in all, but one small sector turns clockwise inside a quadrant (40 to 30
    // degrees), over parts of the sectors beside it.
    expect_brute_force(fan({0.0, 40.0, 30.0, 100.0, 200.0, 300.0}, axis, level), "clockwise sector" + where, 1);
    expect_brute_force(grid(7, axis, level, false), "grid" + where, 0);
    expect_brute_force(grid(7, axis, level, true), "grid with a folded vertex" + where, -1);
  }
}

}  // namespace
}  // namespace untangle
