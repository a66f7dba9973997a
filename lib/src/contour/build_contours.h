// Linking crossings into contours and classifying their tracks (DESIGN §3).
#pragma once

#include <cstdint>
#include <vector>

#include "detect/detect_crossings.h"
#include "topology/scene_topology.h"
#include "untangle/intersections.h"

namespace untangle {

// A contour with the bookkeeping later stages need: for each of its crossings (in walk order), the
// track (0 or 1) that holds the crossing's edge; the other track holds its face.
struct TracedContour {
  Contour contour;  // crossings index into CrossingSet::items
  std::vector<std::uint8_t> edge_track;
  std::vector<std::uint32_t> loop_vertex_ids;  // welded ids of its loop vertices
  bool broken = false;  // a link without partner: the 0-or-2 property failed (a bug if ever true)
};

// Builds the contours of a crossing set and classifies both tracks of each: type from the ends on
// each track's mesh boundary, cut edges, and (for CL and BB tracks, when `separation`) separation
// by flood fill; without `separation`, Track::separates and smaller_area keep their defaults.
// Any set whose ids are in range (sorted and unique, as CrossingSet requires) is safe, not only a
// real detection: every crossing lies on exactly one contour, and a contour whose links are
// inconsistent (a missing partner, a link into another contour, a chain that runs into itself)
// is marked broken and lists its crossings in breadth-first order. The tracks are classified in
// parallel on `threads` threads (0: all cores; the same result for every count).
std::vector<TracedContour> build_contours(const SceneTopology& topology,
                                          const CrossingSet& crossings, int threads = 1,
                                          bool separation = true);

// The edges that occur an odd number of times in `crossed` (the edges a set of contours cuts),
// ascending. `crossed` is sorted in place.
std::vector<std::uint32_t> odd_edges(std::vector<std::uint32_t>& crossed);

// Regions of one mesh after cutting `cut_edges` (edges of that mesh): region id per welded vertex
// of the mesh (index v - mesh_vertex_begin[mesh]); vertices reachable without crossing a cut edge
// share a region. Regions are numbered in order of their lowest vertex. Returns the region count.
std::size_t flood_regions(const SceneTopology& topology, std::uint32_t mesh,
                          const std::vector<std::uint8_t>& edge_is_cut,
                          std::vector<std::uint32_t>& region);

}  // namespace untangle
