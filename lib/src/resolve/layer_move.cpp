// Layer moves: two garment layers through each other, an exact or nearly exact copy, a fold of
// one garment lying over itself. Their contours are the noise of two surfaces a fraction of an
// edge apart, so no large legal region can be trusted; the order of the layers is kept instead,
// the outer one laid outside the inner one at the clearance.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>

#include "resolve/move_kinds.h"

namespace untangle {
namespace {

// How far (in mean edge lengths) a vertex of the outer layer that dips through the inner one is
// still laid back on its side.
constexpr double kLayerReach = 2.0;

// Adds to delta[v] what it lacks of `length` along the unit direction `along` (each vertex keeps
// the longest push asked of it along a direction).
void push_along(std::map<std::uint32_t, Vec3>& delta, std::uint32_t v, const Vec3& along,
                double length) {
  Vec3& d = delta[v];
  const double have = dot(d, along);
  if (have < length) d = add(d, scale(along, length - have));
}

// The move one crossing between an outer and an inner sheet asks for, at most `limit` long, added
// to `delta` (push_along). `outward(f)` is face f's normal turned to the outer side. An outer
// edge through an inner face (`edge_outside`) has its ends laid on the face's outer side at the
// clearance; an inner edge through an outer face pushes that face's corners outward until the
// edge's ends lie the clearance beneath its plane. Layers (lay_layer) and folds
// (fold_layer_choice) both lay their crossings this way.
void lay_crossing(const SceneTopology& topo, const RawCrossing& x, bool edge_outside,
                  const std::function<Vec3(std::uint32_t)>& outward, double clearance, double limit,
                  std::map<std::uint32_t, Vec3>& delta) {
  auto push = [&](std::uint32_t v, const Vec3& along, double length) {
    push_along(delta, v, along, std::min(length, limit));
  };
  const auto& tri = topo.tris[x.face];
  const Vec3& corner = topo.points[tri[0]];
  if (edge_outside) {
    const Vec3 out = outward(x.face);
    for (std::uint32_t v : topo.edges[x.edge])
      push(v, out, clearance - dot(sub(topo.points[v], corner), out));
    return;
  }
  Vec3 out{0.0, 0.0, 0.0};
  for (std::uint32_t k = topo.edge_face_begin[x.edge]; k < topo.edge_face_begin[x.edge + 1]; ++k)
    out = add(out, outward(topo.edge_faces[k]));
  out = unit(out);
  Vec3 m = face_normal(topo, x.face);
  if (dot(m, out) < 0.0) m = scale(m, -1.0);
  const double facing = dot(m, out);
  if (facing < 0.2) return;  // the sheets nearly perpendicular: not one lying over the other
  double length = 0.0;
  for (std::uint32_t v : topo.edges[x.edge])
    length = std::max(length, (dot(sub(topo.points[v], corner), m) + clearance) / facing);
  for (std::uint32_t v : tri) push(v, out, length);
}

// Around a closed obstacle (a body) the outer layer moves and the inner one stays against the
// body. Each component's faces near the other face away from the body (their normals point away
// from its nearest point) mostly on one side, `outward`; the other lies on that side by a margin
// (its area vote, turned by that sign). Interleaved layers lie on both sides of each other, and
// from each one's faces the other can look outer, so both views are weighed and the one with the
// larger margin is outer, whichever is listed first. The mover is laid on the inner one's outer
// side. Without an obstacle the component with the higher index (the meshes are in canonical
// order, canonical_order.h, not necessarily the listing order) moves, to the side most of its
// near vertices lie on.
LayerOrder decide_layer_order(const RepairContext& ctx, SurfaceTrees& surfaces, std::uint32_t a,
                              std::uint32_t b) {
  const SceneTopology& topo = ctx.topo;
  FreshTrees trees;
  const MeshTree& tree_a = surfaces.component_tree(a, trees);
  const MeshTree& tree_b = surfaces.component_tree(b, trees);
  if (tree_a.empty() || tree_b.empty()) return {};
  const double near_a = 0.5 * ctx.measures.mean_edge[topo.component_mesh[a]];
  const double near_b = 0.5 * ctx.measures.mean_edge[topo.component_mesh[b]];
  long long vote_a = 0, vote_b = 0;
  const std::vector<NearPoint> a_near = near_points(topo, ctx.measures, a, tree_b, near_a, vote_a);
  const std::vector<NearPoint> b_near = near_points(topo, ctx.measures, b, tree_a, near_b, vote_b);
  auto outward_of = [&](const std::vector<NearPoint>& near) {
    long long outward = 0;
    for (const NearPoint& x : near) {
      Vec3 body{};
      if (!surfaces.nearest_obstacle_point(x.c, body)) break;
      const double away = dot(x.n, sub(x.c, body));
      outward += away > 0 ? 1 : away < 0 ? -1 : 0;
    }
    return outward > 0 ? 1 : outward < 0 ? -1 : 0;
  };
  const int out_a = outward_of(b_near);  // a's faces, seen from b's near vertices
  const int out_b = outward_of(a_near);
  LayerOrder order;
  bool a_moves = false;
  if (out_a != 0 && out_b != 0) {
    const double b_outer = area_vote(topo, b_near) * out_a;
    const double a_outer = area_vote(topo, a_near) * out_b;
    a_moves = a_outer > b_outer;
    order.side = a_moves ? out_b : out_a;
  } else {
    // One view only: b is outer when it lies on a's outer side.
    a_moves = out_a != 0 && out_a != (vote_b < 0 ? -1 : 1);
    // An exact copy has no majority and goes to the positive side.
    order.side = (a_moves ? vote_a : vote_b) < 0 ? -1.0 : 1.0;
  }
  order.mover = a_moves ? a : b;
  long long aligned = 0;
  for (const NearPoint& x : a_moves ? a_near : b_near) {
    const double c = dot(oriented_vertex_normal(topo, ctx.measures, x.v), x.n);
    aligned += c > 0 ? 1 : c < 0 ? -1 : 0;
  }
  order.normals_decided = aligned != 0;
  // Interleaved: a quarter or more of the near vertices on the minority side.
  const std::size_t near = a_near.size() + b_near.size();
  order.interleaved =
      near > 0 && 2 * static_cast<std::size_t>(std::llabs(vote_a) + std::llabs(vote_b)) <= near;
  return order;
}

// Whether a vertex of one of the contour's crossings (its edge's ends, its face's corners) is a key
// of `moved`.
bool touches(const SceneTopology& topo, const CrossingSet& set, const TracedContour& t,
             const std::map<std::uint32_t, Vec3>& moved) {
  for (std::uint32_t ci : t.contour.crossings) {
    const RawCrossing& x = set.items[ci];
    for (std::uint32_t v : topo.edges[x.edge])
      if (moved.count(v)) return true;
    for (std::uint32_t v : topo.tris[x.face])
      if (moved.count(v)) return true;
  }
  return false;
}

// Lays the outer component of a layered pair (layered_pairs) on its side of the inner one at the
// clearance: every vertex of it closer than half an edge and not that far on its side goes to the
// closest point plus the clearance; the corners of its faces that a vertex of the inner one comes
// closer to than the clearance (a bulge poking through a flat triangle) move away by the
// difference; a contour between them that none of these moves touches moves by its crossings
// (lay_crossing), at most half an edge per step.
void lay_layer(const RepairContext& ctx, SurfaceTrees& surfaces, const CrossingSet& set,
               const std::vector<TracedContour>& traced, std::uint32_t a, std::uint32_t b,
               const LayerOrders& orders, std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  FreshTrees trees;
  const MeshTree& tree_a = surfaces.component_tree(a, trees);
  const MeshTree& tree_b = surfaces.component_tree(b, trees);
  if (tree_a.empty() || tree_b.empty()) return;
  const LayerOrder& order = orders.at({a, b});
  const std::uint32_t mover = order.mover;
  const std::uint32_t other = mover == a ? b : a;
  const MeshTree& mover_tree = mover == a ? tree_a : tree_b;
  const MeshTree& other_tree = mover == a ? tree_b : tree_a;
  const std::uint32_t mesh = topo.component_mesh[mover];
  const double clearance = ctx.options.clearance * ctx.measures.mean_edge[mesh];
  long long unused = 0;
  std::map<std::uint32_t, Vec3> delta;  // ordered: the result does not depend on hashing
  const double near = 0.5 * ctx.measures.mean_edge[mesh];
  for (const NearPoint& x : near_points(topo, ctx.measures, mover, other_tree,
                                        kLayerReach * ctx.measures.mean_edge[mesh], unused)) {
    // Half the clearance is enough to leave a vertex alone (one laid at the clearance stays).
    if (order.side * x.side >= 0.5 * clearance) continue;
    // A vertex on the wrong side whose closest point is the other's hem lies past it (a collar
    // above a lower neckline), not over it: it is left alone. Beyond half an edge only a dip
    // through the other's faces is laid back.
    const bool past_hem = order.side * x.side < 0.0 && on_hem(topo, x.face, x.c);
    if (past_hem || (norm(sub(topo.points[x.v], x.c)) > near && order.side * x.side >= 0.0))
      continue;
    delta[x.v] = sub(add(x.c, scale(x.n, order.side * clearance)), topo.points[x.v]);
  }
  if (order.normals_decided) {
    const std::uint32_t other_mesh = topo.component_mesh[other];
    for (const NearPoint& x : near_points(topo, ctx.measures, other, mover_tree,
                                          0.5 * ctx.measures.mean_edge[other_mesh], unused)) {
      // Outward is the inner vertex's own normal turned to the mover's side: the mover's face
      // normals turn over where it folds (a turned-down collar), and pushing along them took
      // the collar into the body.
      const Vec3 along = scale(oriented_vertex_normal(topo, ctx.measures, x.v), order.side);
      const double gap = dot(sub(x.c, topo.points[x.v]), along);
      if (gap >= 0.5 * clearance) continue;
      for (std::uint32_t v : topo.tris[x.face]) push_along(delta, v, along, clearance - gap);
    }
  }
  // Where the layers cross although no vertex above was moved (an edge of one through a face
  // of the other between vertices that each lie on their side of their closest point, over a
  // crease or a spike longer than the reach), the crossings themselves say what moves.
  std::vector<const TracedContour*> untouched;
  for (const TracedContour& t : traced) {
    const std::uint32_t ca = track_component(topo, set, t, 0);
    const std::uint32_t cb = track_component(topo, set, t, 1);
    if (std::min(ca, cb) == a && std::max(ca, cb) == b && !touches(topo, set, t, delta))
      untouched.push_back(&t);
  }
  // Outward is taken from the inner layer's faces each time: the mover's own normals turn over
  // where it folds (a turned-down collar).
  auto outward = [&](std::uint32_t f) {
    return scale(oriented_normal(topo, ctx.measures, f), order.side);
  };
  for (const TracedContour* t : untouched)
    for (std::uint32_t ci : t->contour.crossings) {
      const RawCrossing& x = set.items[ci];
      lay_crossing(topo, x, topo.tri_component(x.face) == other, outward, clearance, near, delta);
    }
  for (const auto& [v, d] : delta) {
    if (!ctx.measures.free[v] || moves.has_region[v]) continue;
    moves.region[v] = d;
    moves.has_region[v] = 1;
    in_moving_set[v] = 1;
  }
}

}  // namespace

// Nearly parallel: |cos| > 0.95 between the face's normal and that of a face on the crossing edge.
ParallelCounts parallel_crossings(const SceneTopology& topo, const CrossingSet& set,
                                  const std::vector<TracedContour>& traced) {
  ParallelCounts parallel;
  for (const TracedContour& t : traced) {
    const std::uint32_t a = track_component(topo, set, t, 0);
    const std::uint32_t b = track_component(topo, set, t, 1);
    if (a == b) continue;
    auto& count = parallel[{std::min(a, b), std::max(a, b)}];
    for (std::uint32_t ci : t.contour.crossings) {
      const RawCrossing& x = set.items[ci];
      const Vec3 nf = face_normal(topo, x.face);
      const Vec3 ne = face_normal(topo, topo.edge_faces[topo.edge_face_begin[x.edge]]);
      ++count[1];
      if (std::abs(dot(nf, ne)) > 0.95) ++count[0];
    }
  }
  return parallel;
}

// Layers: two movable, open, orientable components at least half of whose crossings join nearly
// parallel faces, and whose vertices near each other lie on both sides of each other with no
// clear majority (interleaved: a dress over a t-shirt, made for the same body at the same offset).
// Their order over most of their overlap is kept (lay_layer). Layers with a clear majority (a
// shirt's hem over the trousers' waist) are left to the area rule, which also moves their deep
// dips whole.
ComponentPairs layered_pairs(const RepairContext& ctx, SurfaceTrees& surfaces,
                             const ParallelCounts& parallel, LayerOrders& orders) {
  const SceneTopology& topo = ctx.topo;
  ComponentPairs out;
  for (const auto& [key, count] : parallel) {
    // Decided once, where first seen: as the layers part, their last crossings need not be
    // parallel nor their vertices interleaved.
    auto found = orders.find(key);
    if (found == orders.end()) {
      if (2 * count[0] < count[1]) continue;
      // A closed surface (a ball through a sheet) is not a layer, however flat the crossing.
      auto layer = [&](std::uint32_t c) {
        return ctx.measures.movable_component(topo, c) && ctx.measures.oriented[c] &&
               ctx.measures.closed[c] == 0;
      };
      if (!layer(key.first) || !layer(key.second)) continue;
      found = orders.emplace(key, decide_layer_order(ctx, surfaces, key.first, key.second)).first;
    }
    if (found->second.interleaved) out.insert(key);
  }
  return out;
}

// Two components that cross but where neither side has an illegal region (a garment and an exact
// or nearly exact copy of it; sheets lying in one plane; a garment lying on an obstacle): the
// contours separate nothing, so the layers are told apart by index (in the canonical order of
// meshes, canonical_order.h). The movable component with the higher index is laid on the side of the other where most of its near vertices lie (an exact
// copy: the positive side of the other's face normals) at the clearance, wherever it is closer
// than half an edge. Layered pairs go to lay_layer instead.
void separate_coincident_layers(const RepairContext& ctx, SurfaceTrees& surfaces,
                                const CrossingSet& set, const std::vector<TracedContour>& traced,
                                const ParallelCounts& parallel, const ComponentPairs& layered,
                                const LayerOrders& orders, const RegionAnalysis& analysis,
                                std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  for (const auto& [key, count] : parallel) {
    const auto [a, b] = key;
    if (layered.count(key)) {
      lay_layer(ctx, surfaces, set, traced, a, b, orders, in_moving_set, moves);
      continue;
    }
    if (2 * count[0] < count[1]) continue;  // surfaces crossing at an angle: not layers
    bool decided = false;
    for (const IllegalSet& s : analysis.illegal)
      if ((s.component == a && s.partner == b) || (s.component == b && s.partner == a))
        decided = true;
    if (decided) continue;
    if (!ctx.measures.movable_component(topo, a) && !ctx.measures.movable_component(topo, b))
      continue;
    const std::uint32_t mover = ctx.measures.movable_component(topo, b) ? b : a;
    const std::uint32_t other = mover == b ? a : b;
    const std::uint32_t mesh = topo.component_mesh[mover];
    FreshTrees trees;
    const MeshTree* tree = &surfaces.component_tree(other, trees);
    if (tree->empty()) continue;
    const double clearance = ctx.options.clearance * ctx.measures.mean_edge[mesh];
    long long vote = 0;
    const std::vector<NearPoint> close =
        near_points(topo, ctx.measures, mover, *tree, 0.5 * ctx.measures.mean_edge[mesh], vote);
    const double sign = vote < 0 ? -1.0 : 1.0;
    for (const NearPoint& x : close) {
      if (!ctx.measures.free[x.v] || moves.has_region[x.v] || sign * x.side >= clearance) continue;
      moves.region[x.v] = sub(add(x.c, scale(x.n, sign * clearance)), topo.points[x.v]);
      moves.has_region[x.v] = 1;
      in_moving_set[x.v] = 1;
    }
  }
}

// A fold of one component lying over itself near a closed obstacle (a turned-down collar over its
// neck band, a hem turned up inside a skirt), crossed where the two sheets touch: the region rules
// see no illegal side there, and the DRN shears the fold into the body. The contour's two sheets
// are laid one outside the other instead (lay_crossing), outward meaning away from the nearest
// closed obstacle, at most half an edge per vertex. Each track is tried as the inner one; the move
// is measured and the one that removes most crossings is returned.
Choice fold_layer_choice(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                         const TracedContour& traced, const Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  Choice best;
  const Contour& c = traced.contour;
  if (c.crossings.empty()) return best;
  const std::uint32_t mesh = topo.tri_mesh[set.items[c.crossings[0]].face];
  const double clearance = ctx.options.clearance * ctx.measures.mean_edge[mesh];
  const double limit = 0.5 * ctx.measures.mean_edge[mesh];
  // Away from the body at each crossing.
  std::vector<Vec3> outward;
  for (std::uint32_t ci : c.crossings) {
    Vec3 body{};
    if (!tools.trees.nearest_obstacle_point(set.items[ci].point, body)) return best;
    outward.push_back(unit(sub(set.items[ci].point, body)));
  }
  // face_normal(t) turned to agree with o.
  auto facing = [&](std::uint32_t t, const Vec3& o) {
    const Vec3 n = face_normal(topo, t);
    return dot(n, o) < 0.0 ? scale(n, -1.0) : n;
  };
  for (int inner = 0; inner < 2; ++inner) {
    std::map<std::uint32_t, Vec3> delta;  // ordered: the result does not depend on hashing
    for (std::size_t i = 0; i < c.crossings.size(); ++i) {
      auto outward_here = [&](std::uint32_t f) { return facing(f, outward[i]); };
      lay_crossing(topo, set.items[c.crossings[i]], traced.edge_track[i] != inner, outward_here,
                   clearance, limit, delta);
    }
    Choice option;
    option.strain = 0.0;
    for (const auto& [v, d] : delta) {
      if (!ctx.measures.free[v] || tools.measured.taken(v) || moves.has_region[v]) continue;
      option.propose(v, topo.points[v], add(topo.points[v], d), ctx.round);
    }
    if (option.part.empty() || 3 * option.part.size() > tools.measured.trial_budget) continue;
    tools.measured.trial_budget -= 3 * option.part.size();
    option.gain = tools.measured.gain(ctx.detect, set, option.part, option.at);
    if (option.gain > best.gain) best = std::move(option);
  }
  return best;
}

}  // namespace untangle
