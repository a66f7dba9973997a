// What the repair reads about the scene and never changes during a run: roles, free vertices,
// edge lengths, orientations, component sizes, the buried faces of closed obstacles.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "topology/scene_topology.h"
#include "untangle/fix.h"
#include "untangle/mesh.h"

namespace untangle {

// Measured once, on the input positions: steps stay relative to the asset's own scale, whatever
// the moves do to it later.
struct SceneMeasures {
  std::vector<Role> role;                   // per mesh
  std::vector<std::uint8_t> free;           // per welded vertex: 1 movable and not pinned
  std::vector<double> mean_edge;            // per mesh: mean edge length
  std::vector<double> vertex_edge;          // per welded vertex: mean incident edge length
  std::vector<std::size_t> component_size;  // per component: welded vertices
  std::vector<int> closed;                  // per component: closed_orientations
  std::vector<std::int8_t> orientation;     // per triangle: face_orientations
  std::vector<std::uint8_t> oriented;       // per component: orientable (face_orientations)
  // Per triangle, 1 for a buried face of a closed obstacle component (buried_faces): inside an
  // obstacle, or on a curve where the closed obstacles pass through themselves or each other.
  std::vector<std::uint8_t> buried;
  std::size_t obstacle_crossing_pairs = 0;  // triangle pairs of the closed obstacles that cross

  bool movable_component(const SceneTopology& topo, std::uint32_t c) const {
    return role[topo.component_mesh[c]] == Role::kMovable;
  }
};

// `pins` per mesh, per input vertex (FixResult's PinMask); `threads` for buried_faces.
SceneMeasures measure_scene(const SceneTopology& topo, const std::vector<Mesh>& meshes,
                            const PinMask& pins, int threads);

}  // namespace untangle
