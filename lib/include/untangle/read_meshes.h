// Reading meshes from files (every format assimp knows; OBJ and plain OFF by our own readers).
#pragma once

#include <string>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

// Reads every triangle mesh in the file at `path`, applies node transforms (world space) and
// returns them in file order with the given role. Polygons are triangulated as fans.
// Throws Error(kUnreadableInput) with a one-line message naming the file when the file is missing,
// not a regular file, empty, of an unknown format, corrupt, holds no triangles (point clouds,
// lines), has face indices out of range, or NaN or infinite coordinates. Element counts in PLY,
// OFF and GLB headers and glTF accessors are checked against the file's size before anything is
// allocated. assimp runs on a helper thread with a large stack (deeply nested files), and the
// standard streams are silenced while it reads (some of its parsers print): do not call this
// concurrently with code that writes to std::cout or std::cerr. Never prints. A format other than
// OBJ and plain OFF loads the assimp module (libuntangle_assimp.so) on first need; when it cannot
// be loaded, Error(kUnreadableInput) names `path` and says why.
std::vector<Mesh> read_meshes(const std::string& path, Role role);

}  // namespace untangle
