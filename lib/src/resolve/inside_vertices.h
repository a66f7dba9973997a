// Which movable vertices lie inside an obstacle, by the obstacles' generalized winding numbers
// (DESIGN §4): for every obstacle, closed or not.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "detect/detect_crossings.h"
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
  // A hole of an obstacle with an inside: the mean of its boundary vertices and the largest
  // distance from there to one of them (a ball holding the fan that would close it).
  struct Hole {
    Vec3 centre{};
    double radius = 0.0;
  };

  // The obstacle meshes of `topo` (role per mesh) at its current positions; each hierarchy built
  // on `threads` threads (0: all cores), the same for every count. An obstacle whose triangles
  // are those one of `earlier`'s hierarchies was built from (WindingNumber::built_from) shares
  // that hierarchy instead of building it again: the same values (the obstacles never move, and
  // a run detects them several times; issue 24).
  ObstacleWinding(const SceneTopology& topo, const std::vector<Role>& role, int threads = 1,
                  const ObstacleWinding* earlier = nullptr);
  // The winding number of obstacle mesh `mesh` at p, turned for an inside-out mesh (0 for a
  // movable mesh and for an obstacle without an inside).
  double winding(std::uint32_t mesh, const Vec3& p) const;
  // The first obstacle mesh p lies inside, or kNone.
  std::uint32_t inside(const Vec3& p) const;
  // As inside(p), and whether every obstacle's winding number at p lies within 1/4 of an integer
  // with p in no plane of a triangle it was summed over (false on or at rounding distance from a
  // surface, where the value may be either side's, and near a hole).
  bool inside_clearly(const Vec3& p, std::uint32_t& first) const;
  bool inside_out(std::uint32_t mesh) const { return sign_[mesh] < 0; }
  bool any() const { return !obstacles_.empty(); }
  // The holes of all obstacles with an inside.
  const std::vector<Hole>& holes() const { return holes_; }

 private:
  std::vector<std::uint32_t> obstacles_;  // obstacle mesh ids, ascending
  std::vector<std::shared_ptr<const WindingNumber>> numbers_;  // per entry of obstacles_
  std::vector<std::uint32_t> slot_;       // per mesh: index into numbers_, or kNone
  std::vector<double> sign_;              // per mesh: +1, or -1 when inside out
  std::vector<Hole> holes_;
};

// Per welded vertex: the obstacle mesh it lies inside, kNone for outside and for obstacle
// vertices. Only the vertices with `update[v]` set are evaluated again (all when `update` is
// empty); `inside` keeps its other entries. Parallel over vertices, each into its own slot.
void find_inside_vertices(const SceneTopology& topo, const std::vector<Role>& role,
                          const ObstacleWinding& winding, const std::vector<std::uint8_t>& update,
                          int threads, std::vector<std::uint32_t>& inside);

// As find_inside_vertices for every vertex, with one winding-number evaluation per connected part
// instead of one per vertex (DESIGN §4, *Inside by winding number*). `crossings` are all crossings
// at the current positions. Two movable vertices joined by an edge that crosses no obstacle face
// and passes no nearer to an obstacle's hole than kHoleReach times its radius are inside the same
// obstacles: closing each hole by a fan inside its ball makes the obstacle a closed surface,
// whose winding number is an integer that changes only where a segment crosses it, and the fans
// add less than 0.07 per turn of the hole's outline at that distance. Each part takes the answer
// of its lowest vertex whose winding numbers are all within 1/4 of an integer; vertices near a
// hole, at a seam (on the surface), and parts with no such vertex are evaluated one by one. With
// more than kMaxHoles holes, all are.
inline constexpr double kHoleReach = 2.0;
inline constexpr std::size_t kMaxHoles = 256;
void find_inside_by_parts(const SceneTopology& topo, const std::vector<Role>& role,
                          const ObstacleWinding& winding, const CrossingSet& crossings,
                          int threads, std::vector<std::uint32_t>& inside);

// Per mesh, how many of its welded vertices `inside` marks (0 for obstacles).
std::vector<std::size_t> inside_per_mesh(const SceneTopology& topo,
                                         const std::vector<std::uint32_t>& inside);

}  // namespace untangle
