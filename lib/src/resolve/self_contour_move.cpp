// Self contours: a component through itself (a fold through the cloth, a hem's inner layer pushed
// through its outer layer). The illegal side next to each track, by the component's labels (and
// in stages 2-3 each track's own pieces), may move across the sheet of the other track. Every side
// is measured against the narrow sheet (the other track's faces at the crossings grown by two
// rings, the side's own vertices left out) and, when that leaves crossings of this contour, once
// per step against the wide one (every vertex nearer to the other track than to this side): a
// side reaching beyond the narrow sheet (a flap of a finely subdivided sheet diving far through
// its base) finds its closest points on the sheet's rim and would collapse onto it. The move that
// removes most is made. When none helps, the DRN acts; when nothing could be measured (the step's
// budget is spent), the smaller side moves.
#include <algorithm>
#include <memory>

#include "resolve/mesh_walks.h"
#include "resolve/move_kinds.h"

namespace untangle {

void self_contour_move(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                       const TracedContour& traced, const RegionAnalysis& analysis,
                       std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  const std::uint32_t component = track_component(topo, set, traced, 0);
  if (component != track_component(topo, set, traced, 1)) return;
  const std::uint32_t mesh = topo.component_mesh[component];
  if (ctx.measures.role[mesh] != Role::kMovable) return;
  const std::uint32_t base = topo.mesh_vertex_begin[mesh];
  const std::uint32_t end = topo.mesh_vertex_begin[mesh + 1];
  const Contour& c = traced.contour;

  struct Side {
    int track;
    std::vector<std::uint32_t> vertices;  // ascending
    double area = 0.0;
    std::unique_ptr<MeshTree> narrow, wide;
  };
  std::vector<Side> sides;
  const auto labels = analysis.labels.find({component, component});
  if (labels == analysis.labels.end()) return;
  const std::vector<std::int8_t>& illegal = labels->second;
  std::vector<std::uint8_t> seen(end - base, 0);
  for (int k = 0; k < 2; ++k) {
    std::vector<std::uint32_t> side;
    for (std::size_t i = 0; i < c.crossings.size(); ++i) {
      if (traced.edge_track[i] != k) continue;
      for (std::uint32_t v : topo.edges[set.items[c.crossings[i]].edge]) {
        if (illegal[v - base] != 1 || seen[v - base]) continue;
        seen[v - base] = 1;
        side.push_back(v);
      }
    }
    for (std::size_t i = 0; i < side.size(); ++i) {
      const std::uint32_t v = side[i];
      for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
        const std::uint32_t w = topo.vertex_neighbors[j];
        if (illegal[w - base] == 1 && !seen[w - base]) {
          seen[w - base] = 1;
          side.push_back(w);
        }
      }
    }
    if (side.empty()) continue;
    std::sort(side.begin(), side.end());
    double area = 0.0;
    for (std::uint32_t v : side) area += ctx.measures.vertex_edge[v] * ctx.measures.vertex_edge[v];
    sides.push_back({k, std::move(side), area, nullptr, nullptr});
  }
  if (ctx.pieces()) {
    // The second stage: each track's own pieces, as further sides.
    const std::size_t limit =
        std::min(kMeasuredVertices, ctx.measures.component_size[component] / 2);
    for (int k = 0; k < 2; ++k)
      for (std::vector<std::uint32_t>& piece : track_pieces(topo, set, traced, k, limit)) {
        if (std::any_of(sides.begin(), sides.end(),
                        [&](const Side& s) { return s.vertices == piece; }))
          continue;
        double area = 0.0;
        for (std::uint32_t v : piece)
          area += ctx.measures.vertex_edge[v] * ctx.measures.vertex_edge[v];
        sides.push_back({k, std::move(piece), area, nullptr, nullptr});
      }
  }
  if (sides.empty()) {
    // Nothing labelled illegal (a fold lying over itself, crossed where it touches): the fold's
    // outer sheet may still be laid outside its inner one.
    Choice fold = fold_layer_choice(ctx, tools, set, traced, moves);
    if (fold.gain > 0) tools.measured.make(fold, in_moving_set, moves);
    return;
  }

  // The other track's sheet for a side of track k: the faces its crossing edges pass through and
  // the other track's crossing edges, grown by `rings`, never into the moving side nor into
  // `own_side` (the wide patch's limit).
  auto sheet = [&](const Side& side, int rings, const std::vector<std::uint8_t>* own_side) {
    std::vector<std::uint8_t> excluded =
        own_side != nullptr ? *own_side : std::vector<std::uint8_t>(end - base, 0);
    for (std::uint32_t v : side.vertices) excluded[v - base] = 1;
    std::vector<std::uint32_t> seeds;
    for (std::size_t i = 0; i < c.crossings.size(); ++i) {
      const RawCrossing& x = set.items[c.crossings[i]];
      if (traced.edge_track[i] == side.track) {
        for (std::uint32_t v : topo.tris[x.face]) seeds.push_back(v);
      } else {
        for (std::uint32_t v : topo.edges[x.edge]) seeds.push_back(v);
      }
    }
    std::vector<std::uint8_t> in_sheet;
    return build_tree(topo, local_sheet(topo, mesh, seeds, excluded, rings, in_sheet));
  };
  auto candidates_of = [&](bool wide) {
    std::vector<Candidate> out;
    for (const Side& side : sides) {
      const MeshTree* tree = wide ? side.wide.get() : side.narrow.get();
      if (tree == nullptr) continue;
      std::vector<std::uint32_t> still;
      for (std::uint32_t v : side.vertices)
        if (!moves.has_region[v]) still.push_back(v);  // a vertex moves once per iteration
      if (!still.empty()) out.push_back({mesh, 0, std::move(still), tree});
    }
    return out;
  };
  auto take_better = [](Choice& chosen, Choice&& other) {
    if (!other.part.empty() && (chosen.part.empty() || other.gain > chosen.gain ||
                                (other.gain == chosen.gain && other.strain < chosen.strain)))
      chosen = std::move(other);
  };
  const long long all = static_cast<long long>(c.crossings.size());
  for (Side& side : sides) side.narrow = sheet(side, 2, nullptr);
  const std::vector<Candidate> candidates = candidates_of(false);
  if (candidates.empty()) return;  // every side's vertices already move in this step
  Choice chosen = measured_choice(ctx, tools, set, candidates);
  if (chosen.gain < all && !tools.measured.wide_tried) {
    tools.measured.wide_tried = true;
    const int rings = static_cast<int>(ctx.measures.component_size[component]);
    std::vector<std::uint8_t> own_side[2];
    for (int k = 0; k < 2; ++k)
      own_side[k] = own_side_of(topo, mesh, track_corners(topo, set, traced, k),
                                track_corners(topo, set, traced, 1 - k), rings);
    for (Side& side : sides) side.wide = sheet(side, rings, &own_side[side.track]);
    take_better(chosen, measured_choice(ctx, tools, set, candidates_of(true)));
  }
  if (chosen.gain <= 0) {
    Choice fold = fold_layer_choice(ctx, tools, set, traced, moves);
    if (fold.gain > 0) chosen = std::move(fold);
  }
  if (chosen.gain > 0) {
    tools.measured.make(chosen, in_moving_set, moves);
    return;
  }
  if (!chosen.part.empty()) return;  // measured, and no side helps: the DRN acts
  const Side* smaller = nullptr;
  for (const Side& side : sides)
    if (smaller == nullptr || side.area < smaller->area) smaller = &side;
  if (smaller == nullptr) return;
  for (const Candidate& candidate : candidates) {
    if (candidate.tree != smaller->narrow.get()) continue;
    for (std::uint32_t v : candidate.vertices) in_moving_set[v] = 1;
    move_regions(ctx, tools.scratch, mesh, 0, candidate.vertices, *candidate.tree, moves);
  }
}

}  // namespace untangle
