// The shape change of each movable mesh after a repair: edge lengths, flipped faces, displacement.
#pragma once

#include <cstddef>
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

// The faces of the movable meshes of `output` (the meshes of `input`, moved) beyond `bounds`'
// shape: turned over against `input` (QualityStats::flipped_faces), or with an edge stretched or
// shrunk beyond bounds.max_stretch. How much of the garments a result beyond the bounds damaged.
std::size_t faces_beyond_bounds(const std::vector<Mesh>& input, const std::vector<Mesh>& output,
                                const QualityBounds& bounds);

}  // namespace untangle
