// Canonical renumbering of a mesh (canonical): the repair runs on it.
#pragma once

#include <cstdint>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

struct CanonicalMesh {
  std::vector<std::uint32_t> vertex_order;    // canonical index -> input index
  std::vector<std::uint32_t> triangle_order;  // canonical triangle -> input triangle
  Mesh mesh;
};

// The repair sums moves, averages and breaks ties in index order, so its floating-point result
// depends on the order of vertices and faces in the file. It therefore runs on a canonical
// renumbering of every mesh: vertices sorted by their distance from the mesh's mean position,
// which turns and scales with the scene (equal distances by position; exact duplicates, which weld
// into one vertex and move together, by input index), each triangle rotated to start at its
// smallest canonical corner (orientation kept) and triangles sorted by corners. The same geometry
// in any vertex or face order then gives the same positions, bit for bit
// (tests/test_determinism.cpp), and a turned scene is numbered alike (tests/test_unit_free.cpp).
// Detection (`check`, fix's verdict) runs on it too: its symbolic perturbation orders points by
// their ids, so degenerate configurations (shared positions, coplanar faces) would otherwise be
// resolved one way in `check` and another in `fix` (tests/test_check_fix_agree.cpp).
CanonicalMesh canonical(const Mesh& input);

}  // namespace untangle
