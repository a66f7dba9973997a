// The shape change of each movable mesh after a repair: edge lengths, flipped faces, displacement.
#pragma once

#include <vector>

#include "topology/scene_topology.h"
#include "untangle/fix.h"

namespace untangle {

// Per mesh, `topo`'s current positions against `input` (per welded vertex), relative to the input's
// mean edge lengths and bounding boxes. Obstacles (by `role`) get zeros.
std::vector<QualityStats> quality_stats(const SceneTopology& topo, const std::vector<Vec3>& input,
                                        const std::vector<Role>& role);

// Whether the mesh's shape is within `bounds`: its stretch and flipped faces (within_bounds is
// this and the move bound).
bool shape_within_bounds(const QualityStats& q, const QualityBounds& bounds);

}  // namespace untangle
