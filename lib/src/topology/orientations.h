// How the faces of each component of a topology are oriented: consistently, and outward or not.
#pragma once

#include <cstdint>
#include <vector>

#include "topology/scene_topology.h"

namespace untangle {

// Per component: +1 if closed, consistently oriented and enclosing positive volume; -1 if closed
// and consistently oriented inward; 0 otherwise.
std::vector<int> closed_orientations(const SceneTopology& topology);

// Per triangle: +1 or -1 so that the triangles of each component, each turned by its sign, agree
// on their orientation across every edge they share (the lowest triangle of a component keeps its
// own); 0 for every triangle of a component that is not orientable or has an edge of 3+ faces.
// A garment whose file flips its faces at a turned-down collar is still oriented this way.
std::vector<std::int8_t> face_orientations(const SceneTopology& topology);

}  // namespace untangle
