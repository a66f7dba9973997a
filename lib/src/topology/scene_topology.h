// Welded, globally indexed topology of a set of meshes: the input of detection and contours.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

inline constexpr std::uint32_t kNone = 0xffffffffu;

// All meshes of a run in one index space. Vertices at the same position inside one mesh are
// welded (never across meshes); global welded vertex ids are contiguous per mesh, in mesh order.
// Triangles whose welded corners repeat are dropped (counted in `degenerate`). Edges are the
// sorted distinct welded vertex pairs of the kept triangles; `tri_edges[t][k]` joins corners k and
// k+1. Everything is ordered by index only, so the structure is deterministic.
struct SceneTopology {
  // welded vertices
  std::vector<Vec3> points;
  std::vector<std::uint32_t> vertex_mesh;
  std::vector<std::uint32_t> mesh_vertex_begin;  // per mesh, + one past the end
  std::vector<std::vector<std::uint32_t>> welded;  // per mesh: input vertex -> global welded id
  std::vector<std::uint32_t> representative;        // welded id -> smallest input vertex index

  // kept triangles
  std::vector<std::array<std::uint32_t, 3>> tris;  // global welded ids
  std::vector<std::uint32_t> tri_mesh;
  std::vector<std::uint32_t> tri_source;  // index into Mesh::triangles
  std::vector<std::array<std::uint32_t, 3>> tri_edges;
  std::vector<std::uint32_t> mesh_tri_begin;  // per mesh, + one past the end
  std::vector<std::size_t> degenerate;        // per mesh: dropped triangles

  // edges (v0 < v1), sorted; incident kept triangles in CSR form, ascending
  std::vector<std::array<std::uint32_t, 2>> edges;
  std::vector<std::uint32_t> edge_face_begin;  // size edges+1
  std::vector<std::uint32_t> edge_faces;

  // edge-connected components (a two-piece garment in one file is two components): global ids,
  // numbered in order of their lowest vertex; an isolated vertex is a component of its own
  std::vector<std::uint32_t> vertex_component;
  std::vector<std::uint32_t> component_mesh;
  std::uint32_t tri_component(std::uint32_t t) const { return vertex_component[tris[t][0]]; }

  // vertex -> incident edges, CSR, ascending; vertex_neighbors[i] is the other end of
  // vertex_edges[i] (floods read it in sequence instead of looking the edge up)
  std::vector<std::uint32_t> vertex_edge_begin;  // size points+1
  std::vector<std::uint32_t> vertex_edges;
  std::vector<std::uint32_t> vertex_neighbors;

  std::size_t edge_face_count(std::uint32_t e) const {
    return edge_face_begin[e + 1] - edge_face_begin[e];
  }
  bool is_boundary(std::uint32_t e) const { return edge_face_count(e) == 1; }
  std::uint32_t edge_mesh(std::uint32_t e) const { return vertex_mesh[edges[e][0]]; }
  // Edge id of the welded vertex pair, or kNone.
  std::uint32_t find_edge(std::uint32_t a, std::uint32_t b) const;
  // The triangles with a corner among `vertices` (welded ids), ascending, each once.
  std::vector<std::uint32_t> triangles_at(const std::vector<std::uint32_t>& vertices) const;
};

SceneTopology build_topology(const std::vector<Mesh>& meshes);

// Refreshes the welded positions from the meshes' positions (same connectivity).
void update_points(const std::vector<Mesh>& meshes, SceneTopology& topology);

}  // namespace untangle
