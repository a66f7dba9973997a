// Queries against "the other surface" of a move: closest-point and ray trees per component,
// vertices near a surface and their sides, oriented face and vertex normals.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <vector>

#include "detect/triangle_bvh.h"
#include "resolve/scene_measures.h"
#include "topology/scene_topology.h"

namespace untangle {

struct MeshTreeCgal;  // resolve/mesh_tree_cgal.h

// The closest-point structure of some triangles at the positions it was built at: our own
// hierarchy over their boxes for closest points (closest_on), CGAL's tree for rays
// (first_ray_hit), built at the first ray: most trees never meet one, and CGAL's build with its
// distance acceleration was 14% of the shipped pair's `fix` (issue 24). The entries' CGAL
// triangles and that tree are behind a pointer, so that the many files that include this header
// do not parse CGAL's tree (7.6 s of every compile of theirs).
struct MeshTree {
  MeshTree();
  ~MeshTree();
  std::vector<std::uint32_t> ids;      // global triangle id per entry
  TriangleBvh boxes;                   // over the entries
  std::unique_ptr<MeshTreeCgal> cgal;  // the entries' triangles, and the ray tree
  bool empty() const { return ids.empty(); }
};

// Trees of movable components, built for one step (their positions change between steps).
using FreshTrees = std::map<std::uint32_t, std::unique_ptr<MeshTree>>;

// A tree over triangles `tris` (global ids) at the topology's current positions.
std::unique_ptr<MeshTree> build_tree(const SceneTopology& topo,
                                     const std::vector<std::uint32_t>& tris);

// The point of `tree` closest to `p`, the triangle it lies on (global id) and its squared
// distance. Triangles equally close (the point at a corner or on an edge they share) give the
// lowest id, and the point is projected onto that triangle here: CGAL's own answer is whichever
// its traversal met first, and the traversal follows the coordinates, so a scene turned half round
// an axis could be given another triangle (another normal, another side) and another point.
struct Closest {
  Vec3 point;
  std::uint32_t face = 0;
  double squared = 0.0;
};
Closest closest_on(const MeshTree& tree, const Vec3& p);

// The first point where the ray from `from` along `direction` meets a triangle of `tree` in one
// point (a ray in the plane of the triangle it meets first, which meets it along a segment, gives
// none): false when it meets nothing. CGAL picks the triangle (along the direction scaled to the
// tree's box diagonal, so that the pick too is the same in any unit); the point is computed here
// from its corners, homogeneously in the coordinates, so that a scene scaled by a power of two
// gives the same point scaled, bit for bit (CGAL's constructed intersection point does not:
// measured on the MakeHuman body, the last bits differed at 1024 times the size, and the region
// moves with them).
bool first_ray_hit(const MeshTree& tree, const Vec3& from, const Vec3& direction, Vec3& out);

// The unit normal of triangle t by its winding.
Vec3 face_normal(const SceneTopology& topo, std::uint32_t t);
// The unit normal of triangle t turned by its orientation sign (face_orientations).
Vec3 oriented_normal(const SceneTopology& topo, const SceneMeasures& measures, std::uint32_t t);
// The normal of vertex v: the sum of its faces' area vectors, each turned by its orientation sign.
Vec3 oriented_vertex_normal(const SceneTopology& topo, const SceneMeasures& measures,
                            std::uint32_t v);
// Whether point `c` on triangle t lies on one of its boundary edges (the mesh's hem).
bool on_hem(const SceneTopology& topo, std::uint32_t t, const Vec3& c);

// The closest-point trees of whole components.
class SurfaceTrees {
 public:
  SurfaceTrees(const SceneTopology& topo, const SceneMeasures& measures)
      : topo_(topo), measures_(measures) {}
  // The tree of a whole component: kept for the run when the component is an obstacle (it never
  // moves), built into `fresh` for this step otherwise. A closed obstacle that passes through
  // itself (the cow's tail through its rump) leaves out its buried faces: a point on one, or a
  // ray's exit through one, is still inside the obstacle.
  const MeshTree& component_tree(std::uint32_t component, FreshTrees& fresh);
  // The point of the nearest closed obstacle component to `p`, if the scene has one.
  bool nearest_obstacle_point(const Vec3& p, Vec3& out);
  // The tree over obstacle triangles `tris` (global ids, ascending), kept for the run like a
  // component's: the same list as a component tree already built (one obstacle component) is
  // that tree.
  const MeshTree& obstacle_tree(const std::vector<std::uint32_t>& tris);

 private:
  const SceneTopology& topo_;
  const SceneMeasures& measures_;
  std::map<std::uint32_t, std::unique_ptr<MeshTree>> obstacle_trees_;
  std::vector<std::unique_ptr<MeshTree>> obstacle_lists_;  // obstacle_tree's of other lists
};

// A vertex of one component near another: its closest point there, that face's oriented normal,
// the signed distance along it.
struct NearPoint {
  std::uint32_t v;
  std::uint32_t face;
  Vec3 c, n;
  double side;
};

// The vertices of `component` within `near` of `tree`, and the vote of their sides (+1 for each
// on the positive side of the closest face, -1 for each on the negative side).
std::vector<NearPoint> near_points(const SceneTopology& topo, const SceneMeasures& measures,
                                   std::uint32_t component, const MeshTree& tree, double near,
                                   long long& vote);
// The vote of near vertices' sides weighted by their areas (a third of their faces'), over their
// total area: from -1 (all on the negative side) to 1. A garment finer in one place than another
// still votes by how much of it lies on each side.
double area_vote(const SceneTopology& topo, const std::vector<NearPoint>& near);

}  // namespace untangle
