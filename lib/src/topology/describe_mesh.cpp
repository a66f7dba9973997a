// describe_mesh: the topological facts `untangle info` prints.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <numeric>

#include "geometry/vec3.h"
#include "topology/scene_topology.h"
#include "untangle/mesh_info.h"

namespace untangle {
namespace {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void join(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace

MeshInfo describe_mesh(const Mesh& mesh) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  MeshInfo info;
  info.vertices = mesh.positions.size();
  info.faces = mesh.source_faces;
  info.triangles = mesh.triangles.size();
  const SceneTopology topo = build_topology({mesh});
  info.welded_vertices = topo.points.size();
  info.degenerate_triangles = topo.degenerate[0];

  UnionFind components(topo.points.size());
  std::vector<std::uint8_t> used(topo.points.size(), 0);
  double edge_sum = 0.0;
  for (const auto& tri : topo.tris) {
    for (std::uint32_t v : tri) used[v] = 1;
    components.join(tri[0], tri[1]);
    components.join(tri[1], tri[2]);
    const Vec3 &a = topo.points[tri[0]], &b = topo.points[tri[1]], &c = topo.points[tri[2]];
    if (CGAL::collinear(K::Point_3(a[0], a[1], a[2]), K::Point_3(b[0], b[1], b[2]),
                        K::Point_3(c[0], c[1], c[2]))) {
      ++info.zero_area_triangles;
    }
    info.area += triangle_area(a, b, c);
  }
  for (std::uint32_t v = 0; v < topo.points.size(); ++v)
    if (used[v] && components.find(v) == v) ++info.components;

  UnionFind loops(topo.points.size());
  std::vector<std::uint8_t> on_boundary(topo.points.size(), 0);
  for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
    const auto& edge = topo.edges[e];
    const Vec3 &a = topo.points[edge[0]], &b = topo.points[edge[1]];
    edge_sum += norm(sub(a, b));
    const std::size_t faces = topo.edge_face_count(e);
    if (faces >= 3) ++info.non_manifold_edges;
    if (faces == 1) {
      ++info.boundary_edges;
      loops.join(edge[0], edge[1]);
      on_boundary[edge[0]] = on_boundary[edge[1]] = 1;
    }
  }
  for (std::uint32_t v = 0; v < topo.points.size(); ++v)
    if (on_boundary[v] && loops.find(v) == v) ++info.boundary_loops;
  info.closed = info.boundary_edges == 0 && info.non_manifold_edges == 0 && !topo.tris.empty();
  if (!topo.edges.empty()) info.mean_edge_length = edge_sum / static_cast<double>(topo.edges.size());
  return info;
}

}  // namespace untangle
