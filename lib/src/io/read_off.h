// Our own OFF reader: assimp reads OFF but splits its vertices; the writer is write_off.h.
#pragma once

#include <string>

#include "untangle/mesh.h"

namespace untangle {

// Reads a plain `OFF` file (vertex and face lists, optional colours, '#' comments) as one mesh in
// file vertex order. Counts in the header are checked against the file's size before anything is
// allocated. Throws Error(kUnreadableInput) naming the line.
Mesh read_off(const std::string& path, Role role);

// Whether the file starts with the plain OFF keyword (not COFF, NOFF, 4OFF, ...).
bool is_plain_off(const std::string& path);

}  // namespace untangle
