// Topological description of one mesh: what `untangle info` prints.
#pragma once

#include <cstddef>

#include "untangle/mesh.h"

namespace untangle {

struct MeshInfo {
  std::size_t vertices = 0;            // as in the file
  std::size_t faces = 0;               // as in the file (polygons)
  std::size_t triangles = 0;           // after triangulating polygons
  std::size_t welded_vertices = 0;     // distinct positions used by triangles
  std::size_t components = 0;          // edge-connected components of the welded mesh
  std::size_t boundary_loops = 0;      // closed chains of boundary edges
  std::size_t boundary_edges = 0;      // edges with one incident triangle
  std::size_t non_manifold_edges = 0;  // edges with three or more incident triangles
  std::size_t degenerate_triangles = 0;  // triangles with two welded corners equal (dropped)
  std::size_t zero_area_triangles = 0;   // exactly collinear corners (kept: handled symbolically)
  bool closed = false;                 // no boundary edge and no non-manifold edge
  double area = 0.0;
  double mean_edge_length = 0.0;
};

MeshInfo describe_mesh(const Mesh& mesh);

}  // namespace untangle
