// Canonical renumbering of a mesh (canonical): the repair runs on it.
#pragma once

#include <cstdint>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

struct CanonicalMesh {
  std::vector<std::uint32_t> vertex_order;  // canonical index -> input index
  Mesh mesh;
};

// The repair sums moves, averages and breaks ties in index order, so its floating-point result
// depends on the order of vertices and faces in the file. It therefore runs on a canonical
// renumbering of every mesh: vertices sorted by position (exact duplicates, which weld into one
// vertex and move together, by input index), each triangle rotated to start at its smallest
// canonical corner (orientation kept) and triangles sorted by corners. The same geometry in any
// vertex or face order then gives the same positions, bit for bit (tests/test_determinism.cpp).
CanonicalMesh canonical(const Mesh& input);

}  // namespace untangle
