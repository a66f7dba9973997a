// Which movable vertices lie inside an obstacle, by the obstacles' generalized winding numbers
// (DESIGN §4): for every obstacle, closed or not.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "resolve/winding_number.h"
#include "topology/scene_topology.h"
#include "untangle/mesh.h"

namespace untangle {

// A point is inside an obstacle mesh where that mesh's winding number exceeds 1/2. Each obstacle
// mesh is one soup (all its components together: an open body with holes, limbs through each
// other); one whose signed volume is negative (inside out) is read turned round. Only a nearly
// closed mesh has an inside: the vector areas of its holes (each connected chain of boundary
// edges) sum to at most kMaxHoleArea of its area (eye holes in a body, not a sheet, an arc or a
// short open tube, whose winding number exceeds 1/2 in their hollows too).
class ObstacleWinding {
 public:
  static constexpr double kMaxHoleArea = 0.05;

  // The obstacle meshes of `topo` (role per mesh) at its current positions; each hierarchy built
  // on `threads` threads (0: all cores), the same for every count.
  ObstacleWinding(const SceneTopology& topo, const std::vector<Role>& role, int threads = 1);
  // The winding number of obstacle mesh `mesh` at p, turned for an inside-out mesh (0 for a
  // movable mesh and for an obstacle without an inside).
  double winding(std::uint32_t mesh, const Vec3& p) const;
  // The first obstacle mesh p lies inside, or kNone.
  std::uint32_t inside(const Vec3& p) const;
  bool inside_out(std::uint32_t mesh) const { return sign_[mesh] < 0; }
  bool any() const { return !obstacles_.empty(); }

 private:
  std::vector<std::uint32_t> obstacles_;  // obstacle mesh ids, ascending
  std::vector<WindingNumber> numbers_;    // per entry of obstacles_
  std::vector<std::uint32_t> slot_;       // per mesh: index into numbers_, or kNone
  std::vector<double> sign_;              // per mesh: +1, or -1 when inside out
};

// Per welded vertex: the obstacle mesh it lies inside, kNone for outside and for obstacle
// vertices. Only the vertices with `update[v]` set are evaluated again (all when `update` is
// empty); `inside` keeps its other entries. Parallel over vertices, each into its own slot.
void find_inside_vertices(const SceneTopology& topo, const std::vector<Role>& role,
                          const ObstacleWinding& winding, const std::vector<std::uint8_t>& update,
                          int threads, std::vector<std::uint32_t>& inside);

// Per mesh, how many of its welded vertices `inside` marks (0 for obstacles).
std::vector<std::size_t> inside_per_mesh(const SceneTopology& topo,
                                         const std::vector<std::uint32_t>& inside);

}  // namespace untangle
