// The shape change of each movable mesh after a repair: edge lengths, flipped faces, displacement.
#pragma once

#include <vector>

#include "resolve/scene_measures.h"
#include "topology/scene_topology.h"
#include "untangle/fix.h"

namespace untangle {

// Per mesh, `topo`'s current positions against `input` (per welded vertex); the mean edge
// lengths are the measures' (of the input). Obstacles get zeros.
std::vector<QualityStats> quality_stats(const SceneTopology& topo, const std::vector<Vec3>& input,
                                        const SceneMeasures& measures);

}  // namespace untangle
