// The assimp export formats whose files assimp 5.2 reads back as meshes.
#pragma once

#include <string>

namespace untangle {

// Every output is verified by reading it back, so only these extensions are written through
// assimp. Left out, because assimp writes them but does not read them back as meshes: .stp
// (read as IFC), .3mf (read without meshes), .assxml and .json (no reader), .pbrt (the
// exporter needs a camera). tests/test_format_determinism.cpp writes and reads back each one.
inline bool is_verified_export(const std::string& extension) {
  for (const char* e : {"3ds", "assbin", "dae", "fbx", "glb", "gltf", "obj", "ply", "stl", "x", "x3d"})
    if (extension == e) return true;
  return false;
}

}  // namespace untangle
