// Our own OFF reader and writer: assimp reads OFF but cannot write it, and splits its vertices.
#pragma once

#include <string>

#include "untangle/mesh.h"

namespace untangle {

// Reads a plain `OFF` file (vertex and face lists, optional colours, '#' comments) as one mesh in
// file vertex order. Counts in the header are checked against the file's size before anything is
// allocated. Throws Error(kUnreadableInput) naming the line.
Mesh read_off(const std::string& path, Role role);

// The text of `input` (an OFF file) with the coordinates of moved vertices replaced; every other
// character is kept. Throws Error(kOutputNotWritten) if the file no longer matches the mesh.
std::string rewrite_off(const std::string& input, const Mesh& mesh);

// Whether the file starts with the plain OFF keyword (not COFF, NOFF, 4OFF, ...).
bool is_plain_off(const std::string& path);

}  // namespace untangle
