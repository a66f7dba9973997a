// Our own OBJ reader, which keeps the file's vertex order and counts.
// assimp splits OBJ vertices per face corner; this reader does not, and names each line in its
// errors.
#pragma once

#include <string>

#include "untangle/mesh.h"

namespace untangle {

// Reads the `v` and `f` lines of an OBJ file as one mesh (all objects and groups together,
// named after the first `o` or `g`). Polygons are fanned. Throws Error(kUnreadableInput).
Mesh read_obj(const std::string& path, Role role);

}  // namespace untangle
