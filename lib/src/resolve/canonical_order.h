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
// renumbering of every mesh: vertices sorted by their distance from the mean of the mesh's
// vertices, then (in a scene) from the mean of the scene's, then by position (x, y, z: only a
// mesh symmetric in the scene too gets this far), exact duplicates (which weld into one vertex
// and move together) by input index; each triangle rotated to start at its smallest canonical
// corner (orientation kept) and triangles sorted by corners. The same geometry in any vertex or
// face order then gives the same positions, bit for bit (tests/test_determinism.cpp). The means
// are summed exactly, so the distances keep their bits when the scene is scaled by a power of two
// or turned half round an axis (two coordinates negated): the order, and with it the repair, is
// unit- and rotation-free there (tests/test_unit_free.cpp). A general rotation rounds every
// coordinate; distances equal to the last bits may then swap.
// Detection (`check`, fix's verdict) runs on it too: its symbolic perturbation orders points by
// their ids, so degenerate configurations (shared positions, coplanar faces) would otherwise be
// resolved one way in `check` and another in `fix` (tests/test_check_fix_agree.cpp).
CanonicalMesh canonical(const Mesh& input);
// The same, equal distances from the mesh's mean told apart by the distance from `scene_mean`.
CanonicalMesh canonical(const Mesh& input, const Vec3* scene_mean);

// A scene with every mesh renumbered (canonical) and the meshes in canonical order.
//
// Ids across meshes follow the meshes' order, and so do the symbolic perturbation (ties decided
// by vertex id) and the order in which the repair accumulates moves: the meshes listed in another
// order would give other crossings in degenerate configurations and other positions. The order is
// therefore taken from the meshes themselves, by what the repair never changes, so that the
// written meshes, checked again, take the same order as the input:
//   1. role (movable meshes first, then obstacles),
//   2. vertex count, then triangle count,
//   3. the valences of the vertices (distinct neighbours through triangle edges), compared as
//      counts of vertices per valence, then the number of pinned vertices: free of the unit, the
//      rotation and the numbering,
//   4. the listing order, for meshes alike in all of these (a mesh and a copy of it, a layer
//      generated from a garment): positions are not compared, as the repair changes them and the
//      written copies would then be ordered otherwise than the input (a ball and its exact copy,
//      repaired, were checked under another perturbation than the one the repair used).
// `pins` (per input mesh, per input vertex; may be empty or shorter) counts in step 3.
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
