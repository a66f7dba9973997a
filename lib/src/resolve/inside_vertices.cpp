// Inside vertices: one winding-number hierarchy per obstacle mesh, queried per movable vertex.
#include "resolve/inside_vertices.h"

#include "detect/run_parallel.h"

#include <cmath>
#include <numeric>

#include "geometry/vec3.h"

namespace untangle {
namespace {

// Whether mesh m is nearly closed: the summed norms of its holes' vector areas (each connected
// chain of boundary edges, directed by its face's winding: (1/2) Σ a × b) against its area.
bool has_inside(const SceneTopology& topo, std::uint32_t m) {
  double area = 0.0;
  for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1]; ++t) {
    const auto& f = topo.tris[t];
    area += triangle_area(topo.points[f[0]], topo.points[f[1]], topo.points[f[2]]);
  }
  const std::uint32_t base = topo.mesh_vertex_begin[m];
  const std::uint32_t n = topo.mesh_vertex_begin[m + 1] - base;
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::vector<std::array<std::uint32_t, 2>> directed;
  for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
    if (topo.edge_mesh(e) != m || !topo.is_boundary(e)) continue;
    const auto& f = topo.tris[topo.edge_faces[topo.edge_face_begin[e]]];
    std::uint32_t a = topo.edges[e][0], b = topo.edges[e][1];
    for (int k = 0; k < 3; ++k)
      if (f[k] == b && f[(k + 1) % 3] == a) std::swap(a, b);
    directed.push_back({a, b});
    parent[find(a - base)] = find(b - base);
  }
  std::vector<Vec3> hole(n, Vec3{0, 0, 0});
  for (const auto& d : directed) {
    const std::uint32_t r = find(d[0] - base);
    hole[r] = add(hole[r], scale(cross(topo.points[d[0]], topo.points[d[1]]), 0.5));
  }
  double holes = 0.0;
  for (const Vec3& h : hole) holes += norm(h);
  return holes <= ObstacleWinding::kMaxHoleArea * area;
}

}  // namespace

ObstacleWinding::ObstacleWinding(const SceneTopology& topo, const std::vector<Role>& role,
                                 int threads)
    : slot_(role.size(), kNone), sign_(role.size(), 1.0) {
  for (std::uint32_t m = 0; m < role.size(); ++m) {
    if (role[m] != Role::kObstacle) continue;
    std::vector<std::array<std::uint32_t, 3>> tris(topo.tris.begin() + topo.mesh_tri_begin[m],
                                                   topo.tris.begin() + topo.mesh_tri_begin[m + 1]);
    if (tris.empty() || !has_inside(topo, m)) continue;
    slot_[m] = static_cast<std::uint32_t>(numbers_.size());
    obstacles_.push_back(m);
    numbers_.emplace_back(topo.points, tris, threads);
    if (numbers_.back().signed_volume() < 0.0) sign_[m] = -1.0;
  }
}

double ObstacleWinding::winding(std::uint32_t mesh, const Vec3& p) const {
  if (mesh >= slot_.size() || slot_[mesh] == kNone) return 0.0;
  return sign_[mesh] * numbers_[slot_[mesh]](p);
}

std::uint32_t ObstacleWinding::inside(const Vec3& p) const {
  for (std::uint32_t m : obstacles_)
    if (winding(m, p) > 0.5) return m;
  return kNone;
}

void find_inside_vertices(const SceneTopology& topo, const std::vector<Role>& role,
                          const ObstacleWinding& winding, const std::vector<std::uint8_t>& update,
                          int threads, std::vector<std::uint32_t>& inside) {
  inside.resize(topo.points.size(), kNone);
  if (!winding.any()) return;
  run_parallel(threads, topo.points.size(), 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      if (!update.empty() && !update[v]) continue;
      inside[v] = role[topo.vertex_mesh[v]] == Role::kMovable ? winding.inside(topo.points[v])
                                                               : kNone;
    }
  });
}

std::vector<std::size_t> inside_per_mesh(const SceneTopology& topo,
                                         const std::vector<std::uint32_t>& inside) {
  std::vector<std::size_t> count(topo.mesh_vertex_begin.size() - 1, 0);
  for (std::size_t v = 0; v < inside.size(); ++v)
    if (inside[v] != kNone) ++count[topo.vertex_mesh[v]];
  return count;
}

}  // namespace untangle
