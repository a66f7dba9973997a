// From internal detection results to the public Intersections (crossings, contours, counts).
#pragma once

#include <vector>

#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "topology/scene_topology.h"
#include "untangle/intersections.h"

namespace untangle {

Intersections summarize(const SceneTopology& topology, const CrossingSet& crossings,
                        const std::vector<TracedContour>& contours);

// The two halves of summarize: the crossings and intersecting pairs (which need no contours, so
// they can be made while the contours are built), then the contours and their counts. Without
// `separation` (contours built without it) non_separating is not counted.
Intersections summarize_crossings(const SceneTopology& topology, const CrossingSet& crossings);
void add_contours(const std::vector<TracedContour>& contours, Intersections& result,
                  bool separation = true);

// The exact contacts of a scene (DESIGN §2): the topology's seam vertices and repeated faces with
// the coplanar pairs detection met, per pair of meshes, sorted.
std::vector<MeshContact> contacts_of(const SceneTopology& topology, const CrossingSet& crossings);

}  // namespace untangle
