// Culling before the broad phase: the triangles of a mesh that can meet another mesh at all.
#pragma once

#include <cstdint>
#include <vector>

#include "topology/scene_topology.h"

namespace untangle {

// Per mesh, the ascending ids of its triangles whose closed box may overlap the box of a triangle
// of another mesh; meshes not flagged in `cull` keep every triangle. Conservative and exact: a
// triangle is dropped only when its box provably meets no triangle box of another mesh, decided
// by comparisons of the double coordinates and one monotone rounding into a grid of cells over the
// region where the meshes' bounding boxes overlap (two boxes that meet share a cell). Callers cull
// the meshes whose own pairs are not tested (no self-intersections): a linear pass is far cheaper
// than a hierarchy over triangles that lie nowhere near the other meshes. The per-mesh passes run
// on `threads` threads (0: all cores; the same result for every count).
std::vector<std::vector<std::uint32_t>> cull_triangles(const SceneTopology& topology,
                                                       const std::vector<bool>& cull, int threads = 1);

}  // namespace untangle
