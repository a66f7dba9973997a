// describe_mesh on a topology already built (check builds one for the whole scene).
#pragma once

#include <cstddef>

#include "topology/scene_topology.h"
#include "untangle/mesh_info.h"

namespace untangle {

// What describe_mesh(mesh) gives, for mesh m of `topology` (built from a list holding `mesh` at m,
// in the canonical numbering describe_mesh uses).
MeshInfo describe_mesh_in(const SceneTopology& topology, std::size_t m, const Mesh& mesh);

}  // namespace untangle
