// Which vertices a repair would call illegal, for pictures: the illegal regions of the movable
// meshes and the movable vertices inside an obstacle (render --inside).
#pragma once

#include <cstdint>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

// Per mesh, per input vertex: 1 where the vertex lies in an illegal region of a movable component
// (analyse_regions: what lies inside an obstacle, or the smaller side by area; both sides' when
// two movable components cross) or inside an obstacle by winding number; 0 elsewhere and on
// obstacles. Computed on the canonical scene (canonical_order.h), as the repair's first step is:
// the same in any order of vertices, faces and meshes.
std::vector<std::vector<std::uint8_t>> illegal_vertices(const std::vector<Mesh>& meshes,
                                                        bool outside_closed_obstacles, int threads);

}  // namespace untangle
