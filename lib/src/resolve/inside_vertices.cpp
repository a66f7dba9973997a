// Inside vertices: one winding-number hierarchy per obstacle mesh, queried per movable vertex.
#include "resolve/inside_vertices.h"

#include "detect/run_parallel.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include "geometry/vec3.h"

namespace untangle {
namespace {

double norm2(const Vec3& a) { return dot(a, a); }

// Whether mesh m is nearly closed: the summed norms of its holes' vector areas (each connected
// chain of boundary edges, directed by its face's winding: (1/2) Σ a × b) against its area.
// The holes (centre and radius) are appended to `holes` when it is nearly closed.
bool has_inside(const SceneTopology& topo, std::uint32_t m,
                std::vector<ObstacleWinding::Hole>& holes) {
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
  // Each chain's vector area about its first vertex met, not the origin (far from it the terms
  // are some |p|^2 and cancel to rounding noise; see volume6).
  std::vector<Vec3> hole(n, Vec3{0, 0, 0}), about(n);
  std::vector<std::uint8_t> started(n, 0);
  for (const auto& d : directed) {
    const std::uint32_t r = find(d[0] - base);
    if (!started[r]) about[r] = topo.points[d[0]];
    started[r] = 1;
    const Vec3 a = sub(topo.points[d[0]], about[r]), b = sub(topo.points[d[1]], about[r]);
    hole[r] = add(hole[r], scale(cross(a, b), 0.5));
  }
  double hole_area = 0.0;
  for (const Vec3& h : hole) hole_area += norm(h);
  if (hole_area > ObstacleWinding::kMaxHoleArea * area) return false;
  // Per hole (root of its chain), in the order of the roots: the mean of its vertices, then the
  // farthest of them.
  std::vector<Vec3> sum(n, Vec3{0, 0, 0});
  std::vector<std::uint32_t> count(n, 0), seen(n, 0);
  for (const auto& d : directed) {
    for (std::uint32_t v : d) {
      if (seen[v - base]) continue;
      seen[v - base] = 1;
      const std::uint32_t r = find(v - base);
      sum[r] = add(sum[r], topo.points[v]);
      ++count[r];
    }
  }
  std::vector<std::uint32_t> slot(n, kNone);
  const std::size_t first = holes.size();
  for (std::uint32_t r = 0; r < n; ++r) {
    if (count[r] == 0) continue;
    slot[r] = static_cast<std::uint32_t>(holes.size() - first);
    holes.push_back({scale(sum[r], 1.0 / count[r]), 0.0});
  }
  for (std::uint32_t v = 0; v < n; ++v) {
    if (!seen[v]) continue;
    ObstacleWinding::Hole& h = holes[first + slot[find(v)]];
    h.radius = std::max(h.radius, norm(sub(topo.points[base + v], h.centre)));
  }
  return true;
}

}  // namespace

ObstacleWinding::ObstacleWinding(const SceneTopology& topo, const std::vector<Role>& role,
                                 int threads, const ObstacleWinding* earlier)
    : slot_(role.size(), kNone), sign_(role.size(), 1.0) {
  for (std::uint32_t m = 0; m < role.size(); ++m) {
    if (role[m] != Role::kObstacle) continue;
    std::vector<std::array<std::uint32_t, 3>> tris(topo.tris.begin() + topo.mesh_tri_begin[m],
                                                   topo.tris.begin() + topo.mesh_tri_begin[m + 1]);
    if (tris.empty() || !has_inside(topo, m, holes_)) continue;
    slot_[m] = static_cast<std::uint32_t>(numbers_.size());
    obstacles_.push_back(m);
    std::shared_ptr<const WindingNumber> number;
    if (earlier != nullptr)
      for (const auto& e : earlier->numbers_)
        if (e->built_from(topo.points, tris)) {
          number = e;
          break;
        }
    if (!number) number = std::make_shared<const WindingNumber>(topo.points, tris, threads);
    numbers_.push_back(std::move(number));
    if (numbers_.back()->signed_volume() < 0.0) sign_[m] = -1.0;
  }
}

double ObstacleWinding::winding(std::uint32_t mesh, const Vec3& p) const {
  if (mesh >= slot_.size() || slot_[mesh] == kNone) return 0.0;
  return sign_[mesh] * (*numbers_[slot_[mesh]])(p);
}

std::uint32_t ObstacleWinding::inside(const Vec3& p) const {
  for (std::uint32_t m : obstacles_)
    if (winding(m, p) > 0.5) return m;
  return kNone;
}

bool ObstacleWinding::inside_clearly(const Vec3& p, std::uint32_t& first) const {
  first = kNone;
  bool clear = true;
  for (std::uint32_t m : obstacles_) {
    bool in_plane = false;
    const double w = sign_[m] * numbers_[slot_[m]]->evaluate(p, in_plane);
    if (in_plane || std::abs(w - std::round(w)) > 0.25) clear = false;
    if (first == kNone && w > 0.5) first = m;
  }
  return clear;
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

void find_inside_by_parts(const SceneTopology& topo, const std::vector<Role>& role,
                          const ObstacleWinding& winding, const CrossingSet& crossings,
                          int threads, std::vector<std::uint32_t>& inside) {
  const std::size_t n = topo.points.size();
  inside.assign(n, kNone);
  if (!winding.any()) return;
  if (winding.holes().size() > kMaxHoles) {
    find_inside_vertices(topo, role, winding, {}, threads, inside);
    return;
  }
  auto movable = [&](std::uint32_t v) { return role[topo.vertex_mesh[v]] == Role::kMovable; };
  // Vertices evaluated alone: at a seam, or within reach of a hole.
  std::vector<std::uint8_t> alone(n, 0);
  for (std::uint32_t v = 0; v < n; ++v) {
    if (!movable(v)) continue;
    if (!topo.seam.empty() && topo.seam[v]) alone[v] = 1;
    for (const ObstacleWinding::Hole& h : winding.holes()) {
      const double reach = kHoleReach * h.radius;
      if (norm2(sub(topo.points[v], h.centre)) <= reach * reach) alone[v] = 1;
    }
  }
  std::vector<std::uint8_t> cut(topo.edges.size(), 0);
  for (const RawCrossing& x : crossings.items)
    if (role[topo.tri_mesh[x.face]] == Role::kObstacle) cut[x.edge] = 1;
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::uint32_t e = 0; e < topo.edges.size(); ++e) {
    const std::uint32_t a = topo.edges[e][0], b = topo.edges[e][1];
    if (cut[e] || !movable(a) || alone[a] || alone[b]) continue;
    bool far = true;
    for (const ObstacleWinding::Hole& h : winding.holes()) {
      // The segment's nearest point to the hole's centre.
      const Vec3 ab = sub(topo.points[b], topo.points[a]);
      const double len2 = dot(ab, ab);
      double t = len2 > 0.0 ? dot(sub(h.centre, topo.points[a]), ab) / len2 : 0.0;
      t = std::min(1.0, std::max(0.0, t));
      const Vec3 q = add(topo.points[a], scale(ab, t));
      const double reach = kHoleReach * h.radius;
      if (norm2(sub(q, h.centre)) <= reach * reach) far = false;
    }
    if (!far) continue;
    const std::uint32_t ra = find(a), rb = find(b);
    // The smaller index stays the root, so a part's root is its lowest vertex.
    if (ra < rb) parent[rb] = ra; else if (rb < ra) parent[ra] = rb;
  }
  // The parts' members in ascending order (CSR by root).
  std::vector<std::uint32_t> begin(n + 1, 0), member;
  for (std::uint32_t v = 0; v < n; ++v)
    if (movable(v)) ++begin[find(v) + 1];
  for (std::size_t i = 0; i < n; ++i) begin[i + 1] += begin[i];
  member.resize(begin[n]);
  {
    std::vector<std::uint32_t> next(begin.begin(), begin.end() - 1);
    for (std::uint32_t v = 0; v < n; ++v)
      if (movable(v)) member[next[find(v)]++] = v;
  }
  std::vector<std::uint32_t> roots;
  for (std::uint32_t v = 0; v < n; ++v)
    if (movable(v) && parent[v] == v) roots.push_back(v);
  // A vertex evaluated alone is a part of its own (no edge joins it). In a part of several, each
  // member's own answer is computed until one is clear; then every member takes that one.
  run_parallel(threads, roots.size(), 1, [&](std::size_t lo, std::size_t hi) {
    for (std::size_t i = lo; i < hi; ++i) {
      const std::uint32_t r = roots[i];
      for (std::uint32_t k = begin[r]; k < begin[r + 1]; ++k) {
        const std::uint32_t v = member[k];
        if (!winding.inside_clearly(topo.points[v], inside[v]) || alone[v]) continue;
        for (std::uint32_t j = begin[r]; j < begin[r + 1]; ++j) inside[member[j]] = inside[v];
        break;
      }
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
