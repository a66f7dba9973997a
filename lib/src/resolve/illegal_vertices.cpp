// illegal_vertices: detection, contours and region analysis as one repair step runs them, and the
// winding-number inside test, on the canonical scene a repair starts from.
#include "resolve/illegal_vertices.h"

#include "contour/build_contours.h"
#include "resolve/canonical_order.h"
#include "detect/detect_crossings.h"
#include "resolve/inside_vertices.h"
#include "resolve/region_analysis.h"
#include "topology/orientations.h"
#include "topology/scene_topology.h"

namespace untangle {

std::vector<std::vector<std::uint8_t>> illegal_vertices(const std::vector<Mesh>& input,
                                                        bool outside_closed_obstacles, int threads) {
  const CanonicalScene scene = canonical_scene(input);
  const std::vector<Mesh>& meshes = scene.meshes;
  const SceneTopology topo = build_topology(meshes);
  std::vector<Role> role;
  DetectSettings detect;
  detect.threads = threads;
  RegionSettings settings;
  settings.outside_closed_obstacles = outside_closed_obstacles;
  for (const Mesh& m : meshes) {
    role.push_back(m.role);
    detect.skip_among.push_back(m.role == Role::kObstacle);
    settings.obstacle.push_back(m.role == Role::kObstacle);
  }
  const ObstacleWinding winding(topo, role, threads);
  settings.orientation = closed_orientations(topo);
  settings.winding = &winding;
  const CrossingSet set = detect_crossings(topo, detect);
  const std::vector<TracedContour> traced = build_contours(topo, set);
  const RegionAnalysis analysis = analyse_regions(topo, set, traced, settings);

  std::vector<std::uint8_t> illegal(topo.points.size(), 0);  // per welded vertex
  for (const IllegalSet& s : analysis.illegal)
    if (role[topo.component_mesh[s.component]] == Role::kMovable)
      for (std::uint32_t v : s.vertices) illegal[v] = 1;
  std::vector<std::uint32_t> inside(topo.points.size(), kNone);
  find_inside_by_parts(topo, role, winding, set, threads, inside);
  for (std::uint32_t v = 0; v < topo.points.size(); ++v)
    if (inside[v] != kNone) illegal[v] = 1;

  std::vector<std::vector<std::uint8_t>> out(meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    out[m].assign(meshes[m].positions.size(), 0);
    for (std::size_t i = 0; i < meshes[m].positions.size() && i < topo.welded[m].size(); ++i)
      out[m][i] = illegal[topo.welded[m][i]];
  }
  return vertices_in_input_order(scene, out);
}

}  // namespace untangle
