// find_intersections (untangle/intersections.h) with the obstacles' winding numbers of an earlier
// run at hand.
#pragma once

#include <vector>

#include "untangle/intersections.h"
#include "untangle/mesh.h"
#include "untangle/mesh_info.h"

namespace untangle {

class ObstacleWinding;

// find_intersections, where every obstacle whose triangles are those of a hierarchy of `earlier`
// (the same coordinates bit for bit, in the same order: WindingNumber::built_from) shares that
// hierarchy instead of building it again. The same result; null builds them all.
Intersections find_intersections_reusing(const std::vector<Mesh>& meshes,
                                         const DetectOptions& options,
                                         const ObstacleWinding* earlier,
                                         DetectTimings* timings = nullptr,
                                         std::vector<MeshInfo>* infos = nullptr);

}  // namespace untangle
