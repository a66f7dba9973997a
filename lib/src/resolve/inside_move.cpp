// Inside moves: movable vertices inside an obstacle (by its winding number) that no contour
// reaches, moved out across the obstacle's surface like an illegal region (DESIGN §4).
#include <algorithm>
#include <map>
#include <utility>

#include "resolve/move_kinds.h"

namespace untangle {

void inside_move(const RepairContext& ctx, Scratch& scratch, SurfaceTrees& trees,
                 const CrossingSet& set, const std::vector<std::uint32_t>& inside,
                 std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  const SceneMeasures& measures = ctx.measures;
  // Inside vertices joined through inside vertices to a crossing belong to a patch the contour
  // moves act on (a region, a flap, the DRN): left to them.
  std::vector<std::uint8_t> reached(topo.points.size(), 0);
  std::vector<std::uint32_t> queue;
  auto reach = [&](std::uint32_t v) {
    if (inside[v] == kNone || reached[v]) return;
    reached[v] = 1;
    queue.push_back(v);
  };
  for (const RawCrossing& x : set.items) {
    for (std::uint32_t v : topo.edges[x.edge]) reach(v);
    for (std::uint32_t v : topo.tris[x.face]) reach(v);
  }
  for (std::size_t i = 0; i < queue.size(); ++i) {
    const std::uint32_t v = queue[i];
    for (std::uint32_t k = topo.vertex_edge_begin[v]; k < topo.vertex_edge_begin[v + 1]; ++k)
      reach(topo.vertex_neighbors[k]);
  }

  // The rest, grouped by (movable mesh, obstacle component): the component of the inside
  // obstacle mesh whose surface is nearest (most obstacles are one component).
  std::map<std::uint32_t, std::vector<std::uint32_t>> components_of;  // obstacle mesh -> comps
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> groups;
  FreshTrees fresh;  // unused: the partners are obstacles, whose trees are kept for the run
  for (std::uint32_t v = 0; v < topo.points.size(); ++v) {
    if (inside[v] == kNone || reached[v] || in_moving_set[v] || !measures.free[v]) continue;
    const std::uint32_t obstacle = inside[v];
    auto it = components_of.find(obstacle);
    if (it == components_of.end()) {
      std::vector<std::uint32_t> comps;
      for (std::uint32_t c = 0; c < topo.component_mesh.size(); ++c)
        if (topo.component_mesh[c] == obstacle) comps.push_back(c);
      it = components_of.emplace(obstacle, std::move(comps)).first;
    }
    std::uint32_t target = it->second.size() == 1 ? it->second.front() : kNone;
    double best = 0.0;
    for (std::uint32_t c : it->second) {
      if (it->second.size() == 1) break;
      const MeshTree& tree = trees.component_tree(c, fresh);
      if (tree.empty()) continue;
      const Vec3& p = topo.points[v];
      const double d = closest_on(tree, p).squared;
      if (target == kNone || d < best) {
        target = c;
        best = d;
      }
    }
    if (target != kNone) groups[{topo.vertex_mesh[v], target}].push_back(v);
  }
  for (const auto& [key, vertices] : groups) {
    for (std::uint32_t v : vertices) in_moving_set[v] = 1;
    move_regions(ctx, scratch, key.first, measures.closed[key.second], vertices,
                 trees.component_tree(key.second, fresh), moves);
  }
}

}  // namespace untangle
