// Global analysis (DESIGN §4): which side of each mesh, cut by all contours it shares with one
// other mesh, is illegal.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "topology/scene_topology.h"

namespace untangle {

enum class RegionRule : std::uint8_t { kInside, kArea };

// The illegal vertices of mesh `mesh` with respect to mesh `partner`.
struct IllegalSet {
  std::uint32_t mesh = 0;
  std::uint32_t partner = 0;
  RegionRule rule = RegionRule::kArea;
  std::vector<std::uint32_t> vertices;  // welded ids, ascending
  double area = 0.0;
  std::size_t regions = 0;
};

// Per (mesh, partner): label of each welded vertex of mesh (index v - mesh_vertex_begin):
// 1 illegal, 0 legal, -1 undecided (its component is not cut, or the cut does not 2-colour).
using VertexLabels = std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::int8_t>>;

struct RegionAnalysis {
  std::vector<IllegalSet> illegal;  // ordered by (mesh, partner)
  VertexLabels labels;
};

struct RegionSettings {
  bool outside_closed_obstacles = true;
  std::vector<bool> obstacle;       // per mesh
  std::vector<int> orientation;     // per mesh: +1 closed and outward, -1 inward, 0 not closed
};

// Analyses every pair of meshes that share contours; a mesh that intersects itself is analysed
// against itself (cut by both tracks of its self contours, always by the area rule).
RegionAnalysis analyse_regions(const SceneTopology& topology, const CrossingSet& crossings,
                               const std::vector<TracedContour>& contours,
                               const RegionSettings& settings);

// +1 if mesh `m` is closed, consistently oriented and encloses positive volume; -1 if closed and
// consistently oriented inward; 0 otherwise.
int closed_orientation(const SceneTopology& topology, std::uint32_t m);

}  // namespace untangle
