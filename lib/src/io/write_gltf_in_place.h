// glTF to glTF by patching positions in a copy of the input's buffers: everything else (other
// attributes, indices, animations, skins, materials, shaders, extensions, glTF 1.0 or 2.0) kept.
#pragma once

#include <string>
#include <vector>

#include "io/assimp_module.h"
#include "untangle/mesh.h"

namespace untangle {

// Writes `input` (.gltf, version 1.0 or 2.0) to `staged` (a .gltf in a temporary folder; its
// buffers beside it) with the positions of `meshes` (world space, one per instance in order),
// mapped back through each instance's transform into the position accessor that holds it, as the
// assimp module computed them (`instances`: the placed meshes as assimp read them, in read_meshes
// order); an unmoved vertex keeps its stored bytes. The JSON changes only in the `min`/`max` of patched
// accessors whose bounds changed, the buffer URIs (buffers_of_output) and the relative URIs of
// images and shaders, rewritten to stay valid from `final_folder`.
// A binary glTF 2 (`input` and `staged` .glb) is written as its own bytes with the positions
// patched in its BIN chunk: the JSON chunk is kept byte for byte unless a patched accessor's
// bounds or a relative URI (images, shaders, external buffers, which are not copied) must change,
// when it is written again compact (and the chunk and file lengths with it); every other chunk
// and byte is kept. Returns false, having written nothing, when the file is not one it can patch
// (positions not float32 VEC3 in external buffers, or for a .glb in its BIN chunk; sparse; a
// mesh whose positions match no accessor; a glTF 1.0 binary); the caller then exports with assimp.
// Throws Error(kOutputNotWritten) when writing fails.
bool write_gltf_in_place(const std::string& input, const std::string& staged,
                         const std::string& final_folder,
                         const std::vector<assimp_module::PlacedMesh>& instances,
                         const std::vector<const Mesh*>& meshes);

// Whether write_gltf_in_place can patch `input`: its primitives' positions are float32 VEC3 in
// external buffers that hold them, or in a .glb's BIN chunk (a mesh matching no accessor is found
// only when writing).
bool can_patch_gltf(const std::string& input);

// The buffer files writing `input` to a .gltf named `output` creates beside it: `<stem>.bin` for
// one external buffer, `<stem>_<k>.bin` for the k-th of several.
std::vector<std::string> buffers_of_output(const std::string& input, const std::string& output);

}  // namespace untangle
