// Writing corrected meshes: only positions change; everything else comes out as it went in.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

// Writes the meshes read from `input` (in read_meshes order, with new positions) to `output`,
// through a temporary file and a rename: never a partial file. OBJ to OBJ rewrites only the `v`
// lines of moved vertices (shortest round-trip decimal) and keeps every other byte; other
// combinations re-import `input` with assimp, replace positions (mapped back through the node
// transforms) and export in the format of `output`'s extension, in the assimp module (loaded on
// first need; OBJ to OBJ and OFF to OFF never load it). Throws Error(kOutputNotWritten), also when
// the module cannot be loaded.
void write_meshes(const std::string& input, const std::string& output,
                  const std::vector<const Mesh*>& meshes);

// What the format of `output` stores for a position: the identity for OBJ written by us, float32
// rounding for formats exported by assimp.
std::function<Vec3(const Vec3&)> output_rounding(const std::string& output);

// The files that writing `input` to `output` creates besides `output`, in its folder: the `.mtl`
// of an OBJ exported by assimp (an OBJ input is rewritten and writes none), the `.bin` buffer of
// a `.gltf`. A file the exporter makes beyond these never replaces an existing file
// (write_meshes throws instead), so that a caller that checked these paths loses nothing.
std::vector<std::string> side_files_of_output(const std::string& input, const std::string& output);

// What writing `input` to `output` would not keep, as "2 animations, 1 skin" ("" when nothing).
// OBJ to OBJ, plain OFF to OFF and glTF to glTF (positions patched into copies of the buffers)
// keep everything. Otherwise the file is re-imported and exported by assimp, which carries
// meshes, materials, texture references, node names and, in glTF, glTF binary, Collada, FBX,
// assbin and X, animations and skins (bones); counted as lost: the animations and skins of the
// file that assimp does not import (glTF 1.0 animations), those of a format that cannot store
// them (PLY, STL, OBJ, OFF, 3DS, X3D), and the textures of PLY and STL outputs.
std::string export_loss(const std::string& input, const std::string& output);

// Whether `output`'s extension names a format untangle can write.
bool can_write(const std::string& output);

}  // namespace untangle
