// The functions of the public Mesh type (untangle/mesh.h), in the base layer under every stage.
#include "untangle/mesh.h"

namespace untangle {

const char* to_string(Role role) { return role == Role::kMovable ? "movable" : "obstacle"; }

std::string mesh_label(const Mesh& mesh, bool with_name) {
  if (!with_name || mesh.name.empty()) return mesh.path;
  return mesh.path + ":" + mesh.name;
}

}  // namespace untangle
