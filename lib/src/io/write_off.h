// Our own OFF writer: assimp cannot write OFF, so the text of a plain OFF input is edited.
#pragma once

#include <string>

#include "untangle/mesh.h"

namespace untangle {

// The text of `input` (an OFF file) with the coordinates of moved vertices replaced; every other
// character is kept. Throws Error(kOutputNotWritten) if the file no longer matches the mesh.
std::string rewrite_off(const std::string& input, const Mesh& mesh);

}  // namespace untangle
