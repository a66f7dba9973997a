// Global analysis (DESIGN §4): which side of each surface, cut by its contours, is illegal.
// A surface is cut by all contours it shares with one other surface. The unit is the connected
// component (a shirt and trousers stored in one file are two surfaces that can be layered), so
// "self" contours between two components of one mesh are analysed like contours between two
// meshes.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "topology/orientations.h"  // RegionSettings::orientation is closed_orientations' result
#include "topology/scene_topology.h"

namespace untangle {
class ObstacleWinding;
}

namespace untangle {

enum class RegionRule : std::uint8_t { kInside, kArea };

// The illegal vertices of component `component` with respect to component `partner`.
struct IllegalSet {
  std::uint32_t component = 0;
  std::uint32_t partner = 0;
  RegionRule rule = RegionRule::kArea;
  std::vector<std::uint32_t> vertices;  // welded ids, ascending
  double area = 0.0;
  std::size_t regions = 0;
};

// Per (component, partner): label of each welded vertex of the component's mesh (index
// v - mesh_vertex_begin): 1 illegal, 0 legal, -1 undecided (not cut, or the cut does not 2-colour).
using VertexLabels = std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::int8_t>>;

struct RegionAnalysis {
  std::vector<IllegalSet> illegal;  // ordered by (component, partner)
  VertexLabels labels;
};

struct RegionSettings {
  bool outside_closed_obstacles = true;
  std::vector<bool> obstacle;    // per mesh
  std::vector<int> orientation;  // per component: +1 closed and outward, -1 inward, 0 not closed
  // The obstacles' winding numbers: an open obstacle's inside decides too (none: area rule).
  const ObstacleWinding* winding = nullptr;
};

// The component holding track k of a contour.
std::uint32_t track_component(const SceneTopology& topology, const CrossingSet& crossings,
                              const TracedContour& contour, int k);

// Analyses every pair of components that share contours; a component that intersects itself is
// analysed against itself (cut by both tracks, always by the area rule).
RegionAnalysis analyse_regions(const SceneTopology& topology, const CrossingSet& crossings,
                               const std::vector<TracedContour>& contours,
                               const RegionSettings& settings);

}  // namespace untangle
