// closest_on, the resolve stage's closest-point query on its own hierarchy: against every triangle
// projected by brute force, the point it gives is as near as the nearest (decided exactly, or by
// the rounded distances between the triangles holding a point on an edge or a corner), on the
// named scenes (coincident, coplanar and snapped ones among them), for points on the surface
// (vertices, edge midpoints), near it and far from it, at the scene's size and (every third point)
// scaled by 2^-30 and 2^30, where its filter's tolerance is relative.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "geometry/vec3.h"
#include "resolve/mesh_tree_cgal.h"
#include "resolve/surface_queries.h"
#include "scenes/scenes.h"
#include "topology/scene_topology.h"

namespace untangle {
namespace {

// The nearest projection over all triangles of `tree`, decided exactly.
TreeKernel::Point_3 brute_nearest(const MeshTree& tree, const TreeKernel::Point_3& q) {
  const auto project = TreeKernel().construct_projected_point_3_object();
  TreeKernel::Point_3 best = project(tree.cgal->triangles[0], q);
  for (std::size_t k = 1; k < tree.cgal->triangles.size(); ++k) {
    const TreeKernel::Point_3 c = project(tree.cgal->triangles[k], q);
    if (CGAL::compare_distance_to_point(q, c, best) == CGAL::SMALLER) best = c;
  }
  return best;
}

// The points asked about: every vertex of the scene, every edge's midpoint, and as many points
// drawn in the scene's box grown by half its size.
std::vector<Vec3> query_points(const SceneTopology& topo, std::mt19937& rng) {
  std::vector<Vec3> out = topo.points;
  for (const auto& e : topo.edges)
    out.push_back(scale(add(topo.points[e[0]], topo.points[e[1]]), 0.5));
  Vec3 lo = topo.points[0], hi = lo;
  for (const Vec3& p : topo.points)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  const std::size_t n = topo.points.size();
  for (std::size_t i = 0; i < n; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      const double half = 0.5 * (hi[k] - lo[k]);
      std::uniform_real_distribution<double> along(lo[k] - half, hi[k] + half);
      p[k] = along(rng);
    }
    out.push_back(p);
  }
  return out;
}

// Every `stride`-th of the query points (the brute force costs a projection on every triangle).
void check_meshes(const std::vector<Mesh>& meshes, const std::string& name,
                  std::size_t stride = 1) {
  const SceneTopology topo = build_topology(meshes);
  std::mt19937 rng(7);
  std::vector<Vec3> points;
  const std::vector<Vec3> all = query_points(topo, rng);
  for (std::size_t i = 0; i < all.size(); i += stride) points.push_back(all[i]);
  const std::size_t mesh_count = topo.mesh_tri_begin.size() - 1;
  for (std::size_t m = 0; m < mesh_count; ++m) {
    std::vector<std::uint32_t> tris;
    for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1]; ++t)
      tris.push_back(t);
    if (tris.empty()) continue;
    const std::unique_ptr<MeshTree> tree = build_tree(topo, tris);
    int wrong = 0;
    for (const Vec3& p : points) {
      const TreeKernel::Point_3 q(p[0], p[1], p[2]);
      const Closest got = closest_on(*tree, p);
      const TreeKernel::Point_3 c(got.point[0], got.point[1], got.point[2]);
      // As near as the nearest, exactly; or, where the point lies on an edge or a corner and the
      // triangles holding it were compared by their rounded distances, as near in doubles.
      const TreeKernel::Point_3 best = brute_nearest(*tree, q);
      const bool nearest = CGAL::compare_distance_to_point(q, c, best) == CGAL::EQUAL ||
                           got.squared <= CGAL::squared_distance(q, best);
      // The point lies on the face it names: its projection there is the point itself.
      std::size_t entry = 0;
      while (entry < tree->ids.size() && tree->ids[entry] != got.face) ++entry;
      const bool on_face =
          entry < tree->ids.size() &&
          TreeKernel().construct_projected_point_3_object()(tree->cgal->triangles[entry], q) == c;
      const bool squared = got.squared == CGAL::squared_distance(q, c);
      if ((!nearest || !on_face || !squared) && ++wrong <= 3)
        ADD_FAILURE() << name << " mesh " << m << ": point (" << p[0] << ", " << p[1] << ", "
                      << p[2] << ") nearest " << nearest << ", on its face " << on_face
                      << ", squared distance " << squared;
    }
    EXPECT_EQ(wrong, 0) << name << " mesh " << m << " of " << points.size() << " points";
  }
}

std::vector<Mesh> scaled(std::vector<Mesh> meshes, double factor) {
  for (Mesh& mesh : meshes)
    for (Vec3& p : mesh.positions) p = scale(p, factor);
  return meshes;
}

TEST(ClosestPoints, NearestOfEveryTriangleOnTheNamedScenes) {
  for (const scenes::Scene& scene : scenes::named_scenes()) {
    const std::vector<Mesh> meshes = scenes::scene_meshes(scene);
    check_meshes(meshes, scene.name);
    check_meshes(scaled(meshes, std::ldexp(1.0, -30)), scene.name + " x 2^-30", 3);
    check_meshes(scaled(meshes, std::ldexp(1.0, 30)), scene.name + " x 2^30", 3);
  }
}

TEST(ClosestPoints, NearestOfEveryTriangleOnTheSheetThroughTheCow) {
  if (scenes::cow_path().empty()) GTEST_SKIP() << "the cow (libcgal-demo) is not installed";
  check_meshes(scenes::scene_meshes(scenes::sheet_through_cow(21)), "sheet through the cow", 4);
}

}  // namespace
}  // namespace untangle
