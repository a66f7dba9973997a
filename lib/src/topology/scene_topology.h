// Welded, globally indexed topology of a set of meshes: the input of detection and contours.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "untangle/intersections.h"
#include "untangle/mesh.h"

namespace untangle {

inline constexpr std::uint32_t kNone = 0xffffffffu;

// All meshes of a run in one index space. Vertices at the same position inside one mesh are
// welded (never across meshes); global welded vertex ids are contiguous per mesh, in mesh order.
// Triangles whose welded corners repeat are dropped (counted in `degenerate`), and so are exact
// repeats of a kept triangle of the same mesh (the same three welded corners, either winding;
// counted in `repeated`; where a repeat ran the other way, the kept one is turned to agree with
// its neighbours). Edges are the
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
  std::vector<std::size_t> repeated;          // per mesh: dropped exact repeats of a kept triangle

  // Exact contact across meshes (DESIGN §2). Welded vertices of different meshes at the position
  // (bit for bit) of an obstacle's vertex are one point for detection: `contact_tris` are `tris` with each such
  // corner replaced by `contact_point` of it, the lowest obstacle vertex at that position. Detection,
  // contours and measured moves read `detect_tris()`, so that triangles meeting at a shared
  // position share a vertex (and two shared corners are a shared edge). `seam` flags the welded
  // vertices at a shared position. All three are empty when no position is shared. Decided on
  // the positions given to build_topology; update_points drops a vertex from its contact once it
  // has moved away (fix never moves one: it pins them).
  std::vector<std::uint32_t> contact_point;
  std::vector<std::array<std::uint32_t, 3>> contact_tris;
  std::vector<std::uint8_t> seam;
  // Seam vertices and repeated faces per pair of meshes (coplanar_pairs 0 here: detection finds
  // those), sorted by (mesh_a, mesh_b), only pairs with any.
  std::vector<MeshContact> contacts;
  const std::vector<std::array<std::uint32_t, 3>>& detect_tris() const {
    return contact_tris.empty() ? tris : contact_tris;
  }
  // The point detection sees at welded vertex v (its contact_point, or v).
  std::uint32_t detect_point(std::uint32_t v) const { return contact_point.empty() ? v : contact_point[v]; }

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
