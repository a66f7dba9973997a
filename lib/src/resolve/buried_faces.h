// Buried faces: the faces of the closed obstacles that lie inside an obstacle.
// They occur where obstacles pass through themselves or through each other.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "topology/scene_topology.h"

namespace untangle {

// One closed, consistently oriented surface: the ascending ids of a component's triangles, and
// +1 when its faces point outward, -1 inward (closed_orientations).
struct ClosedSurface {
  std::vector<std::uint32_t> triangles;
  int orientation = 1;
};

// Per surface, per entry of its `triangles`: 1 when the triangle is buried, 0 otherwise. A face is
// buried when its outer side lies inside one of the surfaces (its own or another), or when a
// curve where the surfaces intersect (themselves or each other) runs through it. A closed surface
// that passes through itself (the cow's tail through its rump, a scanned arm through its torso),
// or two closed parts of a body that overlap, have such faces; a garment moved onto one, or along
// a ray to one, is still inside an obstacle, so moves never aim at them. A face that an
// intersection curve crosses is partly buried and counts as buried: the exposed faces around it
// still hold the surface, one face's width from the crease.
//
// Exact where it decides which faces the curves cross: the triangles of the pairs that cross
// under detection's predicates (an edge of one through the other; with one shared corner, the
// opposite edge). One surface without such a pair has no buried face, and the result is all zeros
// at the cost of one descent of a hierarchy over it. The other triangles are judged in regions
// flooded across their edges (the winding number of the outer side changes only across the
// intersection curves), by a majority of up to seven faces of each region; a face is judged a
// thousandth of its shortest edge outside its centroid, by the median of three signed ray counts
// (winding numbers) against all the surfaces: doubles, used only to steer moves. The descent runs
// on `threads` threads (0: all cores); the result does not depend on the count. Prints nothing.
// With `crossing_pairs`, also the number of triangle pairs of the surfaces that cross (themselves
// or each other), each pair once.
std::vector<std::vector<std::uint8_t>> buried_faces(const SceneTopology& topology,
                                                    const std::vector<ClosedSurface>& surfaces,
                                                    int threads,
                                                    std::size_t* crossing_pairs = nullptr);

}  // namespace untangle
