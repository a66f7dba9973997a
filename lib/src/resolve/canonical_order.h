// Canonical renumbering of a mesh (canonical) and canonical order of a scene's meshes
// (canonical_scene): the repair and detection run on them.
#pragma once

#include <cstdint>
#include <vector>

#include "untangle/intersections.h"
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

// A scene with every mesh renumbered (canonical) and the meshes in canonical order.
//
// Ids across meshes follow the meshes' order, and so do the symbolic perturbation (ties decided
// by vertex id) and the order in which the repair accumulates moves: the meshes listed in another
// order would give other crossings in degenerate configurations and other positions. The order is
// therefore taken from the meshes themselves, by
//   1. role (movable meshes first, then obstacles),
//   2. vertex count, then triangle count,
//   3. the valences of the vertices (distinct neighbours through triangle edges), compared as
//      counts of vertices per valence: free of the unit, the rotation and the numbering,
//   4. the total area, summed over the triangles' areas in increasing order and rounded to float:
//      equal areas computed with different rounding (a mesh and a rotated copy of it) round to the
//      same float unless they straddle a rounding boundary (a chance of about 1e-16 / 6e-8 per
//      pair), so such meshes tie here instead of being ordered by noise; scaling by a power of two
//      keeps the order exactly,
//   5. the canonical meshes' positions bit for bit, then their triangles: this orders congruent
//      meshes at different places by their coordinates, so a rotation of the scene can swap two
//      such meshes (rotation independence is not claimed for this step),
//   6. the pins (fix_meshes): which canonical vertices are pinned,
//   7. the listing order, only for meshes that are copies to the last bit with the same pins:
//      they get the same canonical slots in any listing order, so the positions computed for the
//      slots are the same and the copy listed first gets the first slot's.
// `pins` (per input mesh, per input vertex; may be empty or shorter) is step 6.
struct CanonicalScene {
  std::vector<std::uint32_t> mesh_order;  // canonical mesh -> input mesh
  std::vector<std::uint32_t> mesh_rank;   // input mesh -> canonical mesh
  // Per canonical mesh, its renumbering (its `mesh` moved into `meshes`, left empty).
  std::vector<CanonicalMesh> renumbering;
  std::vector<Mesh> meshes;  // the canonical meshes, in canonical order
  // The pins given, per canonical mesh, per canonical vertex (empty for a mesh without pins).
  std::vector<std::vector<std::uint8_t>> pins;
};
CanonicalScene canonical_scene(const std::vector<Mesh>& input,
                               const std::vector<std::vector<std::uint8_t>>& pins = {});

// Per-mesh values of the canonical scene, put back in the input's order of meshes (returned as
// they are unless there is one per mesh: an empty list stays empty).
template <class T>
std::vector<T> in_input_order(const CanonicalScene& scene, const std::vector<T>& per_canonical) {
  if (per_canonical.size() != scene.mesh_rank.size()) return per_canonical;
  std::vector<T> out;
  out.reserve(per_canonical.size());
  for (std::uint32_t c : scene.mesh_rank) out.push_back(per_canonical[c]);
  return out;
}

// Per-vertex values of the canonical scene (per canonical mesh, per canonical vertex), put back in
// the input's order of meshes and vertices.
template <class T>
std::vector<std::vector<T>> vertices_in_input_order(const CanonicalScene& scene,
                                                    const std::vector<std::vector<T>>& per_canonical) {
  std::vector<std::vector<T>> out(scene.mesh_order.size());
  for (std::size_t c = 0; c < scene.mesh_order.size() && c < per_canonical.size(); ++c) {
    const auto& order = scene.renumbering[c].vertex_order;
    std::vector<T>& to = out[scene.mesh_order[c]];
    to.resize(order.size());
    for (std::size_t k = 0; k < order.size() && k < per_canonical[c].size(); ++k)
      to[order[k]] = per_canonical[c][k];
  }
  return out;
}

// Counts of a detection on the canonical scene, in the input's order of meshes: inside_by_mesh
// reordered, contacts named by input meshes and sorted again.
void counts_in_input_order(const CanonicalScene& scene, IntersectionCounts& counts);

}  // namespace untangle
