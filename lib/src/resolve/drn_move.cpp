// The paper's dynamic repulsive normal (DRN, Eq. 1) per crossing: at crossing x of edge e (mesh
// P) through face f (mesh Q), d = n_r + lambda (r1 + r2), e gets +d and f gets -d, split by mass;
// BI/BI tracks slide toward the other mesh's boundary. And its measured form, for stages 2-3 on
// contours whose two sides both move.
#include <algorithm>
#include <cmath>

#include "detect/orientation.h"
#include "resolve/move_kinds.h"

namespace untangle {
namespace {

// Label of welded vertex v with respect to component `partner` (-1 undecided).
int label(const SceneTopology& topo, const RegionAnalysis& analysis, std::uint32_t v,
          std::uint32_t partner) {
  const std::uint32_t component = topo.vertex_component[v];
  auto it = analysis.labels.find({component, partner});
  if (it == analysis.labels.end()) return -1;
  return it->second[v - topo.mesh_vertex_begin[topo.component_mesh[component]]];
}

}  // namespace

void drn_moves(const RepairContext& ctx, const CrossingSet& set, const TracedContour& t,
               const RegionAnalysis& analysis, Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  const Contour& c = t.contour;
  const std::size_t n = c.crossings.size();
  // Which end of an open contour lies on each mesh's boundary (for the BI rule).
  auto end_on_boundary_of = [&](std::size_t index, std::uint32_t mesh) {
    const RawCrossing& x = set.items[c.crossings[index]];
    return topo.is_boundary(x.edge) && topo.edge_mesh(x.edge) == mesh;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const RawCrossing& x = set.items[c.crossings[i]];
    const std::uint32_t q_mesh = topo.tri_mesh[x.face];
    const std::uint32_t a = topo.edges[x.edge][0], b = topo.edges[x.edge][1];
    const auto& f = topo.tris[x.face];
    // Unit vectors from x to its neighbours on the contour.
    Vec3 r_prev{0, 0, 0}, r_next{0, 0, 0};
    if (i > 0 || c.closed)
      r_prev = unit(sub(set.items[c.crossings[(i + n - 1) % n]].point, x.point));
    if (i + 1 < n || c.closed)
      r_next = unit(sub(set.items[c.crossings[(i + 1) % n]].point, x.point));
    const Vec3 in_plane = scale(add(r_prev, r_next), ctx.options.lambda);
    const double local =
        0.5 * (norm(sub(topo.points[a], topo.points[b])) + ctx.measures.mean_edge[q_mesh]);
    const double len = ctx.options.step * local;

    Vec3 d{0, 0, 0};
    bool face_side = false;  // the face's mesh holds the labels: it moves along +d
    const std::uint32_t p_component = topo.vertex_component[a];
    const std::uint32_t q_component = topo.tri_component(x.face);
    const int la = label(topo, analysis, a, q_component);
    const int lb = label(topo, analysis, b, q_component);
    int f_legal = 0, f_illegal = 0;
    Vec3 f_legal_sum{0, 0, 0};
    for (std::uint32_t v : f) {
      const int l = label(topo, analysis, v, p_component);
      if (l == 0) {
        ++f_legal;
        f_legal_sum = add(f_legal_sum, topo.points[v]);
      }
      if (l == 1) ++f_illegal;
    }
    const Vec3 nf = face_normal(topo, x.face);
    const int q_orientation = ctx.measures.closed[q_component];
    if (la >= 0 && lb >= 0 && la != lb) {
      // e has a legal endpoint: n_r is f's normal turned toward it (Eq. 1).
      const std::uint32_t legal = la == 0 ? a : b;
      const int s = orient_sos(topo.points, f[0], f[1], f[2], legal);
      d = add(scale(nf, s), in_plane);
    } else if (f_legal > 0 && f_illegal > 0) {
      // The face side holds the illegal region: the normal of P near e, toward f's legal side.
      Vec3 ne{0, 0, 0};
      for (std::uint32_t k = topo.edge_face_begin[x.edge]; k < topo.edge_face_begin[x.edge + 1];
           ++k)
        ne = add(ne, face_normal(topo, topo.edge_faces[k]));
      ne = unit(ne);
      const Vec3 toward = sub(scale(f_legal_sum, 1.0 / f_legal), x.point);
      d = add(scale(ne, dot(ne, toward) >= 0 ? 1.0 : -1.0), in_plane);
      face_side = true;
    } else if (!c.self && q_orientation != 0 && ctx.options.outside_closed_obstacles &&
               ctx.measures.role[q_mesh] == Role::kObstacle) {
      // A closed obstacle: e's endpoint outside it is the legal one.
      const int s = orient_sos(topo.points, f[0], f[1], f[2], a) * q_orientation;
      const std::uint32_t legal = s > 0 ? a : b;
      d = add(scale(nf, orient_sos(topo.points, f[0], f[1], f[2], legal)), in_plane);
    } else if (!c.closed && !c.self &&
               ((end_on_boundary_of(0, q_mesh)) || end_on_boundary_of(n - 1, q_mesh))) {
      // BI rule: slide e toward the end of the contour on the other mesh's boundary.
      d = end_on_boundary_of(n - 1, q_mesh) ? r_next : r_prev;
      if (norm(d) == 0.0)
        d = end_on_boundary_of(n - 1, q_mesh) ? scale(r_prev, -1.0) : scale(r_next, -1.0);
    } else {
      // Nothing decides: the shallower endpoint of e is taken as the one that went through.
      const double da = std::abs(dot(nf, sub(topo.points[a], topo.points[f[0]])));
      const double db = std::abs(dot(nf, sub(topo.points[b], topo.points[f[0]])));
      const std::uint32_t legal = da < db ? b : a;
      d = add(scale(nf, orient_sos(topo.points, f[0], f[1], f[2], legal)), in_plane);
    }
    d = scale(unit(d), len);
    // Action and reaction, split by mass: obstacles and pinned vertices take nothing.
    bool e_free = ctx.measures.free[a] || ctx.measures.free[b];
    bool f_free = ctx.measures.free[f[0]] || ctx.measures.free[f[1]] || ctx.measures.free[f[2]];
    double we = e_free ? (f_free ? 0.5 : 1.0) : 0.0;
    double wf = f_free ? (e_free ? 0.5 : 1.0) : 0.0;
    const Vec3 de = scale(d, face_side ? -we : we);
    const Vec3 df = scale(d, face_side ? wf : -wf);
    for (std::uint32_t v : {a, b})
      if (ctx.measures.free[v]) moves.push_drn(v, de);
    for (std::uint32_t v : f)
      if (ctx.measures.free[v]) moves.push_drn(v, df);
  }
}

// The mean of its DRN moves, capped.
Vec3 drn_step(const RepairContext& ctx, const Moves& moves, std::uint32_t v) {
  const Vec3 d = scale(moves.drn[v], 1.0 / moves.drn_count[v]);
  const double len = norm(d), cap = ctx.options.max_step * ctx.measures.vertex_edge[v];
  return len > cap ? scale(d, cap / len) : d;
}

// Measured and made when it removes crossings: a pinch between two triangles next to
// a moved flap is undone, a shear that would tangle a fold further is not made. When the step
// removes nothing, the contour's neighbourhood relaxed (relax_choice) is made if it does.
void measured_drn_move(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                       const TracedContour& t, const RegionAnalysis& analysis,
                       std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
  const SceneTopology& topo = ctx.topo;
  Moves& scratch = tools.scratch.drn;
  drn_moves(ctx, set, t, analysis, scratch);
  std::vector<std::uint32_t> touched;
  for (std::uint32_t ci : t.contour.crossings) {
    const RawCrossing& x = set.items[ci];
    for (std::uint32_t v : topo.edges[x.edge]) touched.push_back(v);
    for (std::uint32_t v : topo.tris[x.face]) touched.push_back(v);
  }
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  Choice step;
  for (std::uint32_t v : touched) {
    if (scratch.drn_count[v] == 0 || !ctx.measures.free[v] || tools.measured.taken(v) ||
        moves.has_region[v])
      continue;
    step.propose(v, topo.points[v], add(topo.points[v], drn_step(ctx, scratch, v)), ctx.round);
  }
  for (std::uint32_t v : touched) {
    scratch.drn[v] = Vec3{0, 0, 0};
    scratch.drn_count[v] = 0;
  }
  // The step; when it removes nothing, the neighbourhood relaxed.
  Choice chosen;
  if (!step.part.empty() && 3 * step.part.size() <= tools.measured.trial_budget) {
    tools.measured.trial_budget -= 3 * step.part.size();
    step.gain = tools.measured.gain(ctx.detect, set, step.part, step.at);
    chosen = std::move(step);
  }
  if (chosen.gain <= 0) chosen = relax_choice(ctx, tools, set, touched, moves);
  if (chosen.gain > 0) tools.measured.make(chosen, in_moving_set, moves);
}

}  // namespace untangle
