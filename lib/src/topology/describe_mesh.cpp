// describe_mesh: the topological facts `untangle info` prints.
#include "topology/describe_mesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "geometry/order_free_sum.h"
#include "geometry/vec3.h"
#include "resolve/canonical_order.h"
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

// The area of triangle (a, b, c) from its sides (Kahan's form of Heron's, accurate for needles
// too): the same bits whichever corner the triangle starts at, as edge lengths are.
double area_from_sides(const Vec3& a, const Vec3& b, const Vec3& c) {
  std::array<double, 3> s{norm(sub(b, c)), norm(sub(c, a)), norm(sub(a, b))};
  std::sort(s.begin(), s.end(), [](double x, double y) { return x > y; });
  const double p = (s[0] + (s[1] + s[2])) * (s[2] - (s[0] - s[1])) * (s[2] + (s[0] - s[1])) *
                   (s[0] + (s[1] - s[2]));
  return p > 0.0 ? 0.25 * std::sqrt(p) : 0.0;
}

}  // namespace

// On the canonical numbering detection uses (find_intersections). The sums are order-free
// (OrderFreeSum, areas from sides), so `info` on a mesh alone and `check` on a scene holding it
// give the same figures whatever the order of the file and of the scene's tie-breaks.
MeshInfo describe_mesh(const Mesh& mesh) {
  const Mesh canon = canonical(mesh).mesh;
  return describe_mesh_in(build_topology({canon}), 0, canon);
}

// Mesh m's welded vertices, triangles and edges are contiguous ranges of the scene's (welding is
// per mesh, edges sorted by their lower vertex) in the order a topology of the mesh alone has
// them, so every figure, sums included, comes out as from that topology.
MeshInfo describe_mesh_in(const SceneTopology& topo, std::size_t m, const Mesh& mesh) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  MeshInfo info;
  info.vertices = mesh.positions.size();
  info.faces = mesh.source_faces;
  info.triangles = mesh.triangles.size();
  const std::uint32_t first = topo.mesh_vertex_begin[m], last = topo.mesh_vertex_begin[m + 1];
  info.welded_vertices = last - first;
  info.degenerate_triangles = topo.degenerate[m];

  UnionFind components(last - first);
  std::vector<std::uint8_t> used(last - first, 0);
  OrderFreeSum edge_sum, area;
  for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1]; ++t) {
    const auto& tri = topo.tris[t];
    for (std::uint32_t v : tri) used[v - first] = 1;
    components.join(tri[0] - first, tri[1] - first);
    components.join(tri[1] - first, tri[2] - first);
    const Vec3 &a = topo.points[tri[0]], &b = topo.points[tri[1]], &c = topo.points[tri[2]];
    if (CGAL::collinear(K::Point_3(a[0], a[1], a[2]), K::Point_3(b[0], b[1], b[2]),
                        K::Point_3(c[0], c[1], c[2]))) {
      ++info.zero_area_triangles;
    }
    area.add(area_from_sides(a, b, c));
  }
  for (std::uint32_t v = 0; v < last - first; ++v)
    if (used[v] && components.find(v) == v) ++info.components;

  const auto edge_at = [&](std::uint32_t v) {
    return static_cast<std::uint32_t>(
        std::lower_bound(topo.edges.begin(), topo.edges.end(), std::array<std::uint32_t, 2>{v, 0u}) -
        topo.edges.begin());
  };
  const std::uint32_t edge_first = edge_at(first), edge_last = edge_at(last);
  UnionFind loops(last - first);
  std::vector<std::uint8_t> on_boundary(last - first, 0);
  for (std::uint32_t e = edge_first; e < edge_last; ++e) {
    const std::array<std::uint32_t, 2> edge{topo.edges[e][0] - first, topo.edges[e][1] - first};
    const Vec3 &a = topo.points[topo.edges[e][0]], &b = topo.points[topo.edges[e][1]];
    edge_sum.add(norm(sub(a, b)));
    const std::size_t faces = topo.edge_face_count(e);
    if (faces >= 3) ++info.non_manifold_edges;
    if (faces == 1) {
      ++info.boundary_edges;
      loops.join(edge[0], edge[1]);
      on_boundary[edge[0]] = on_boundary[edge[1]] = 1;
    }
  }
  for (std::uint32_t v = 0; v < last - first; ++v)
    if (on_boundary[v] && loops.find(v) == v) ++info.boundary_loops;
  const bool no_triangles = topo.mesh_tri_begin[m] == topo.mesh_tri_begin[m + 1];
  info.closed = info.boundary_edges == 0 && info.non_manifold_edges == 0 && !no_triangles;
  info.area = area.value();
  if (edge_last > edge_first)
    info.mean_edge_length = edge_sum.value() / static_cast<double>(edge_last - edge_first);
  return info;
}

}  // namespace untangle
