// Walks over one mesh's edges near a contour: rings of neighbours, local sheets, the corners of a
// track's crossings and the pieces a track cuts off.
#pragma once

#include <cstdint>
#include <vector>

#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "topology/scene_topology.h"

namespace untangle {

// Whether welded vertex v lies on a boundary edge of its mesh.
bool is_boundary_vertex(const SceneTopology& topo, std::uint32_t v);

// A patch of one mesh near a contour: `seeds` grown by `rings` rings of neighbours, never into the
// vertices flagged in `excluded` (indexed v - the mesh's first vertex); `in_sheet` receives the
// patch's vertices, the result its triangles (all three corners in it), ascending. The cost
// follows the patch, not the mesh.
std::vector<std::uint32_t> local_sheet(const SceneTopology& topo, std::uint32_t mesh,
                                       const std::vector<std::uint32_t>& seeds,
                                       const std::vector<std::uint8_t>& excluded, int rings,
                                       std::vector<std::uint8_t>& in_sheet);

// Rings from `seeds` to every vertex of `mesh` (indexed v - the mesh's first vertex), counted up
// to `limit`; farther vertices get limit + 1.
std::vector<int> ring_distance(const SceneTopology& topo, std::uint32_t mesh,
                               const std::vector<std::uint32_t>& seeds, int limit);

// The corners of the crossings on track k of a contour: endpoints of its crossing edges, corners
// of the faces the other track's edges pass through; loop vertices left out (where the two sides
// meet: a barrier, never part of a flap). Ascending.
std::vector<std::uint32_t> track_corners(const SceneTopology& topo, const CrossingSet& set,
                                         const TracedContour& t, int k);

// The pieces of a self contour's track k: its crossing edges cut the component, and the vertices
// reachable from their endpoints on one side of the other track's faces, without crossing a cut
// edge or passing a loop vertex, form a piece when they never reach the other side's endpoints
// and stay within `limit` vertices. Unlike the labels (which combine every contour of the
// component), a piece follows this track alone: where two self contours cross, the labels split a
// flap into slivers and the piece is still the whole flap. Each ascending.
std::vector<std::vector<std::uint32_t>> track_pieces(const SceneTopology& topo,
                                                     const CrossingSet& set, const TracedContour& t,
                                                     int k, std::size_t limit);

// Vertices of `mesh` (indexed v - the mesh's first vertex) on this side of a self contour for the
// wide patch: this side's corners `own` and every vertex nearer (in rings) to them than to the
// other track's corners `others`, counted up to `rings`.
std::vector<std::uint8_t> own_side_of(const SceneTopology& topo, std::uint32_t mesh,
                                      const std::vector<std::uint32_t>& own,
                                      const std::vector<std::uint32_t>& others, int rings);

}  // namespace untangle
