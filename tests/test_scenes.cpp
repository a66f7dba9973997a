// The generated scenes: well-formed meshes, the contours each scene is built to produce (expected
// from the geometry, see the comments in tests/scenes/scenes.cpp), the same result under permuted
// vertex and face order, and testdata/ in step with the generator.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "scenes/scenes.h"
#include "untangle/intersections.h"
#include "untangle/mesh.h"
#include "untangle/read_meshes.h"

namespace untangle {
namespace {

using scenes::Scene;

// Why the cow's tests are skipped when they are.
constexpr const char* kNoCow =
    "cow.off of Debian's libcgal-demo is not installed (/usr/share/doc/libcgal-demo/data.tar.gz); "
    "install libcgal-demo and re-run cmake to test on the cow";

// ---- mesh helpers ----

struct Shape {
  std::size_t boundary_loops = 0;
  std::size_t components = 0;
  long euler = 0;       // V - E + F
  double volume = 0.0;  // signed, for closed meshes: > 0 when oriented outward
  std::vector<std::uint32_t> loop_of_vertex;  // boundary loop id per vertex, or -1
  std::vector<std::string> problems;
};

std::uint32_t find(std::vector<std::uint32_t>& parent, std::uint32_t v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

// Topology of a mesh that is welded by construction (vertex index = position).
Shape shape_of(const Mesh& mesh) {
  Shape shape;
  const std::size_t n = mesh.positions.size();
  if (std::set<Vec3>(mesh.positions.begin(), mesh.positions.end()).size() != n) {
    shape.problems.push_back("two vertices share a position (not welded)");
  }
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
  std::vector<bool> used(n, false);
  for (const Triangle& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
      shape.problems.push_back("degenerate triangle");
    for (int k = 0; k < 3; ++k) {
      used[t[k]] = true;
      if (++directed[{t[k], t[(k + 1) % 3]}] > 1) {
        shape.problems.push_back("directed edge used twice (inconsistent orientation)");
      }
    }
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    shape.volume += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0])) /
                    6.0;
  }
  if (std::count(used.begin(), used.end(), false) != 0) shape.problems.push_back("unused vertex");
  std::vector<std::uint32_t> parent(n), boundary_parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  std::iota(boundary_parent.begin(), boundary_parent.end(), 0u);
  std::vector<int> boundary_out(n, 0), boundary_in(n, 0);
  std::size_t edges = 0;
  for (const auto& [edge, count] : directed) {
    const auto [a, b] = edge;
    parent[find(parent, a)] = find(parent, b);
    const bool twin = directed.count({b, a}) != 0;
    if (!twin || a < b) ++edges;
    if (!twin) {  // boundary edge
      ++boundary_out[a];
      ++boundary_in[b];
      boundary_parent[find(boundary_parent, a)] = find(boundary_parent, b);
    }
  }
  shape.loop_of_vertex.assign(n, static_cast<std::uint32_t>(-1));
  std::map<std::uint32_t, std::uint32_t> loop_id;
  std::set<std::uint32_t> roots;
  for (std::uint32_t v = 0; v < n; ++v) {
    roots.insert(find(parent, v));
    if (boundary_out[v] == 0 && boundary_in[v] == 0) continue;
    if (boundary_out[v] != 1 || boundary_in[v] != 1) {
      shape.problems.push_back("boundary vertex " + std::to_string(v) +
                               " is not on one simple loop");
    }
    const std::uint32_t root = find(boundary_parent, v);
    const auto it = loop_id.emplace(root, static_cast<std::uint32_t>(loop_id.size())).first;
    shape.loop_of_vertex[v] = it->second;
  }
  shape.boundary_loops = loop_id.size();
  shape.components = roots.size();
  shape.euler =
      static_cast<long>(n) - static_cast<long>(edges) + static_cast<long>(mesh.triangles.size());
  return shape;
}

// Boundary loops each primitive is built with, by mesh name.
std::size_t expected_loops(const std::string& name) {
  static const std::map<std::string, std::size_t> kLoops = {
      {"sheet", 1},   {"strip", 1},  {"flat", 1}, {"tilted", 1},   {"ribbon", 1}, {"tube", 2},
      {"garment", 4}, {"sphere", 0}, {"body", 0}, {"shoulder", 0}, {"spikes", 0}};
  const auto it = kLoops.find(name);
  return it == kLoops.end() ? static_cast<std::size_t>(-1) : it->second;
}

// ---- contour helpers ----

const Track& track_on(const Contour& contour, std::uint32_t mesh) {
  return contour.tracks[0].mesh == mesh ? contour.tracks[0] : contour.tracks[1];
}

bool has_track_on(const Contour& contour, std::uint32_t mesh) {
  return contour.tracks[0].mesh == mesh || contour.tracks[1].mesh == mesh;
}

std::string text(const Contour& c) {
  std::string out = std::string(c.closed ? "closed" : "open") + (c.self ? " self" : "") + " ";
  for (int k = 0; k < 2; ++k) {
    out += (k == 0 ? "" : "/") + std::string("mesh ") + std::to_string(c.tracks[k].mesh) + " " +
           to_string(c.tracks[k].type) + (c.tracks[k].separates ? " (separates)" : "");
  }
  return out + ", " + std::to_string(c.crossings.size()) + " crossings";
}

std::string text(const Intersections& result) {
  std::string out = std::to_string(result.contours.size()) + " contours:";
  for (const Contour& c : result.contours) out += "\n  " + text(c);
  return out;
}

// The boundary loops (of `mesh`, index `mesh_index` in the scene) that an open contour's two ends
// lie on: the end crossings' edges are boundary edges of that mesh.
std::pair<std::uint32_t, std::uint32_t> end_loops(const Intersections& result,
                                                  const Contour& contour, std::uint32_t mesh_index,
                                                  const Shape& shape) {
  std::array<std::uint32_t, 2> loops{static_cast<std::uint32_t>(-1),
                                     static_cast<std::uint32_t>(-1)};
  for (int end = 0; end < 2; ++end) {
    const Crossing& x =
        result.crossings[end == 0 ? contour.crossings.front() : contour.crossings.back()];
    EXPECT_EQ(x.edge_mesh, mesh_index) << "an end crossing's edge is not on mesh " << mesh_index;
    if (x.edge_mesh != mesh_index) continue;
    const std::uint32_t l0 = shape.loop_of_vertex[x.edge_v0], l1 = shape.loop_of_vertex[x.edge_v1];
    EXPECT_EQ(l0, l1) << "an end crossing's edge is not a boundary edge";
    loops[end] = l0;
  }
  return {loops[0], loops[1]};
}

// ---- well-formed meshes ----

class SceneMeshes : public ::testing::TestWithParam<std::size_t> {};

TEST_P(SceneMeshes, WeldedOrientedWithTheStatedLoops) {
  const Scene scene = scenes::named_scenes()[GetParam()];
  const std::vector<Mesh> meshes = scenes::scene_meshes(scene);
  ASSERT_FALSE(meshes.empty());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = meshes[m];
    SCOPED_TRACE(scene.name + ":" + mesh.name);
    const Shape shape = shape_of(mesh);
    for (const std::string& problem : shape.problems) ADD_FAILURE() << problem;
    const std::size_t loops = expected_loops(mesh.name);
    ASSERT_NE(loops, static_cast<std::size_t>(-1)) << "unknown primitive name";
    EXPECT_EQ(shape.boundary_loops, loops);
    EXPECT_EQ(shape.components, 1u);
    EXPECT_EQ(shape.euler, 2 - static_cast<long>(loops)) << "not genus 0";
    if (loops == 0) {
      EXPECT_GT(shape.volume, 0.0) << "closed mesh oriented inward";
    }
    EXPECT_EQ(mesh.polygon.size(), mesh.triangles.size());
    EXPECT_EQ(mesh.source_faces, mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.polygon.size(); ++t) ASSERT_EQ(mesh.polygon[t], t);
    EXPECT_EQ(mesh.role, m < scene.movable.size() ? Role::kMovable : Role::kObstacle);
    EXPECT_GE(mesh.triangles.size(), 50u);  // the narrow strip has 76
    EXPECT_LE(mesh.triangles.size(), 5000u);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, SceneMeshes,
                         ::testing::Range<std::size_t>(0, scenes::named_scenes().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& info) {
                           return scenes::named_scenes()[info.param].name;
                         });

// ---- the contours each scene is built for ----

// A sheet through the sphere's middle: one closed curve, closed on both surfaces; it cuts the sheet
// into a disc and the rest, the sphere into two caps.
TEST(SceneContours, SheetThroughSphere) {
  const Scene scene = scenes::sheet_through_sphere();
  const Intersections result = find_intersections(scenes::scene_meshes(scene));
  ASSERT_EQ(result.contours.size(), 1u) << text(result);
  const Contour& c = result.contours[0];
  EXPECT_TRUE(c.closed);
  EXPECT_FALSE(c.self);
  for (std::uint32_t mesh : {0u, 1u}) {
    ASSERT_TRUE(has_track_on(c, mesh)) << text(c);
    EXPECT_EQ(track_on(c, mesh).type, TrackType::kCL) << text(c);
    EXPECT_TRUE(track_on(c, mesh).separates) << text(c);
    EXPECT_EQ(track_on(c, mesh).boundary_ends, 0u);
  }
  EXPECT_EQ(result.counts.pairs_cl_cl, 1u);
  EXPECT_EQ(result.counts.non_separating, 0u);
  EXPECT_EQ(result.counts.tracks[static_cast<int>(TrackType::kCL)], 2u);
}

// The strip's two long boundary edges pierce the sheet: the curve crosses the strip's width (both
// ends on the strip's boundary: BB, cutting it in two) and lies inside the sheet (II).
TEST(SceneContours, StripThroughSheet) {
  const Scene scene = scenes::strip_through_sheet();
  ASSERT_EQ(scene.movable[0].name, "strip");
  const Intersections result = find_intersections(scenes::scene_meshes(scene));
  ASSERT_EQ(result.contours.size(), 1u) << text(result);
  const Contour& c = result.contours[0];
  EXPECT_FALSE(c.closed);
  EXPECT_FALSE(c.self);
  ASSERT_TRUE(has_track_on(c, 0) && has_track_on(c, 1)) << text(c);
  EXPECT_EQ(track_on(c, 0).type, TrackType::kBB) << text(c);
  EXPECT_EQ(track_on(c, 0).boundary_ends, 2u);
  EXPECT_TRUE(track_on(c, 0).separates) << text(c);
  EXPECT_EQ(track_on(c, 1).type, TrackType::kII) << text(c);
  EXPECT_EQ(track_on(c, 1).boundary_ends, 0u);
  EXPECT_EQ(result.counts.pairs_bb_ii, 1u);
  // The strip's two long sides are one boundary loop; both ends are on it.
  const Shape strip = shape_of(scene.movable[0]);
  const auto [a, b] = end_loops(result, c, 0, strip);
  EXPECT_EQ(a, b);
}

// The segment where the planes meet leaves the tilted sheet inside the flat one and the flat sheet
// inside the tilted one: one end on each boundary, so BI on both.
TEST(SceneContours, SheetsCorner) {
  const Scene scene = scenes::sheets_corner();
  const Intersections result = find_intersections(scenes::scene_meshes(scene));
  ASSERT_EQ(result.contours.size(), 1u) << text(result);
  const Contour& c = result.contours[0];
  EXPECT_FALSE(c.closed);
  EXPECT_FALSE(c.self);
  for (std::uint32_t mesh : {0u, 1u}) {
    ASSERT_TRUE(has_track_on(c, mesh)) << text(c);
    EXPECT_EQ(track_on(c, mesh).type, TrackType::kBI) << text(c);
    EXPECT_EQ(track_on(c, mesh).boundary_ends, 1u);
  }
  EXPECT_EQ(result.counts.pairs_bi_bi, 1u);
}

// The ribbon crosses itself once, where its narrow part (t = -1) lies within its wide part (t = 1):
// one open self-intersection contour, both ends on the ribbon's boundary edges of the narrow part.
TEST(SceneContours, FoldedSheet) {
  const Scene scene = scenes::folded_sheet();
  const Intersections result = find_intersections(scenes::scene_meshes(scene));
  ASSERT_EQ(result.contours.size(), 1u) << text(result);
  for (const Contour& c : result.contours) {
    EXPECT_TRUE(c.self) << text(c);
    EXPECT_EQ(c.tracks[0].mesh, 0u);
    EXPECT_EQ(c.tracks[1].mesh, 0u);
  }
  const Contour& c = result.contours[0];
  EXPECT_FALSE(c.closed);
  EXPECT_EQ(c.loop_vertices, 0u);
  std::multiset<TrackType> types = {c.tracks[0].type, c.tracks[1].type};
  EXPECT_EQ(types, (std::multiset<TrackType>{TrackType::kBB, TrackType::kII})) << text(c);
  EXPECT_EQ(result.counts.pairs_self, 1u);
  EXPECT_EQ(result.counts.pairs_cl_cl + result.counts.pairs_bb_ii + result.counts.pairs_bi_bi +
                result.counts.pairs_other,
            0u);
}

// The capsule sticks out of the tube along its whole length on one side: two curves, each from one
// tube loop to the other (BB on the tube, II on the closed capsule). A cut from loop to loop does
// not split a tube, so neither tube track separates on its own.
TEST(SceneContours, TubeAroundBody) {
  const Scene scene = scenes::tube_around_body();
  ASSERT_EQ(scene.movable[0].name, "tube");
  const Shape tube = shape_of(scene.movable[0]);
  const Intersections result = find_intersections(scenes::scene_meshes(scene));
  ASSERT_EQ(result.contours.size(), 2u) << text(result);
  for (const Contour& c : result.contours) {
    SCOPED_TRACE(text(c));
    EXPECT_FALSE(c.closed);
    ASSERT_TRUE(has_track_on(c, 0) && has_track_on(c, 1));
    EXPECT_EQ(track_on(c, 0).type, TrackType::kBB);
    EXPECT_FALSE(track_on(c, 0).separates);
    EXPECT_EQ(track_on(c, 1).type, TrackType::kII);
    const auto [a, b] = end_loops(result, c, 0, tube);
    EXPECT_NE(a, b) << "the contour should join the tube's two loops";
  }
  EXPECT_EQ(result.counts.pairs_bb_ii, 2u);
  EXPECT_GT(result.counts.non_separating, 0u);
  EXPECT_EQ(result.counts.non_separating, 2u);
}

// The shoulder sphere covers the facing rims of the neck and the right sleeve: its curve on the
// garment is cut by the two holes into a front and a back piece, each joining the neck loop to the
// sleeve loop (BB, non-separating alone), II on the sphere.
TEST(SceneContours, GarmentFourLoops) {
  const Scene scene = scenes::garment_four_loops();
  ASSERT_EQ(scene.movable[0].name, "garment");
  const Shape garment = shape_of(scene.movable[0]);
  ASSERT_EQ(garment.boundary_loops, 4u);
  const Intersections result = find_intersections(scenes::scene_meshes(scene));
  ASSERT_EQ(result.contours.size(), 2u) << text(result);
  std::set<std::uint32_t> joined;
  for (const Contour& c : result.contours) {
    SCOPED_TRACE(text(c));
    EXPECT_FALSE(c.closed);
    ASSERT_TRUE(has_track_on(c, 0) && has_track_on(c, 1));
    EXPECT_EQ(track_on(c, 0).type, TrackType::kBB);
    EXPECT_FALSE(track_on(c, 0).separates);
    EXPECT_EQ(track_on(c, 1).type, TrackType::kII);
    const auto [a, b] = end_loops(result, c, 0, garment);
    EXPECT_NE(a, b) << "the contour should join two of the garment's loops";
    joined.insert(a);
    joined.insert(b);
  }
  EXPECT_EQ(joined.size(), 2u) << "both contours should join the same two loops (neck, sleeve)";
  EXPECT_EQ(result.counts.pairs_bb_ii, 2u);
  EXPECT_EQ(result.counts.non_separating, 2u);
}

// Each of the nine tips pokes through the sheet: a small closed curve around it, closed on both;
// it encloses the tip on the spikes and at least one sheet vertex (cut radius 0.19 > spacing 0.1).
TEST(SceneContours, SheetOnSpikes) {
  const Scene scene = scenes::sheet_on_spikes();
  const Intersections result = find_intersections(scenes::scene_meshes(scene));
  constexpr std::size_t kPoking = 9;  // 3 x 3 spikes of height 0.6, sheet at 0.2237
  ASSERT_EQ(result.contours.size(), kPoking) << text(result);
  for (const Contour& c : result.contours) {
    SCOPED_TRACE(text(c));
    EXPECT_TRUE(c.closed);
    EXPECT_FALSE(c.self);
    for (std::uint32_t mesh : {0u, 1u}) {
      ASSERT_TRUE(has_track_on(c, mesh));
      EXPECT_EQ(track_on(c, mesh).type, TrackType::kCL);
      EXPECT_TRUE(track_on(c, mesh).separates);
    }
  }
  EXPECT_EQ(result.counts.pairs_cl_cl, kPoking);
  EXPECT_EQ(result.counts.non_separating, 0u);
}

// The sheet spans 1.2 times the cow's box across its middle: every sheet-cow curve is closed on
// both (the cow is closed, the sheet's boundary lies outside it).
TEST(SceneContours, SheetThroughCow) {
  if (scenes::cow_path().empty()) GTEST_SKIP() << kNoCow;
  const Scene scene = scenes::sheet_through_cow(40);
  ASSERT_EQ(scene.movable.size(), 1u);
  ASSERT_GE(scene.obstacles.size(), 1u);
  const Intersections result = find_intersections(scenes::scene_meshes(scene));
  std::size_t sheet_cow = 0;
  for (const Contour& c : result.contours) {
    if (c.self) continue;  // within the cow, if it has any
    ++sheet_cow;
    SCOPED_TRACE(text(c));
    EXPECT_TRUE(c.closed);
    EXPECT_EQ(c.tracks[0].type, TrackType::kCL);
    EXPECT_EQ(c.tracks[1].type, TrackType::kCL);
  }
  EXPECT_GE(sheet_cow, 1u) << text(result);
  EXPECT_EQ(result.counts.pairs_cl_cl, sheet_cow);
}

// ---- permuted input order ----

// The same meshes with vertices renumbered, triangles shuffled and their corners rotated
// (orientation kept). Fixed seed: the same permutation on every run.
std::vector<Mesh> permuted(std::vector<Mesh> meshes, std::uint32_t seed) {
  std::mt19937 random(seed);
  auto shuffle = [&random](std::vector<std::uint32_t>& order) {
    for (std::size_t i = order.size(); i > 1; --i) {
      const std::size_t j = random() % i;  // Fisher-Yates, independent of the library's shuffle
      std::swap(order[i - 1], order[j]);
    }
  };
  for (Mesh& mesh : meshes) {
    std::vector<std::uint32_t> new_index(mesh.positions.size());
    std::iota(new_index.begin(), new_index.end(), 0u);
    shuffle(new_index);
    std::vector<Vec3> positions(mesh.positions.size());
    for (std::size_t v = 0; v < positions.size(); ++v) positions[new_index[v]] = mesh.positions[v];
    std::vector<std::uint32_t> order(mesh.triangles.size());
    std::iota(order.begin(), order.end(), 0u);
    shuffle(order);
    std::vector<Triangle> triangles;
    std::vector<std::uint32_t> polygon;
    for (std::uint32_t t : order) {
      const Triangle& old = mesh.triangles[t];
      const int r = static_cast<int>(random() % 3);
      triangles.push_back(
          {new_index[old[r]], new_index[old[(r + 1) % 3]], new_index[old[(r + 2) % 3]]});
      polygon.push_back(mesh.polygon[t]);
    }
    mesh.positions = std::move(positions);
    mesh.triangles = std::move(triangles);
    mesh.polygon = std::move(polygon);
  }
  return meshes;
}

// What must not depend on input order: per contour, closed/self and its two tracks as (mesh, type,
// separates), as a multiset.
std::multiset<std::tuple<bool, bool, std::array<std::tuple<std::uint32_t, int, bool>, 2>>>
signature(const Intersections& result) {
  std::multiset<std::tuple<bool, bool, std::array<std::tuple<std::uint32_t, int, bool>, 2>>> out;
  for (const Contour& c : result.contours) {
    std::array<std::tuple<std::uint32_t, int, bool>, 2> tracks;
    for (int k = 0; k < 2; ++k) {
      tracks[k] = {c.tracks[k].mesh, static_cast<int>(c.tracks[k].type), c.tracks[k].separates};
    }
    std::sort(tracks.begin(), tracks.end());
    out.insert({c.closed, c.self, tracks});
  }
  return out;
}

void expect_order_independent(const std::vector<Mesh>& meshes) {
  const Intersections reference = find_intersections(meshes);
  ASSERT_GT(reference.contours.size(), 0u);
  for (std::uint32_t seed : {1u, 2u}) {
    SCOPED_TRACE("permutation seed " + std::to_string(seed));
    const Intersections result = find_intersections(permuted(meshes, seed));
    EXPECT_EQ(result.contours.size(), reference.contours.size())
        << "original: " << text(reference) << "\npermuted: " << text(result);
    EXPECT_TRUE(signature(result) == signature(reference))
        << "original: " << text(reference) << "\npermuted: " << text(result);
    EXPECT_EQ(result.counts.crossings, reference.counts.crossings);
    EXPECT_EQ(result.counts.triangle_pairs, reference.counts.triangle_pairs);
    EXPECT_EQ(result.counts.tracks, reference.counts.tracks);
    EXPECT_EQ(result.counts.non_separating, reference.counts.non_separating);
  }
}

class ScenePermuted : public ::testing::TestWithParam<std::size_t> {};

TEST_P(ScenePermuted, SameContoursForPermutedVerticesAndFaces) {
  expect_order_independent(scenes::scene_meshes(scenes::named_scenes()[GetParam()]));
}

INSTANTIATE_TEST_SUITE_P(Scenes, ScenePermuted,
                         ::testing::Range<std::size_t>(0, scenes::named_scenes().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& info) {
                           return scenes::named_scenes()[info.param].name;
                         });

TEST(ScenePermuted, SheetThroughCow) {
  if (scenes::cow_path().empty()) GTEST_SKIP() << kNoCow;
  expect_order_independent(scenes::scene_meshes(scenes::sheet_through_cow(40)));
}

// ---- DetectOptions::separation off changes nothing but separation ----

// Detection and contours with and without the separation floods, at 1 and 2 threads: the same
// crossings, pairs, contours, track types and cut edges bit for bit; without them, every track's
// separates and smaller_area and the count non_separating keep their defaults.
void expect_same_without_separation(const std::vector<Mesh>& meshes, DetectOptions with = {}) {
  for (int threads : {1, 2}) {
    SCOPED_TRACE("threads " + std::to_string(threads));
    with.threads = threads;
    DetectOptions without = with;
    without.separation = false;
    const Intersections a = find_intersections(meshes, with);
    const Intersections b = find_intersections(meshes, without);
    ASSERT_EQ(a.crossings.size(), b.crossings.size());
    for (std::size_t i = 0; i < a.crossings.size(); ++i) {
      const Crossing &x = a.crossings[i], &y = b.crossings[i];
      EXPECT_EQ(std::tie(x.edge_mesh, x.edge_v0, x.edge_v1, x.face_mesh, x.face, x.point),
                std::tie(y.edge_mesh, y.edge_v0, y.edge_v1, y.face_mesh, y.face, y.point))
          << "crossing " << i;
    }
    EXPECT_EQ(a.triangle_pairs, b.triangle_pairs);
    ASSERT_EQ(a.contours.size(), b.contours.size());
    for (std::size_t i = 0; i < a.contours.size(); ++i) {
      SCOPED_TRACE("contour " + std::to_string(i) + ": " + text(a.contours[i]));
      const Contour &c = a.contours[i], &d = b.contours[i];
      EXPECT_EQ(std::tie(c.closed, c.self, c.loop_vertices, c.branch_points, c.crossings,
                         c.polyline, c.length),
                std::tie(d.closed, d.self, d.loop_vertices, d.branch_points, d.crossings,
                         d.polyline, d.length));
      for (int k = 0; k < 2; ++k) {
        const Track &s = c.tracks[k], &t = d.tracks[k];
        EXPECT_EQ(std::tie(s.mesh, s.type, s.boundary_ends, s.cut_edges),
                  std::tie(t.mesh, t.type, t.boundary_ends, t.cut_edges));
        EXPECT_FALSE(t.separates);
        EXPECT_EQ(t.smaller_area, 0.0);
      }
    }
    IntersectionCounts expected = a.counts;
    expected.non_separating = 0;
    const IntersectionCounts& got = b.counts;
    EXPECT_EQ(
        std::tie(expected.crossings, expected.triangle_pairs, expected.contours,
                 expected.contour_length, expected.tracks, expected.pairs_cl_cl,
                 expected.pairs_bb_ii, expected.pairs_bi_bi, expected.pairs_self,
                 expected.pairs_other, expected.loop_vertices, expected.non_separating,
                 expected.branch_points, expected.broken),
        std::tie(got.crossings, got.triangle_pairs, got.contours, got.contour_length, got.tracks,
                 got.pairs_cl_cl, got.pairs_bb_ii, got.pairs_bi_bi, got.pairs_self, got.pairs_other,
                 got.loop_vertices, got.non_separating, got.branch_points, got.broken));
  }
}

TEST(SceneWithoutSeparation, EveryNamedScene) {
  for (const Scene& scene : scenes::named_scenes()) {
    SCOPED_TRACE(scene.name);
    expect_same_without_separation(scenes::scene_meshes(scene));
  }
}

// The benchmark's scene (bench/bench_detect.cpp): between the meshes only, as there, and with
// self-intersections; both tracks of its contour separate when the floods run.
TEST(SceneWithoutSeparation, SheetThroughCow) {
  if (scenes::cow_path().empty()) GTEST_SKIP() << kNoCow;
  const std::vector<Mesh> meshes = scenes::scene_meshes(scenes::sheet_through_cow(81));
  DetectOptions between;
  between.self_intersections = false;
  const Intersections result = find_intersections(meshes, between);
  ASSERT_FALSE(result.contours.empty());
  for (const Contour& c : result.contours)
    for (const Track& t : c.tracks) EXPECT_TRUE(t.separates && t.smaller_area > 0.0) << text(c);
  expect_same_without_separation(meshes, between);
  expect_same_without_separation(meshes);
}

// ---- testdata/ is what the generator makes ----

class SceneTestdata : public ::testing::TestWithParam<std::size_t> {};

// Compares one written mesh with the generated one: same triangles, corners at the same positions
// (within float precision: the reader may go through single-precision assimp).
void expect_same_mesh(const std::string& path, Role role, const Mesh& generated) {
  SCOPED_TRACE(path);
  ASSERT_TRUE(std::filesystem::exists(path))
      << "missing; regenerate with: build/untangle_gen_scenes testdata";
  const std::vector<Mesh> read = read_meshes(path, role);
  ASSERT_EQ(read.size(), 1u);
  const Mesh& mesh = read[0];
  EXPECT_EQ(mesh.role, role);
  ASSERT_EQ(mesh.triangles.size(), generated.triangles.size())
      << "out of date; regenerate with: build/untangle_gen_scenes testdata";
  double size = 0.0;
  for (const Vec3& p : generated.positions) {
    for (double c : p) size = std::max(size, std::abs(c));
  }
  const double tolerance = 1e-6 * std::max(size, 1.0);
  std::size_t far = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      const Vec3& a = mesh.positions[mesh.triangles[t][k]];
      const Vec3& b = generated.positions[generated.triangles[t][k]];
      for (int d = 0; d < 3; ++d) {
        if (std::abs(a[d] - b[d]) > tolerance) ++far;
      }
    }
  }
  EXPECT_EQ(far, 0u) << "corner coordinates differ from the generator's; regenerate with: "
                        "build/untangle_gen_scenes testdata";
}

TEST_P(SceneTestdata, MatchesTheGenerator) {
  const Scene scene = scenes::named_scenes()[GetParam()];
  const std::filesystem::path dir =
      std::filesystem::path(UNTANGLE_SOURCE_DIR) / "testdata" / scene.name;
  ASSERT_TRUE(std::filesystem::is_directory(dir))
      << dir.string() << " missing; regenerate with: build/untangle_gen_scenes testdata";
  std::size_t movable_files = 0, obstacle_files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string file = entry.path().filename().string();
    if (entry.path().extension() != ".obj") continue;
    if (file.rfind("movable_", 0) == 0) ++movable_files;
    if (file.rfind("obstacle_", 0) == 0) ++obstacle_files;
  }
  EXPECT_EQ(movable_files, scene.movable.size());
  EXPECT_EQ(obstacle_files, scene.obstacles.size());
  for (std::size_t i = 0; i < scene.movable.size(); ++i) {
    expect_same_mesh((dir / ("movable_" + std::to_string(i) + ".obj")).string(), Role::kMovable,
                     scene.movable[i]);
  }
  for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
    expect_same_mesh((dir / ("obstacle_" + std::to_string(i) + ".obj")).string(), Role::kObstacle,
                     scene.obstacles[i]);
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, SceneTestdata,
                         ::testing::Range<std::size_t>(0, scenes::named_scenes().size()),
                         [](const ::testing::TestParamInfo<std::size_t>& info) {
                           return scenes::named_scenes()[info.param].name;
                         });

// write_obj keeps every double exactly (%.17g round-trips).
TEST(SceneTestdata, WriteObjRoundTripsDoubles) {
  Mesh mesh = scenes::grid_sheet(2, 2, {0.1, 1.0 / 3.0, -2e-300}, {std::sqrt(2.0), 0.0, 0.0},
                                 {0.0, 1e10 / 7.0, 0.0}, "sheet");
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "untangle_test_scenes_write_obj.obj";
  scenes::write_obj(mesh, path.string());
  std::FILE* file = std::fopen(path.string().c_str(), "r");
  ASSERT_NE(file, nullptr);
  std::vector<Vec3> read;
  char line[256];
  while (std::fgets(line, sizeof line, file) != nullptr) {
    Vec3 p{};
    if (std::sscanf(line, "v %lf %lf %lf", &p[0], &p[1], &p[2]) == 3) read.push_back(p);
  }
  std::fclose(file);
  std::filesystem::remove(path);
  EXPECT_EQ(read, mesh.positions);
}

}  // namespace
}  // namespace untangle
