// The positions a step's moves lead to (settle_moves): the one place where proposals become
// positions; the loop writes them.
#include <algorithm>
#include <utility>

#include "resolve/move_kinds.h"

namespace untangle {
namespace {

// Two vertices of one mesh must never land on one position: read back, they would weld into one
// and the written surface would pinch or lose an edge (a closest-point or mirrored move can put two
// vertices on one point, most easily on grid-snapped input). A mover that would share its new
// position with another vertex of its mesh stays where it is; repeated until no position is shared
// (positions before the step are all distinct, so this ends).
void hold_back_coincident(const SceneTopology& topo, std::vector<std::uint32_t>& movers,
                          std::vector<Vec3>& next) {
  if (movers.empty()) return;
  for (;;) {
    std::vector<std::uint32_t> mover_of(topo.points.size(), kNone);
    for (std::size_t i = 0; i < movers.size(); ++i)
      mover_of[movers[i]] = static_cast<std::uint32_t>(i);
    // Every vertex of a mesh with a mover, at its position after the step, sorted by position.
    std::vector<std::uint8_t> mesh_moves(topo.mesh_vertex_begin.size() - 1, 0);
    for (std::uint32_t v : movers) mesh_moves[topo.vertex_mesh[v]] = 1;
    std::vector<std::pair<Vec3, std::uint32_t>> at;
    for (std::uint32_t m = 0; m < topo.mesh_vertex_begin.size() - 1; ++m) {
      if (!mesh_moves[m]) continue;
      for (std::uint32_t v = topo.mesh_vertex_begin[m]; v < topo.mesh_vertex_begin[m + 1]; ++v)
        at.push_back({mover_of[v] != kNone ? next[mover_of[v]] : topo.points[v], v});
    }
    std::sort(at.begin(), at.end());
    std::vector<std::uint8_t> stay(movers.size(), 0);
    bool any = false;
    for (std::size_t i = 0; i + 1 < at.size(); ++i) {
      if (at[i].first != at[i + 1].first ||
          topo.vertex_mesh[at[i].second] != topo.vertex_mesh[at[i + 1].second])
        continue;
      for (std::uint32_t v : {at[i].second, at[i + 1].second}) {
        if (mover_of[v] != kNone) {
          stay[mover_of[v]] = 1;
          any = true;
        }
      }
    }
    if (!any) return;
    std::size_t kept = 0;
    for (std::size_t i = 0; i < movers.size(); ++i) {
      if (stay[i]) continue;
      movers[kept] = movers[i];
      next[kept] = next[i];
      ++kept;
    }
    movers.resize(kept);
    next.resize(kept);
  }
}

}  // namespace

// A region moves whole, as far as it must; DRN steps are capped (drn_step). Triangles that would
// flip (or turn by more than ~85 degrees) halve their corners' moves; every round first finds all
// such triangles, then halves each corner once, so the result does not depend on the order of
// triangles. Triangles touched by a region move are left alone: a region's move was chosen whole
// (by least strain) and may fold it over on purpose.
SettledMoves settle_moves(const RepairContext& ctx, const Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  const std::size_t nv = topo.points.size();
  std::vector<Vec3> delta(nv, Vec3{0, 0, 0});
  std::vector<std::uint8_t> active(nv, 0);
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (!ctx.measures.free[v]) continue;
    Vec3 d{0, 0, 0};
    if (moves.has_region[v])
      d = moves.region[v];
    else if (moves.drn_count[v] > 0)
      d = drn_step(ctx, moves, v);
    if (norm(d) == 0.0) continue;
    delta[v] = d;
    active[v] = 1;
  }
  std::vector<std::uint8_t> halve(nv, 0);
  for (int round = 0; round < 6; ++round) {
    bool any = false;
    for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
      const auto& tri = topo.tris[t];
      if (!active[tri[0]] && !active[tri[1]] && !active[tri[2]]) continue;
      if (moves.has_region[tri[0]] || moves.has_region[tri[1]] || moves.has_region[tri[2]])
        continue;
      const Vec3 n0 = cross(sub(topo.points[tri[1]], topo.points[tri[0]]),
                            sub(topo.points[tri[2]], topo.points[tri[0]]));
      const Vec3 q0 = add(topo.points[tri[0]], delta[tri[0]]);
      const Vec3 n1 = cross(sub(add(topo.points[tri[1]], delta[tri[1]]), q0),
                            sub(add(topo.points[tri[2]], delta[tri[2]]), q0));
      if (dot(n0, n1) > 0.1 * norm(n0) * norm(n1)) continue;
      any = true;
      for (std::uint32_t v : tri) halve[v] = 1;
    }
    if (!any) break;
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (!halve[v]) continue;
      delta[v] = round < 5 ? scale(delta[v], 0.5) : Vec3{0, 0, 0};
      halve[v] = 0;
    }
  }
  SettledMoves out;
  std::vector<Vec3>& next = out.next;  // the new position of each vertex that moves
  std::vector<std::uint32_t>& movers = out.movers;
  for (std::uint32_t v = 0; v < nv; ++v) {
    if (!active[v] || norm(delta[v]) == 0.0) continue;
    Vec3 p = add(topo.points[v], delta[v]);
    if (ctx.round) p = ctx.round(p);
    if (p == topo.points[v]) continue;
    movers.push_back(v);
    next.push_back(p);
  }
  hold_back_coincident(topo, movers, next);
  return out;
}

}  // namespace untangle
