// Plain-data triangle mesh as read from a file: world-space positions, triangles, role.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace untangle {

using Vec3 = std::array<double, 3>;
using Triangle = std::array<std::uint32_t, 3>;

// A movable mesh may be displaced; an obstacle never moves (infinite mass).
enum class Role { kMovable, kObstacle };

const char* to_string(Role role);

// One mesh of a scene. Positions are in world space (node transforms applied) and indexed as in
// the file (vertex order preserved, nothing welded). Polygons are triangulated as fans; `polygon`
// gives, per triangle, the index of the face it came from in the file's mesh.
struct Mesh {
  std::string path;  // file the mesh came from
  std::string name;  // mesh name inside the file (may be empty)
  // The name of the node that places this mesh (assimp formats; empty for OBJ and plain OFF).
  std::string node_name;
  Role role = Role::kMovable;
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;  // indices into positions
  std::vector<std::uint32_t> polygon;  // per triangle: the source face index
  std::size_t source_faces = 0;        // faces in the file (before triangulation)
  // Named groups (OBJ `g` and `o`, or the mesh name for other formats): per triangle, the index
  // of its group in group_names, or none when group_names is empty.
  std::vector<std::string> group_names;
  std::vector<std::uint32_t> triangle_group;
  // OBJ: per group, the name of the `o` line in effect where it starts (its own for an `o`
  // group, empty before the first `o`); empty for other formats.
  std::vector<std::string> group_objects;
  // What the reader skipped and the CLI says on stderr (the library never prints), one line each
  // without the path: "18 faces with fewer than 3 corners skipped (their lines are kept in the
  // output)".
  std::vector<std::string> warnings;
};

// A label for messages and reports: "path" or "path:name" when the file holds several meshes.
std::string mesh_label(const Mesh& mesh, bool with_name);

}  // namespace untangle
