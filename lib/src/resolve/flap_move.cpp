// Flap moves. A BI/BI contour between two components (two sheets overlapping at a corner, a
// sleeve's cuff through a hem) separates nothing, so no region holds its labels; the paper slides
// it toward the other mesh's boundary one small step per iteration, which takes about one
// iteration per crossing and, being a shear of both meshes, is sensitive to rounding. Here the
// contour's flap moves instead: on each side of the contour, the vertices next to it that lie on
// one side of the other surface and over it (their closest point on it is not on its boundary),
// grown from the crossing edges. Each flap's parts and their candidate moves across the other
// surface are measured: the move that removes most crossings is made. When none removes any, the
// flap with the least area moves as a region. What remains near the boundary goes to the DRN.
//
// A contour of one component with itself that separates nothing (a flap of a sheet through its
// own base across the base's edge, contours through loop vertices) is treated the same way, with
// a local patch as "the other surface": the other track's faces and edges at the crossings, grown
// by a few rings, never into this side's own crossing corners; its rim counts as boundary. A loop
// vertex (where the two tracks meet) is a barrier: never in a flap, never crossed by its growth
// (the flap of a contour that only touches one elsewhere must not take the pinch along). A contour
// through a loop vertex moves a flap only when the measurement says it helps, and is otherwise
// left to the DRN: unmeasured flaps next to a pinch cost more crossings on real garments than they
// removed on the small loop-vertex cases.
#include <algorithm>
#include <map>
#include <memory>
#include <set>

#include "detect/orientation.h"
#include "resolve/mesh_walks.h"
#include "resolve/move_kinds.h"

namespace untangle {
namespace {

// Rings of neighbours around the other track's crossings that stand for "the other surface" of a
// self contour.
constexpr int kPatchRings = 3;

}  // namespace

void flap_move(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
               const TracedContour& t, FreshTrees& trees, std::vector<std::uint8_t>& in_moving_set,
               Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  const Contour& c = t.contour;
  if (c.closed) return;
  const std::uint32_t components[2] = {track_component(topo, set, t, 0),
                                       track_component(topo, set, t, 1)};
  const bool self = components[0] == components[1];
  // A track that separates but cuts no edge encloses no vertex (a sliver of a base's edge inside
  // a flap's triangles): self_contour_move finds no side there. The second stage gives such a
  // contour a flap too.
  auto separates_vertices = [&](const Track& track) {
    return track.separates && (!ctx.pieces() || track.cut_edges > 0);
  };
  if (self) {
    if (separates_vertices(c.tracks[0]) || separates_vertices(c.tracks[1]))
      return;  // self_contour_move's case
  } else if (c.tracks[0].type != TrackType::kBI || c.tracks[1].type != TrackType::kBI) {
    return;
  }
  for (std::uint32_t ci : c.crossings) {
    const RawCrossing& x = set.items[ci];
    for (std::uint32_t v : topo.edges[x.edge])
      if (in_moving_set[v]) return;
    for (std::uint32_t v : topo.tris[x.face])
      if (in_moving_set[v]) return;
  }
  auto corners_of = [&](int k) { return track_corners(topo, set, t, k); };
  struct Flap {
    double area = INFINITY;
    int track = -1;
    bool wide = false;
    std::vector<std::uint32_t> vertices;
    const MeshTree* tree = nullptr;  // the other surface
  };
  std::vector<Flap> flaps;
  // For a self contour, per patch size and track: the other surface. A flap of a finely
  // subdivided sheet reaches beyond the narrow patch; the wide one can take in another fold of
  // the same sheet, so it is only tried when the narrow one offers nothing that helps.
  std::unique_ptr<MeshTree> patches[2][2];
  auto collect = [&](int wide) {
    for (int k = 0; k < 2; ++k) {
      const std::uint32_t own = components[k], other = components[1 - k];
      const std::uint32_t mesh = topo.component_mesh[own];
      if (ctx.measures.role[mesh] != Role::kMovable) continue;
      const std::vector<std::uint32_t> seeds = corners_of(k);
      std::set<std::pair<std::uint32_t, std::uint32_t>> rim;  // a self patch's edges of one face
      std::vector<std::uint8_t> in_patch;
      const std::uint32_t base = topo.mesh_vertex_begin[mesh];
      if (self) {
        const int rings = wide ? static_cast<int>(ctx.measures.component_size[own]) : kPatchRings;
        // The patch never reaches this side's corners, nor vertices nearer (in rings) to them than
        // to the other track's corners: on a sheet folded at a loop vertex the two sides are
        // joined, and the patch must not grow over the fold into the flap it is to judge.
        const std::vector<std::uint32_t> others = corners_of(1 - k);
        const std::vector<std::uint32_t> tris = local_sheet(
            topo, mesh, others, own_side_of(topo, mesh, seeds, others, rings), rings, in_patch);
        std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
        for (std::uint32_t f : tris) {
          const auto& tri = topo.tris[f];
          for (int e = 0; e < 3; ++e)
            ++uses[{std::min(tri[e], tri[(e + 1) % 3]), std::max(tri[e], tri[(e + 1) % 3])}];
        }
        if (tris.empty()) continue;
        for (const auto& [edge, count] : uses)
          if (count == 1) rim.insert(edge);
        patches[wide][k] = build_tree(topo, tris);
      }
      const MeshTree& tree = self ? *patches[wide][k] : tools.trees.component_tree(other, trees);
      if (tree.empty()) continue;
      auto beyond_edge = [&](std::uint32_t a, std::uint32_t b) {
        if (self) return rim.count({std::min(a, b), std::max(a, b)}) > 0;
        return topo.is_boundary(topo.find_edge(a, b));
      };
      // Side of the other surface (+1, -1) where the vertex is over it, 0 where its closest point
      // lies on the other surface's boundary (beyond it).
      std::map<std::uint32_t, int> side;
      auto side_of = [&](std::uint32_t v) {
        const auto it = side.find(v);
        if (it != side.end()) return it->second;
        if (self && in_patch[v - base]) {
          side.emplace(v, 0);
          return 0;
        }
        const Vec3& p = topo.points[v];
        const Closest hit = closest_on(tree, p);
        const std::uint32_t face = hit.face;
        const auto& f = topo.tris[face];
        const Vec3& q = hit.point;
        // A corner of the closest face lies on the other surface (a fold vertex shared by both
        // sides of a sheet).
        int result =
            f[0] == v || f[1] == v || f[2] == v ? 0 : orient_sos(topo.points, f[0], f[1], f[2], v);
        // In the second stage a vertex beyond the other surface's edge keeps the side of the
        // closest face's plane: the part of a flap that dives beyond a base's edge moves with the
        // flap, instead of holding its triangles through the edge (reflected across that plane).
        for (int e = 0; e < 3 && result != 0 && !ctx.pieces(); ++e) {
          // Closest point on edge (f[e], f[e+1]) of the other surface's boundary: not over it.
          const Vec3& a = topo.points[f[e]];
          const Vec3& b = topo.points[f[(e + 1) % 3]];
          const Vec3 ab = sub(b, a);
          const double len2 = dot(ab, ab);
          if (len2 == 0.0) continue;
          const double along = std::clamp(dot(sub(q, a), ab) / len2, 0.0, 1.0);
          const double off = norm(sub(q, add(a, scale(ab, along))));
          if (off <= 1e-9 * std::sqrt(len2) && beyond_edge(f[e], f[(e + 1) % 3])) result = 0;
        }
        side.emplace(v, result);
        return result;
      };
      // A flap is small next to its component: one that grows past a quarter of it is a side of
      // the surface, not a flap. Next to a loop vertex only measured moves are made, so a flap
      // too large to be measured is not grown further.
      const std::size_t component_size = ctx.measures.component_size[own];
      std::size_t limit = std::max<std::size_t>(16, component_size / 4);
      if (c.loop_vertices > 0) limit = std::min(limit, kMeasuredVertices);
      for (int wanted : {1, -1}) {
        std::vector<std::uint32_t> flap;
        std::map<std::uint32_t, bool> seen;
        for (std::uint32_t v : seeds) {
          if (side_of(v) != wanted || seen.count(v)) continue;
          seen[v] = true;
          flap.push_back(v);
        }
        bool too_large = false;
        for (std::size_t i = 0; i < flap.size() && !too_large; ++i) {
          const std::uint32_t v = flap[i];
          for (std::uint32_t e = topo.vertex_edge_begin[v]; e < topo.vertex_edge_begin[v + 1];
               ++e) {
            const std::uint32_t w = topo.vertex_neighbors[e];
            if (seen.count(w)) continue;
            seen[w] = true;
            if (std::find(t.loop_vertex_ids.begin(), t.loop_vertex_ids.end(), w) !=
                t.loop_vertex_ids.end())
              continue;
            if (side_of(w) != wanted) continue;
            flap.push_back(w);
            if (flap.size() > limit) {
              too_large = true;
              break;
            }
          }
        }
        if (too_large || flap.empty()) continue;
        bool any_free = false;
        double area = 0.0;
        for (std::uint32_t v : flap) {
          any_free = any_free || ctx.measures.free[v];
          area += ctx.measures.vertex_edge[v] * ctx.measures.vertex_edge[v];
        }
        if (!any_free) continue;
        std::sort(flap.begin(), flap.end());
        flaps.push_back({area, k, wide == 1, std::move(flap), &tree});
      }
    }
  };
  auto candidates_of = [&](bool wide) {
    std::vector<Candidate> out;
    for (Flap& flap : flaps)
      if (flap.wide == wide)
        out.push_back({topo.component_mesh[components[flap.track]],
                       self ? 0 : ctx.measures.closed[components[1 - flap.track]], flap.vertices,
                       flap.tree});
    return out;
  };
  collect(0);
  const std::vector<Candidate> candidates = candidates_of(false);
  Choice chosen = measured_choice(ctx, tools, set, candidates);
  // A self contour whose narrow patch offers no helpful flap (a flap of a finely subdivided
  // sheet reaches beyond it) tries the wide patch, within the step's budget.
  // Building a wide patch walks and indexes about half the component: one per step.
  if (self && chosen.gain <= 0 && !tools.measured.wide_tried) {
    tools.measured.wide_tried = true;
    collect(1);
    Choice wide = measured_choice(ctx, tools, set, candidates_of(true));
    if (!wide.part.empty() && wide.gain > 0) chosen = std::move(wide);
  }
  if (candidates.empty() && chosen.part.empty()) return;
  // A move that adds crossings is never made; one that changes nothing only on a contour
  // without a loop vertex (it slides toward the boundary). Otherwise the DRN acts.
  if (!chosen.part.empty()) {
    if (chosen.gain < 0 || (chosen.gain == 0 && c.loop_vertices > 0)) return;
    tools.measured.make(chosen, in_moving_set, moves);
    return;
  }
  // Nothing measured (the step's budget is spent): the smallest flap by the narrow patch moves,
  // except next to a loop vertex.
  if (c.loop_vertices > 0) return;
  // (The narrow patch's flaps come first in `flaps`, in the order of `candidates`.)
  if (candidates.empty()) return;
  std::size_t smallest_index = 0;
  for (std::size_t i = 1; i < candidates.size(); ++i)
    if (flaps[i].area < flaps[smallest_index].area) smallest_index = i;
  const Candidate& smallest = candidates[smallest_index];
  for (std::uint32_t v : smallest.vertices) in_moving_set[v] = 1;
  move_regions(ctx, tools.scratch, smallest.mesh, smallest.orientation, smallest.vertices,
               *smallest.tree, moves);
}

}  // namespace untangle
