// buried_faces (lib/src/resolve): the faces of closed obstacles that lie inside an obstacle, or on
// a curve where obstacles pass through themselves or each other. Judged independently with CGAL:
// a face is expected buried when it intersects a face of another surface (CGAL's exact
// do_intersect on the AABB tree) or its centroid is inside the other surface
// (Side_of_triangle_mesh).
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <random>
#include <vector>

#include "cgal_reference.h"
#include "detect/triangle_bvh.h"
#include "resolve/buried_faces.h"
#include "resolve/region_analysis.h"
#include "scenes/random_tangles.h"
#include "scenes/scenes.h"
#include "scenes/self_scenes.h"
#include "topology/scene_topology.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"
#include "untangle/mesh_info.h"

namespace untangle {
namespace {

using cgal_reference::Kernel;
using cgal_reference::SurfaceMesh;
using FacePrimitive = CGAL::AABB_face_graph_triangle_primitive<SurfaceMesh>;
using FaceTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, FacePrimitive>>;

// Every component of the scene's obstacles as a closed surface, with its orientation.
std::vector<ClosedSurface> closed_surfaces(const SceneTopology& topo) {
  const std::vector<int> orientation = closed_orientations(topo);
  std::vector<ClosedSurface> out(topo.component_mesh.size());
  for (std::uint32_t c = 0; c < out.size(); ++c) out[c].orientation = orientation[c];
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
    out[topo.tri_component(t)].triangles.push_back(t);
  return out;
}

std::size_t count(const std::vector<std::uint8_t>& flags) {
  std::size_t n = 0;
  for (std::uint8_t f : flags) n += f;
  return n;
}

// Two closed spheres of one obstacle mesh (two components), overlapping: a face of one is buried
// exactly when it meets the other sphere or its centroid lies inside it.
void expect_overlap_judged(double radius_b, const Vec3& offset, int threads) {
  const Mesh a = scenes::uv_sphere({0.0, 0.0, 0.0}, 1.0, 32, 16, "a");
  const Mesh b = scenes::uv_sphere(offset, radius_b, 28, 14, "b");
  const Mesh both = scenes::merged(a, b, "both");
  const SceneTopology topo = build_topology({both});
  const std::vector<ClosedSurface> surfaces = closed_surfaces(topo);
  ASSERT_EQ(surfaces.size(), 2u);
  ASSERT_EQ(surfaces[0].orientation, 1);
  ASSERT_EQ(surfaces[1].orientation, 1);
  const std::vector<std::vector<std::uint8_t>> buried = buried_faces(topo, surfaces, threads);
  ASSERT_EQ(buried.size(), 2u);

  const Mesh* sphere[2] = {&a, &b};
  std::size_t total = 0;
  for (int s = 0; s < 2; ++s) {
    const cgal_reference::ReferenceMesh other = cgal_reference::to_reference_mesh(*sphere[1 - s]);
    const FaceTree tree(faces(other.mesh).first, faces(other.mesh).second, other.mesh);
    const CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel> inside(other.mesh);
    ASSERT_EQ(buried[s].size(), surfaces[s].triangles.size());
    for (std::size_t k = 0; k < surfaces[s].triangles.size(); ++k) {
      const auto& tri = topo.tris[surfaces[s].triangles[k]];
      auto p = [&](int i) {
        const Vec3& v = topo.points[tri[i]];
        return Kernel::Point_3(v[0], v[1], v[2]);
      };
      const Kernel::Triangle_3 t(p(0), p(1), p(2));
      const bool meets = tree.do_intersect(t);
      const bool centroid_in = inside(CGAL::centroid(t)) == CGAL::ON_BOUNDED_SIDE;
      EXPECT_EQ(buried[s][k] != 0, meets || centroid_in)
          << "surface " << s << " face " << k << ": meets the other " << meets
          << ", centroid inside it " << centroid_in;
    }
    total += count(buried[s]);
  }
  EXPECT_GT(total, 0u);
}

TEST(BuriedFaces, ClosedSurfaceThatMeetsNothingHasNone) {
  const SceneTopology topo = build_topology({scenes::uv_sphere({0.0, 0.0, 0.0}, 1.0, 48, 24, "s")});
  const std::vector<std::vector<std::uint8_t>> buried =
      buried_faces(topo, closed_surfaces(topo), 0);
  ASSERT_EQ(buried.size(), 1u);
  EXPECT_EQ(count(buried[0]), 0u);
}

// A small sphere wholly inside a large one: every face of the small one is buried (no curve
// crosses it; its one region is judged by the winding number), none of the large one.
TEST(BuriedFaces, SurfaceInsideAnotherIsBuriedWhole) {
  const Mesh both =
      scenes::merged(scenes::uv_sphere({0.0, 0.0, 0.0}, 1.0, 32, 16, "outer"),
                     scenes::uv_sphere({0.11, -0.07, 0.05}, 0.4, 24, 12, "inner"), "both");
  const SceneTopology topo = build_topology({both});
  const std::vector<ClosedSurface> surfaces = closed_surfaces(topo);
  ASSERT_EQ(surfaces.size(), 2u);
  const std::vector<std::vector<std::uint8_t>> buried = buried_faces(topo, surfaces, 0);
  EXPECT_EQ(count(buried[0]), 0u);
  EXPECT_EQ(count(buried[1]), surfaces[1].triangles.size());
}

TEST(BuriedFaces, OverlappingSpheresAgreeWithCgal) {
  expect_overlap_judged(0.6, {0.83, 0.17, -0.11}, 1);
  expect_overlap_judged(0.6, {0.83, 0.17, -0.11}, 2);
  expect_overlap_judged(0.45, {-0.31, 0.62, 0.29}, 0);
}

// Turned inside out (every triangle reversed), both spheres are closed and oriented inward: the
// same faces are buried.
TEST(BuriedFaces, InwardOrientationGivesTheSameFaces) {
  Mesh both = scenes::merged(scenes::uv_sphere({0.0, 0.0, 0.0}, 1.0, 32, 16, "a"),
                             scenes::uv_sphere({0.83, 0.17, -0.11}, 0.6, 28, 14, "b"), "both");
  const SceneTopology outward = build_topology({both});
  for (Triangle& t : both.triangles) std::swap(t[1], t[2]);
  const SceneTopology inward = build_topology({both});
  const std::vector<ClosedSurface> in_surfaces = closed_surfaces(inward);
  ASSERT_EQ(in_surfaces[0].orientation, -1);
  EXPECT_EQ(buried_faces(inward, in_surfaces, 0),
            buried_faces(outward, closed_surfaces(outward), 0));
}

// The cow of Debian's libcgal-demo passes through itself where its tail meets its rump: faces
// there are buried, and none far from the tail.
TEST(BuriedFaces, TheCowsTailThroughItsRump) {
  if (scenes::cow_path().empty()) GTEST_SKIP() << "the cow (libcgal-demo) is not installed";
  const scenes::Scene scene = scenes::sheet_over_cow_rump(0.2053, 5);
  const SceneTopology topo = build_topology(scene.obstacles);
  const std::vector<ClosedSurface> surfaces = closed_surfaces(topo);
  ASSERT_EQ(surfaces.size(), 1u);
  ASSERT_EQ(surfaces[0].orientation, 1);
  const std::vector<std::vector<std::uint8_t>> buried = buried_faces(topo, surfaces, 0);
  EXPECT_GT(count(buried[0]), 10u);
  EXPECT_LT(count(buried[0]), 200u);
  for (std::size_t k = 0; k < buried[0].size(); ++k) {
    if (!buried[0][k]) continue;
    const auto& tri = topo.tris[surfaces[0].triangles[k]];
    for (std::uint32_t v : tri)
      EXPECT_LT(topo.points[v][0], -0.3) << "buried face " << k << " far from the tail";
  }
  EXPECT_EQ(buried_faces(topo, surfaces, 1), buried);
}

// Ten crumpled closed spheres (every vertex moved by up to 0.3 of the radius: they pass through
// themselves in many places; every other one with a zero-area triangle) as obstacles, a sheet
// through each. The pass that finds the buried faces also counts the obstacle's crossing triangle
// pairs: that count must equal detection's on the obstacle alone, exactly. The repair (a few
// iterations: the pass is under test, not the repair) never moves the obstacle, gives the same
// positions at one and two threads, and writes a state with no more crossings than the input.
TEST(BuriedFaces, CrumpledSpheresAsObstacles) {
  std::mt19937_64 random(20261201);
  auto uniform = [&](double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(random() >> 11) * 0x1.0p-53;
  };
  std::size_t crossing_obstacles = 0;
  for (int k = 0; k < 10; ++k) {
    SCOPED_TRACE("crumpled sphere " + std::to_string(k));
    Mesh sphere = scenes::uv_sphere({0.0, 0.0, 0.0}, 1.0, 10 + k % 7, 6 + k % 5, "crumpled");
    for (Vec3& p : sphere.positions)
      for (double& c : p) c += uniform(-0.3, 0.3);
    if (k % 2 == 1) {
      // A zero-area triangle (collinear corners, still three positions): legal input, and the
      // rays of the winding numbers meet it.
      const Triangle t = sphere.triangles[sphere.triangles.size() / 2];
      for (int i = 0; i < 3; ++i)
        sphere.positions[t[2]][i] = 0.5 * (sphere.positions[t[0]][i] + sphere.positions[t[1]][i]);
      ASSERT_GE(describe_mesh(sphere).zero_area_triangles, 1u);
    }
    sphere.role = Role::kObstacle;
    const Mesh sheet = scenes::grid_sheet(17, 17, {-1.6, -1.6, uniform(-0.3, 0.3)}, {3.2, 0.0, 0.0},
                                          {0.0, 3.2, 0.0}, "sheet");
    const std::size_t pairs = find_intersections({sphere}).counts.triangle_pairs;
    const std::vector<Mesh> input{sheet, sphere};
    std::vector<std::vector<Mesh>> results;
    for (int threads : {1, 2}) {
      std::vector<Mesh> meshes = input;
      FixOptions options;
      options.threads = threads;
      options.max_iterations = 6;  // the property, not the repair, is under test
      const FixResult result = fix_meshes(meshes, options);
      EXPECT_EQ(meshes[1].positions, sphere.positions) << "the obstacle moved";
      if (closed_orientations(build_topology({sphere}))[0] != 0)
        EXPECT_EQ(result.obstacle_crossing_pairs, pairs);
      else
        EXPECT_EQ(result.obstacle_crossing_pairs, 0u) << "not closed and oriented: not looked at";
      // The best state counts vertices inside an obstacle like crossings (DESIGN §4).
      EXPECT_LE(result.after.crossings + result.after.inside_vertices,
                result.before.crossings + result.before.inside_vertices)
          << "the best state is written";
      if (threads == 1) crossing_obstacles += pairs > 0 ? 1 : 0;
      results.push_back(meshes);
    }
    EXPECT_EQ(results[0][0].positions, results[1][0].positions) << "depends on the thread count";
  }
  EXPECT_GE(crossing_obstacles, 5u) << "the spheres were meant to pass through themselves";
}

// The pass skips the pairs inside flat patches (as detection's self pairs do). Two boxes through
// each other as one closed obstacle, turned to no special direction: their faces are flat
// patches, and the patches of one box cross those of the other. The crossing pairs the pass
// counts are CGAL's self-intersecting pairs of the mesh, one for one, at one and two threads.
TEST(BuriedFaces, FlatPatchesSkippedSamePairsAsCgal) {
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE("boxes " + std::to_string(k));
    const Mesh a = scenes::rotated(scenes::box_surface({0, 0, 0}, {1.0, 0.7, 0.5}, 5 + k, "a"), 0,
                                   0.3137 + 0.1 * k, {0.0131, -0.0217, 0.0071});
    const Mesh b = scenes::rotated(scenes::box_surface({0.6, 0.2, 0.1}, {0.8, 0.6, 0.9}, 4 + k, "b"),
                                   1, 0.7411 - 0.2 * k, {0.2113, 0.1031, -0.0519});
    Mesh both = scenes::merged(a, b, "boxes");
    both.role = Role::kObstacle;
    const SceneTopology topo = build_topology({both});
    const std::vector<ClosedSurface> surfaces = closed_surfaces(topo);
    ASSERT_EQ(surfaces.size(), 2u);  // one per box
    std::vector<std::uint32_t> all = surfaces[0].triangles;
    all.insert(all.end(), surfaces[1].triangles.begin(), surfaces[1].triangles.end());
    std::sort(all.begin(), all.end());
    TriangleBvh bvh(topo, all);
    bvh.mark_flat_patches(topo);
    EXPECT_GT(bvh.flat_patch_triangles(), both.triangles.size() / 2) << "the faces are patches";
    const std::size_t cgal_pairs = cgal_reference::triangle_pairs({both}).size();
    EXPECT_GT(cgal_pairs, 10u);
    for (int threads : {1, 2}) {
      std::size_t pairs = 0;
      const std::vector<std::vector<std::uint8_t>> buried = buried_faces(topo, surfaces, threads, &pairs);
      EXPECT_EQ(pairs, cgal_pairs);
      EXPECT_GT(count(buried[0]) + count(buried[1]), 0u);  // faces of one box inside the other
    }
  }
}

}  // namespace
}  // namespace untangle
