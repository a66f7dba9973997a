// Property tests of detection on thousands of random, grid-snapped (so degenerate) scenes:
// every triangle pair sharing no vertex has 0 or 2 crossings, every contour closes or ends on
// boundary edges or loop vertices, and the broad phase misses nothing a brute force finds.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "contour/build_contours.h"
#include "detect/cull_triangles.h"
#include "detect/detect_crossings.h"
#include "topology/scene_topology.h"
#include "untangle/intersections.h"

namespace untangle {
namespace {

// A height-field sheet of n x n vertices with integer x, y and z drawn from {0, 1, 2}.
Mesh grid_sheet(std::mt19937& rng, int n, int shift_x, int shift_y, bool swap_axes) {
  std::uniform_int_distribution<int> h(0, 2);
  Mesh m;
  m.name = "sheet";
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      Vec3 p{double(i + shift_x), double(j + shift_y), double(h(rng))};
      if (swap_axes) std::swap(p[1], p[2]);
      m.positions.push_back(p);
    }
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const std::uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      m.triangles.push_back({a, b, d});
      m.triangles.push_back({a, d, c});
    }
  return m;
}

// A closed octahedron with grid-snapped corners.
Mesh octahedron(std::mt19937& rng) {
  std::uniform_int_distribution<int> g(0, 3);
  std::uniform_int_distribution<int> r(1, 2);
  const Vec3 c{double(g(rng)), double(g(rng)), double(g(rng) % 3)};
  const double s = r(rng);
  Mesh m;
  m.name = "octahedron";
  m.positions = {{c[0] + s, c[1], c[2]}, {c[0] - s, c[1], c[2]}, {c[0], c[1] + s, c[2]},
                 {c[0], c[1] - s, c[2]}, {c[0], c[1], c[2] + s}, {c[0], c[1], c[2] - s}};
  m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                 {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  return m;
}

// Loose triangles with corners on a 3x3x3 grid (welding may join them into odd topology).
Mesh soup(std::mt19937& rng, int count) {
  std::uniform_int_distribution<int> g(0, 2);
  Mesh m;
  m.name = "soup";
  for (int t = 0; t < count; ++t) {
    for (int k = 0; k < 3; ++k) m.positions.push_back({double(g(rng)), double(g(rng)), double(g(rng))});
    const std::uint32_t b = static_cast<std::uint32_t>(3 * t);
    m.triangles.push_back({b, b + 1, b + 2});
  }
  return m;
}

std::vector<Mesh> random_scene(std::mt19937& rng, int kind) {
  std::vector<Mesh> meshes;
  switch (kind % 5) {
    case 0:  // two sheets through each other
      meshes.push_back(grid_sheet(rng, 4, 0, 0, false));
      meshes.push_back(grid_sheet(rng, 4, 0, 0, true));
      break;
    case 1:  // a sheet and a closed octahedron
      meshes.push_back(grid_sheet(rng, 5, 0, 0, false));
      meshes.push_back(octahedron(rng));
      break;
    case 2:  // a mesh and its exact duplicate
      meshes.push_back(grid_sheet(rng, 4, 0, 0, false));
      meshes.push_back(meshes.back());
      break;
    case 3:  // triangle soup, one mesh (self-intersections, shared vertices, non-manifold edges)
      meshes.push_back(soup(rng, 6));
      break;
    default:  // two octahedra and a sheet
      meshes.push_back(octahedron(rng));
      meshes.push_back(octahedron(rng));
      meshes.push_back(grid_sheet(rng, 3, 1, 1, false));
      break;
  }
  for (auto& m : meshes) {
    m.polygon.resize(m.triangles.size());
    for (std::uint32_t t = 0; t < m.polygon.size(); ++t) m.polygon[t] = t;
    m.source_faces = m.triangles.size();
  }
  return meshes;
}

bool has(const std::array<std::uint32_t, 3>& tri, std::uint32_t v) {
  return tri[0] == v || tri[1] == v || tri[2] == v;
}

TEST(DetectProperty, ZeroOrTwoCrossingsAndContoursCloseOnGridScenes) {
  std::mt19937 rng(20261121);
  std::size_t total_crossings = 0, total_contours = 0;
  std::size_t total_contact_points = 0;
  for (int round = 0; round < 3000; ++round) {
    std::vector<Mesh> meshes = random_scene(rng, round);
    // Every other round the last mesh is an obstacle: its grid-snapped positions that other meshes
    // share are contact points (DESIGN §2), one point of both, and the property must hold for them.
    if (round % 2 == 1 && meshes.size() > 1) meshes.back().role = Role::kObstacle;
    const SceneTopology topo = build_topology(meshes);
    for (std::size_t v = 0; v < topo.contact_point.size(); ++v) total_contact_points += topo.contact_point[v] != v;

    // Brute force: every edge against every triangle sharing no vertex with it; a position shared
    // by two meshes is one point (DESIGN §2, contact), as detection sees it.
    const auto& tris = topo.detect_tris();
    std::set<std::pair<std::uint32_t, std::uint32_t>> brute;
    for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
      const std::uint32_t p = topo.detect_point(topo.edges[e][0]), q = topo.detect_point(topo.edges[e][1]);
      for (std::uint32_t f = 0; f < topo.tris.size(); ++f) {
        const auto& tri = tris[f];
        if (has(tri, p) || has(tri, q)) continue;
        if (edge_crosses_triangle(topo.points, p, q, tri[0], tri[1], tri[2])) brute.insert({e, f});
      }
    }
    // Per triangle pair: 0 or 2 crossings when no vertex (or shared point) is shared, 0 or 1 when
    // one is.
    for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
      for (std::uint32_t f = t + 1; f < topo.tris.size(); ++f) {
        int shared = 0;
        for (std::uint32_t v : tris[t]) shared += has(tris[f], v) ? 1 : 0;
        if (shared >= 2) continue;
        int count = 0;
        for (std::uint32_t e : topo.tri_edges[t]) count += brute.count({e, f}) ? 1 : 0;
        for (std::uint32_t e : topo.tri_edges[f]) count += brute.count({e, t}) ? 1 : 0;
        if (shared == 0) {
          ASSERT_TRUE(count == 0 || count == 2) << "round " << round << " pair " << t << "," << f
                                                << " has " << count << " crossings";
        } else {
          ASSERT_LE(count, 1) << "round " << round << " pair " << t << "," << f;
        }
      }
    }

    DetectSettings settings;
    settings.threads = 1;
    const CrossingSet set = detect_crossings(topo, settings);
    std::set<std::pair<std::uint32_t, std::uint32_t>> found;
    for (const RawCrossing& c : set.items) found.insert({c.edge, c.face});
    ASSERT_EQ(found, brute) << "round " << round;
    total_crossings += set.items.size();

    const std::vector<TracedContour> contours = build_contours(topo, set);
    for (const TracedContour& traced : contours) {
      const Contour& c = traced.contour;
      ASSERT_FALSE(traced.broken) << "round " << round;
      if (c.branch_points > 0) continue;  // non-manifold soup: branches are reported, not chains
      if (!c.closed) {
        EXPECT_EQ(c.tracks[0].boundary_ends + c.tracks[1].boundary_ends + c.loop_vertices, 2u)
            << "round " << round << ": an open contour must have two ends";
      }
    }
    total_contours += contours.size();
  }
  EXPECT_GT(total_crossings, 1000u);
  EXPECT_GT(total_contours, 500u);
  EXPECT_GT(total_contact_points, 1000u) << "the obstacle rounds must share positions";
}

// A closed mesh and its exact copy: every coincident pair is decided the same consistent way.
TEST(DetectProperty, DuplicatedClosedMeshGivesClosedContours) {
  std::mt19937 rng(3);
  std::vector<Mesh> meshes{octahedron(rng)};
  meshes.push_back(meshes.front());
  for (auto& m : meshes) {
    m.polygon = {0, 1, 2, 3, 4, 5, 6, 7};
    m.source_faces = 8;
  }
  const Intersections found = find_intersections(meshes);
  EXPECT_EQ(found.counts.broken, 0u);
  for (const Contour& c : found.contours) EXPECT_TRUE(c.closed);
  EXPECT_EQ(found.counts.crossings % 2, 0u);
}

// The same scene gives the same result at every thread count.
TEST(DetectProperty, SameResultForEveryThreadCount) {
  std::mt19937 rng(5);
  std::vector<Mesh> meshes;
  for (int i = 0; i < 4; ++i) meshes.push_back(grid_sheet(rng, 30, 0, 0, i % 2 == 1));
  for (auto& m : meshes) {
    m.polygon.resize(m.triangles.size());
    m.source_faces = m.triangles.size();
  }
  DetectOptions one, two, all;
  one.threads = 1;
  two.threads = 2;
  all.threads = 0;
  const Intersections a = find_intersections(meshes, one);
  const Intersections b = find_intersections(meshes, two);
  const Intersections c = find_intersections(meshes, all);
  ASSERT_GT(a.counts.crossings, 0u);
  EXPECT_EQ(a.triangle_pairs, b.triangle_pairs);
  EXPECT_EQ(a.triangle_pairs, c.triangle_pairs);
  ASSERT_EQ(a.contours.size(), b.contours.size());
  for (std::size_t k = 0; k < a.contours.size(); ++k) {
    EXPECT_EQ(a.contours[k].crossings, b.contours[k].crossings);
    EXPECT_EQ(a.contours[k].polyline, c.contours[k].polyline);
    for (int t = 0; t < 2; ++t) {  // tracks are classified in parallel
      EXPECT_EQ(a.contours[k].tracks[t].separates, b.contours[k].tracks[t].separates);
      EXPECT_EQ(a.contours[k].tracks[t].smaller_area, c.contours[k].tracks[t].smaller_area);
      EXPECT_EQ(a.contours[k].tracks[t].type, c.contours[k].tracks[t].type);
    }
  }
}

// Without self pairs only the triangles near another mesh are kept (cull_triangles) and the
// hierarchies are built over those: the culling is conservative (every triangle whose box touches
// a triangle box of another mesh is kept, touching exactly included: the scenes are grid-snapped),
// and detection finds exactly the brute force's crossings between different meshes. The same
// scenes are repeated scaled and shifted by non-integers, where the grid's rounding is inexact.
TEST(DetectProperty, BetweenMeshesOnlyKeepsEveryNearTriangle) {
  std::mt19937 rng(20261122);
  std::size_t total = 0, culled = 0;
  for (int round = 0; round < 2000; ++round) {
    std::vector<Mesh> meshes = random_scene(rng, round);
    if (meshes.size() < 2) continue;
    std::uniform_int_distribution<int> shift(0, 3);
    for (std::size_t m = 1; m < meshes.size(); ++m) {  // partly apart: something to cull
      const double dx = shift(rng), dy = shift(rng);
      for (Vec3& p : meshes[m].positions) {
        p[0] += dx;
        p[1] += dy;
      }
    }
    if (round % 2 == 1) {
      for (Mesh& m : meshes)
        for (Vec3& p : m.positions)
          for (double& x : p) x = x * 0.7310000000000001 + 0.1;
    }
    const SceneTopology topo = build_topology(meshes);
    const std::size_t mesh_count = topo.mesh_tri_begin.size() - 1;
    const std::vector<std::vector<std::uint32_t>> kept =
        cull_triangles(topo, std::vector<bool>(mesh_count, true));
    ASSERT_EQ(kept, cull_triangles(topo, std::vector<bool>(mesh_count, true), 0));  // all cores
    std::vector<std::uint8_t> is_kept(topo.tris.size(), 0);
    for (const auto& list : kept) {
      ASSERT_TRUE(std::is_sorted(list.begin(), list.end()));
      for (std::uint32_t t : list) is_kept[t] = 1;
    }
    std::set<std::pair<std::uint32_t, std::uint32_t>> brute;
    for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
      for (std::uint32_t u = 0; u < topo.tris.size(); ++u) {
        if (topo.tri_mesh[t] == topo.tri_mesh[u]) continue;
        if (triangle_box(topo, t).overlaps(triangle_box(topo, u))) {
          ASSERT_TRUE(is_kept[t]) << "round " << round << ": triangle " << t << " near " << u << " culled";
        }
      }
    }
    for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
      const std::uint32_t p = topo.detect_point(topo.edges[e][0]), q = topo.detect_point(topo.edges[e][1]);
      for (std::uint32_t f = 0; f < topo.tris.size(); ++f) {
        const auto& tri = topo.detect_tris()[f];  // shared positions are one point (contact)
        if (topo.edge_mesh(e) == topo.tri_mesh[f]) continue;
        if (has(tri, p) || has(tri, q)) continue;
        if (edge_crosses_triangle(topo.points, p, q, tri[0], tri[1], tri[2])) brute.insert({e, f});
      }
    }
    DetectSettings settings;
    settings.threads = 1;
    settings.self_pairs = false;
    std::set<std::pair<std::uint32_t, std::uint32_t>> found;
    for (const RawCrossing& c : detect_crossings(topo, settings).items) found.insert({c.edge, c.face});
    ASSERT_EQ(found, brute) << "round " << round;
    total += topo.tris.size();
    culled += topo.tris.size() - std::count(is_kept.begin(), is_kept.end(), 1);
  }
  EXPECT_GT(culled, total / 10) << "the culling should drop some triangles of these scenes";
}

}  // namespace
}  // namespace untangle
