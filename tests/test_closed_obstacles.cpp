// Closed obstacles decide which side is illegal (issue 4, DESIGN §4): a panel mostly inside a body
// comes out, where "the smaller region is illegal" (--orientation-free) would push its corners in.
// Judged independently of untangle: CGAL's Side_of_triangle_mesh on the body.
#include <gtest/gtest.h>

#include <CGAL/Side_of_triangle_mesh.h>

#include <cstddef>
#include <vector>

#include "cgal_reference.h"
#include "scenes/scenes.h"
#include "untangle/fix.h"
#include "untangle/intersections.h"

namespace untangle {
namespace {

using cgal_reference::Kernel;
using cgal_reference::SurfaceMesh;

// Panel vertices strictly inside the body.
std::size_t inside_count(const Mesh& panel, const Mesh& body) {
  const cgal_reference::ReferenceMesh ref = cgal_reference::to_reference_mesh(body);
  const CGAL::Side_of_triangle_mesh<SurfaceMesh, Kernel> side(ref.mesh);
  std::size_t inside = 0;
  for (const Vec3& p : panel.positions)
    if (side(Kernel::Point_3(p[0], p[1], p[2])) == CGAL::ON_BOUNDED_SIDE) ++inside;
  return inside;
}

struct Outcome {
  FixResult result;
  std::size_t inside = 0;
};

// The rules alone: the continuation (which shrinks the body under the panel) left out.
Outcome repair(bool outside_closed_obstacles, bool continuation = false) {
  std::vector<Mesh> meshes = scenes::scene_meshes(scenes::panel_in_body());
  FixOptions options;
  options.outside_closed_obstacles = outside_closed_obstacles;
  options.continuation = continuation;
  Outcome o;
  const std::vector<Vec3> body = meshes[1].positions;
  o.result = fix_meshes(meshes, options);
  o.inside = inside_count(meshes[0], meshes[1]);
  EXPECT_EQ(meshes[1].positions, body) << "the body moved (the continuation shrinks and restores it)";
  return o;
}

TEST(ClosedObstacles, PanelMostlyInsideTheBody) {
  std::vector<Mesh> meshes = scenes::scene_meshes(scenes::panel_in_body());
  const std::size_t vertices = meshes[0].positions.size();
  const std::size_t inside_before = inside_count(meshes[0], meshes[1]);
  ASSERT_GT(inside_before, vertices / 2) << "the scene must put most of the panel inside";
  ASSERT_LT(inside_before, vertices);
  const Intersections found = find_intersections(meshes);
  ASSERT_EQ(found.counts.contours, 4u);
  for (const Contour& c : found.contours) EXPECT_EQ(c.tracks[c.tracks[0].mesh == 0 ? 0 : 1].type, TrackType::kBB);

  // The body's inside decides: the middle comes out, nothing of the panel stays in.
  const Outcome by_inside = repair(true);
  EXPECT_TRUE(by_inside.result.clean);
  EXPECT_EQ(by_inside.inside, 0u);
  EXPECT_GT(by_inside.result.illegal_regions_by_inside, 0u);

  // "The smaller region is illegal": the corners are the smaller side and are pushed in. Without
  // a crossing left the panel would be in the body; the winding number sees it there and moves
  // what it can out (inside vertices are illegal under either rule).
  const Outcome by_area = repair(false);
  EXPECT_GT(by_area.result.illegal_regions_by_area, 0u);
  EXPECT_EQ(by_area.result.illegal_regions_by_inside, 0u);
  // The area rule still leaves part of the panel inside; the winding number's count agrees with
  // CGAL's independent inside test, and such a result is never reported clean.
  EXPECT_GT(by_area.inside, 0u) << "the area rule was expected to leave the panel partly inside";
  EXPECT_EQ(by_area.result.after.inside_vertices, by_area.inside);
  EXPECT_FALSE(by_area.result.clean) << "reported clean with vertices inside the body";

  // With the continuation the body shrinks under the panel first, so even the area rule gets it
  // out: every step is a shallow penetration.
  const Outcome continued = repair(false, true);
  EXPECT_TRUE(continued.result.continuation.ran);
  EXPECT_TRUE(continued.result.continuation.kept);
  EXPECT_TRUE(continued.result.clean);
  EXPECT_EQ(continued.inside, 0u);
}

}  // namespace
}  // namespace untangle
