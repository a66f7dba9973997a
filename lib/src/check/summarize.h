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

}  // namespace untangle
