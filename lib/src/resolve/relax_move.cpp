// Relaxation of a contour's neighbourhood: the contour's vertices grown by 0 to kRelaxRings rings,
// each vertex moved kRelaxSweeps times halfway to the mean of its neighbours (a boundary vertex to
// that of its boundary neighbours, so a rim stays a rim), the ring around held. Where a fine sheet
// was pressed into a sliver or pinched through a loop vertex, no side or DRN step helps; relaxing
// the crumpled triangles opens them again. Each size is measured; the one that removes most
// crossings is returned.
#include <algorithm>
#include <iterator>

#include "resolve/mesh_walks.h"
#include "resolve/move_kinds.h"

namespace untangle {
namespace {

constexpr int kRelaxRings = 4;
constexpr int kRelaxSweeps = 10;

}  // namespace

Choice relax_choice(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                    const std::vector<std::uint32_t>& seeds, const Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  Choice best;
  std::vector<std::uint32_t> region = seeds;  // ascending
  std::vector<std::uint32_t> front = seeds;
  for (int rings = 0; rings <= kRelaxRings; ++rings) {
    if (rings > 0) {
      std::vector<std::uint32_t> next;
      for (std::uint32_t v : front)
        for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j)
          next.push_back(topo.vertex_neighbors[j]);
      std::sort(next.begin(), next.end());
      next.erase(std::unique(next.begin(), next.end()), next.end());
      front.clear();
      std::set_difference(next.begin(), next.end(), region.begin(), region.end(),
                          std::back_inserter(front));
      if (front.empty()) break;
      std::vector<std::uint32_t> grown;
      std::merge(region.begin(), region.end(), front.begin(), front.end(),
                 std::back_inserter(grown));
      region = std::move(grown);
    }
    std::vector<std::uint32_t> part;  // ascending
    for (std::uint32_t v : region)
      if (ctx.measures.free[v] && !tools.measured.taken(v) && !moves.has_region[v])
        part.push_back(v);
    if (part.empty() || 3 * part.size() > tools.measured.trial_budget ||
        3 * part.size() > tools.measured.relax_budget)
      continue;
    std::vector<Vec3> at(part.size());
    for (std::size_t i = 0; i < part.size(); ++i) at[i] = topo.points[part[i]];
    auto position = [&](const std::vector<Vec3>& now, std::uint32_t w) {
      const auto it = std::lower_bound(part.begin(), part.end(), w);
      return it != part.end() && *it == w ? now[static_cast<std::size_t>(it - part.begin())]
                                          : topo.points[w];
    };
    for (int sweep = 0; sweep < kRelaxSweeps; ++sweep) {
      std::vector<Vec3> next(part.size());
      for (std::size_t i = 0; i < part.size(); ++i) {
        const std::uint32_t v = part[i];
        const bool rim = is_boundary_vertex(topo, v);
        Vec3 sum{0.0, 0.0, 0.0};
        int count = 0;
        for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
          if (rim && !topo.is_boundary(topo.vertex_edges[j])) continue;
          sum = add(sum, position(at, topo.vertex_neighbors[j]));
          ++count;
        }
        next[i] = count > 0 ? add(scale(at[i], 0.5), scale(sum, 0.5 / count)) : at[i];
      }
      at = std::move(next);
    }
    Choice option;
    option.strain = 0.0;
    for (std::size_t i = 0; i < part.size(); ++i)
      option.propose(part[i], topo.points[part[i]], at[i], ctx.round);
    if (option.part.empty()) continue;
    tools.measured.trial_budget -= 3 * option.part.size();
    tools.measured.relax_budget -= 3 * option.part.size();
    option.gain = tools.measured.gain(ctx.detect, set, option.part, option.at);
    if (option.gain > best.gain) best = std::move(option);
  }
  return best;
}

}  // namespace untangle
