// Reading meshes from files (every format assimp knows; OBJ by our own reader).
#pragma once

#include <string>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

// Reads every triangle mesh in the file at `path`, applies node transforms (world space) and
// returns them in file order with the given role. Polygons are triangulated as fans.
// Throws Error(kUnreadableInput) with a one-line message naming the file when the file is missing,
// empty, of an unknown format, corrupt, holds no triangles (point clouds, lines), has face indices
// out of range, or NaN or infinite coordinates. Never prints.
std::vector<Mesh> read_meshes(const std::string& path, Role role);

}  // namespace untangle
