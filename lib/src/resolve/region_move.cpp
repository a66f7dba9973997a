// Region moves: every vertex of an illegal region moves across the other surface, each connected
// part by the candidate that strains its edges least.
#include <algorithm>
#include <cmath>

#include "resolve/move_kinds.h"

namespace untangle {
namespace {

// How much a candidate move of `part` strains the mesh: relative length change of every edge
// touching the part, plus a heavy penalty for each triangle it collapses.
double strain(const SceneTopology& topo, const std::vector<std::uint32_t>& part,
              const std::vector<std::uint8_t>& member, std::uint32_t base,
              const std::vector<Vec3>& delta) {
  auto moved = [&](std::uint32_t v) {
    if (!member[v - base]) return topo.points[v];
    const auto it = std::lower_bound(part.begin(), part.end(), v);
    if (it == part.end() || *it != v) return topo.points[v];  // another part: unchanged here
    return add(topo.points[v], delta[static_cast<std::size_t>(it - part.begin())]);
  };
  double score = 0.0;
  for (std::uint32_t v : part) {
    for (std::uint32_t k = topo.vertex_edge_begin[v]; k < topo.vertex_edge_begin[v + 1]; ++k) {
      const std::uint32_t e = topo.vertex_edges[k];
      const auto& ed = topo.edges[e];
      const double before = norm(sub(topo.points[ed[0]], topo.points[ed[1]]));
      const double after = norm(sub(moved(ed[0]), moved(ed[1])));
      if (before > 0.0) score += std::abs(after - before) / before;
      for (std::uint32_t i = topo.edge_face_begin[e]; i < topo.edge_face_begin[e + 1]; ++i) {
        const auto& tri = topo.tris[topo.edge_faces[i]];
        const double a0 = norm(cross(sub(topo.points[tri[1]], topo.points[tri[0]]),
                                     sub(topo.points[tri[2]], topo.points[tri[0]])));
        const Vec3 q0 = moved(tri[0]);
        const double a1 = norm(cross(sub(moved(tri[1]), q0), sub(moved(tri[2]), q0)));
        if (a1 < 0.05 * a0) score += 5.0;
      }
    }
  }
  return score;
}

}  // namespace

// The candidates, and why each exists:
//  - to the closest point of the partner, plus the clearance (a thin layer stays thin);
//  - mirrored through that closest point (a part sticking far through folds back, keeping its
//    shape instead of collapsing onto the surface);
//  - along the part's own normal to where that ray leaves the partner, either way (a sheet cut
//    through the middle of a closed body bulges over it instead of being squeezed sideways);
//  - stages 2-3: reflected across the plane of the closest face (beyond the partner's edge the
//    part turns round the edge instead of onto it).
std::vector<PartMoves> part_moves(const RepairContext& ctx, Scratch& scratch, std::uint32_t mesh,
                                  int orientation, const std::vector<std::uint32_t>& vertices,
                                  const MeshTree& tree) {
  const SceneTopology& topo = ctx.topo;
  std::vector<PartMoves> out;
  if (tree.empty()) return out;
  const double clearance = ctx.options.clearance * ctx.measures.mean_edge[mesh];
  std::vector<std::uint8_t>& member = scratch.member;
  for (std::uint32_t v : vertices) member[v] = 1;

  // Vertex normals (area weighted) at the set and its neighbours, from the triangles it touches
  // in ascending order.
  const std::vector<std::uint32_t> touching = topo.triangles_at(vertices);
  std::vector<Vec3>& normal = scratch.normal;
  for (std::uint32_t t : touching) {
    const auto& tri = topo.tris[t];
    const Vec3 n = cross(sub(topo.points[tri[1]], topo.points[tri[0]]),
                         sub(topo.points[tri[2]], topo.points[tri[0]]));
    for (std::uint32_t v : tri) normal[v] = add(normal[v], n);
  }
  std::vector<std::uint8_t>& seen = scratch.seen;

  // Connected parts of the set.
  for (std::uint32_t seed : vertices) {
    if (seen[seed]) continue;
    std::vector<std::uint32_t> part{seed};
    seen[seed] = 1;
    for (std::size_t i = 0; i < part.size(); ++i) {
      const std::uint32_t v = part[i];
      for (std::uint32_t k = topo.vertex_edge_begin[v]; k < topo.vertex_edge_begin[v + 1]; ++k) {
        const std::uint32_t w = topo.vertex_neighbors[k];
        if (member[w] && !seen[w]) {
          seen[w] = 1;
          part.push_back(w);
        }
      }
    }
    std::sort(part.begin(), part.end());

    const std::size_t n = part.size();
    std::vector<Vec3> closest(n), mirror(n), ray_up(n), ray_down(n), across(n);
    bool up_ok = true, down_ok = true, across_differs = false;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& p = topo.points[part[i]];
      const Closest hit = closest_on(tree, p);
      const Vec3& c = hit.point;
      const std::uint32_t face = hit.face;
      const Vec3 to = sub(c, p);
      Vec3 dir = unit(to);
      if (norm(to) == 0.0) dir = scale(face_normal(topo, face), orientation >= 0 ? 1.0 : -1.0);
      closest[i] = add(to, scale(dir, clearance));
      const Vec3 nv = unit(normal[part[i]]);
      // A part mirrored through a flat partner may land in the plane of its own mesh (a flat
      // strip folded onto itself): the clearance along its own normal keeps the fold open.
      mirror[i] = add(add(scale(to, 2.0), scale(dir, clearance)), scale(nv, clearance));
      if (ctx.pieces()) {
        // The same as mirrored where the closest point lies inside the face.
        const Vec3 nf = face_normal(topo, face);
        const Vec3 to_plane = scale(nf, dot(nf, sub(topo.points[topo.tris[face][0]], p)));
        Vec3 side = unit(to_plane);
        if (norm(to_plane) == 0.0) side = dir;
        across[i] = add(add(scale(to_plane, 2.0), scale(side, clearance)), scale(nv, clearance));
        across_differs = across_differs || across[i] != mirror[i];
      }
      for (int sign : {1, -1}) {
        bool& ok = sign > 0 ? up_ok : down_ok;
        if (!ok) continue;
        const Vec3 d = scale(nv, sign);
        if (norm(d) == 0.0) {
          ok = false;
          continue;
        }
        Vec3 x;
        if (!first_ray_hit(tree, p, d, x)) {
          ok = false;
          continue;
        }
        (sign > 0 ? ray_up : ray_down)[i] = add(sub(x, p), scale(d, clearance));
      }
    }
    PartMoves p;
    p.options.push_back(std::move(closest));
    p.options.push_back(std::move(mirror));
    if (up_ok) p.options.push_back(std::move(ray_up));
    if (down_ok) p.options.push_back(std::move(ray_down));
    if (across_differs) p.options.push_back(std::move(across));
    for (const std::vector<Vec3>& option : p.options)
      p.strain.push_back(strain(topo, part, member, 0, option));
    p.part = std::move(part);
    out.push_back(std::move(p));
  }
  for (std::uint32_t v : vertices) member[v] = seen[v] = 0;
  for (std::uint32_t t : touching)
    for (std::uint32_t v : topo.tris[t]) normal[v] = Vec3{0, 0, 0};
  return out;
}

void move_regions(const RepairContext& ctx, Scratch& scratch, std::uint32_t mesh, int orientation,
                  const std::vector<std::uint32_t>& vertices, const MeshTree& tree, Moves& moves) {
  for (const PartMoves& p : part_moves(ctx, scratch, mesh, orientation, vertices, tree))
    moves.add_region(p.part, p.options[p.least_strain()]);
}

}  // namespace untangle
