// The detection that runs after every step of the simulation, kept from step to step: the scene's
// topology, the obstacles' hierarchy and winding numbers built once, the cloth's hierarchies
// refitted, and only triangles with a moved corner tested again. A step that ends with no crossing
// and no cloth vertex inside an obstacle costs this detection only; the full repair runs only
// when it finds something.
#pragma once

#include <memory>
#include <vector>

#include "detect/detect_crossings.h"
#include "resolve/inside_vertices.h"
#include "topology/scene_topology.h"
#include "untangle/mesh.h"

namespace untangle {

class StepDetector {
 public:
  StepDetector(const std::vector<Mesh>& meshes, int threads);
  // Detects on the meshes' current positions (the same meshes, same topology, as built). When
  // `obstacles_moved`, the obstacles' hierarchy and winding numbers are built again first.
  void detect(const std::vector<Mesh>& meshes, bool obstacles_moved);
  std::size_t crossings() const { return set_.items.size(); }
  std::size_t inside_vertices() const;

 private:
  void build_obstacles();

  SceneTopology topo_;
  std::vector<Role> role_;
  DetectSettings settings_;
  std::unique_ptr<TriangleBvh> obstacle_bvh_;
  std::unique_ptr<ObstacleWinding> winding_;
  std::unique_ptr<SceneHierarchy> hierarchy_;
  CrossingSet set_;
  std::vector<std::uint32_t> inside_;
  std::vector<std::uint8_t> changed_;
};

}  // namespace untangle
