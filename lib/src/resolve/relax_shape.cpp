// Shape relaxation after a clean repair (relax_shape.h). The repair moves each illegal vertex to
// just beyond the other surface and leaves its neighbours where they were: a push of a fraction of
// an edge is a step in the cloth, a push of a few edges a shard. Smoothing the displacement field
// over the moved vertices and the rings around them turns the step into a bump: a vertex that can
// not go back (its way back would cross) holds, its neighbours follow it out.
#include "resolve/relax_shape.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "geometry/vec3.h"
#include "resolve/surface_queries.h"

namespace untangle {
namespace {

constexpr int kRelaxRings = 6;      // rings around the moved vertices that relax with them
constexpr int kMaxSweeps = 40;      // sweeps at most
constexpr double kStill = 3e-3;  // a vertex whose proposal is shorter (in mean edges) has settled
constexpr int kHoldPasses = 8;      // detection passes per sweep before the whole sweep is undone
constexpr int kRefusals = 3;  // sweeps in a row an exact test holds a vertex before it stays put

// The free vertices the repair moved and kRelaxRings rings of free vertices around them,
// ascending.
std::vector<std::uint32_t> relaxing_vertices(const SceneTopology& topo,
                                             const SceneMeasures& measures,
                                             const std::vector<Vec3>& input) {
  std::vector<std::uint8_t> in(topo.points.size(), 0);
  std::vector<std::uint32_t> front;
  for (std::uint32_t v = 0; v < topo.points.size(); ++v)
    if (measures.free[v] && topo.points[v] != input[v]) {
      in[v] = 1;
      front.push_back(v);
    }
  for (int ring = 0; ring < kRelaxRings && !front.empty(); ++ring) {
    std::vector<std::uint32_t> next;
    for (std::uint32_t v : front)
      for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
        const std::uint32_t w = topo.vertex_neighbors[j];
        if (in[w] || !measures.free[w]) continue;
        in[w] = 1;
        next.push_back(w);
      }
    front = std::move(next);
  }
  std::vector<std::uint32_t> out;
  for (std::uint32_t v = 0; v < topo.points.size(); ++v)
    if (in[v]) out.push_back(v);
  return out;
}

}  // namespace

RelaxShapeResult relax_shape(const RelaxShapeInputs& in, SceneTopology& topo,
                             SceneHierarchy& hierarchy, std::vector<std::uint32_t>& inside,
                             std::vector<std::uint8_t>& moved) {
  RelaxShapeResult result;
  const SceneMeasures& measures = in.measures;
  const std::vector<std::uint32_t> part = relaxing_vertices(topo, measures, in.input);
  if (part.empty()) return result;

  // Distances to the obstacles' surfaces (their buried faces left out: a point near one is inside)
  // keep the clearance. lower[i] is a lower bound of part[i]'s distance: the distance last measured
  // less the way moved since, so that only a vertex that may have come near is measured again.
  std::vector<std::uint32_t> obstacle_tris;
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
    if (measures.role[topo.tri_mesh[t]] == Role::kObstacle && !measures.buried[t])
      obstacle_tris.push_back(t);
  const std::unique_ptr<MeshTree> obstacles =
      obstacle_tris.empty() ? nullptr : build_tree(topo, obstacle_tris);
  auto distance = [&](const Vec3& p) {
    return std::sqrt(obstacles->tree.squared_distance(TreeKernel::Point_3(p[0], p[1], p[2])));
  };
  std::vector<double> lower(part.size(), INFINITY);
  if (obstacles)
    for (std::size_t i = 0; i < part.size(); ++i) lower[i] = distance(topo.points[part[i]]);

  std::vector<std::uint8_t> changed(topo.points.size(), 0);
  std::vector<Vec3> from(part.size()), to(part.size());
  std::vector<std::uint8_t> hold(part.size(), 0);
  std::vector<std::uint8_t> refused(part.size(), 0);  // sweeps in a row an exact test held it
  std::vector<std::uint8_t> relaxed(part.size(), 0);  // moved by an accepted sweep
  std::vector<std::uint8_t> near(topo.points.size(), 0);  // may have passed through an obstacle
  const CrossingSet none;
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    // Proposals, all from the positions at the sweep's start: each displacement halfway to the
    // mean of its neighbours' (a neighbour that does not relax keeps its own).
    double largest = 0.0;  // in mean edges
    std::vector<std::size_t> movers;  // indices into part
    for (std::size_t i = 0; i < part.size(); ++i) {
      const std::uint32_t v = part[i];
      // Two targets, averaged: the displacement smoothed (the mean of the neighbours'
      // displacements, keeping the input's shape where they agree) and the input's edge lengths
      // (each neighbour's point at the input distance toward v, which undoes a stretch the
      // smoothing leaves at a held vertex).
      Vec3 shifts{0.0, 0.0, 0.0}, lengths{0.0, 0.0, 0.0};
      std::uint32_t count = 0;
      from[i] = topo.points[v];
      for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
        const std::uint32_t w = topo.vertex_neighbors[j];
        shifts = add(shifts, sub(topo.points[w], in.input[w]));
        const Vec3 along = sub(from[i], topo.points[w]);
        const double now = norm(along);
        const double rest = norm(sub(in.input[v], in.input[w]));
        lengths = add(lengths, now > 0.0 ? add(topo.points[w], scale(along, rest / now))
                                         : from[i]);
        ++count;
      }
      if (count == 0) continue;
      const Vec3 smooth = add(in.input[v], scale(shifts, 1.0 / count));
      const Vec3 goal = scale(add(smooth, scale(lengths, 1.0 / count)), 0.5);
      Vec3 target = scale(add(from[i], goal), 0.5);
      if (in.round) target = in.round(target);
      const double step = norm(sub(target, from[i])) / measures.mean_edge[topo.vertex_mesh[v]];
      largest = std::max(largest, step);
      if (target == from[i] || step < kStill) continue;  // settled: not tested again
      if (refused[i] >= kRefusals) continue;  // its way is blocked: not proposed again
      to[i] = target;
      movers.push_back(i);
    }
    if (movers.empty() || largest < kStill) break;
    ++result.sweeps;

    // Clearance first: a vertex that would come nearer than its clearance to an obstacle, and
    // nearer than it is, slides instead: the part of its step toward the obstacle (along the
    // direction from its closest point) is dropped, the part along the surface kept, so that a
    // vertex pressed against the body can still spread the strain sideways (on the MakeHuman
    // garments the largest edge-length ratio fell from 1.24 to 1.15, and from 1.75 to 1.65 at the
    // female cuffs). If the slid step still comes nearer than the clearance, the vertex holds.
    // (Lifting a proposal back out to the clearance, away from its closest point, made vertices
    // slide together where the body has a crease: on the MakeHuman shoulders edges shrank to 0.39
    // of their length instead of 0.57.) A vertex whose step is shorter than its distance to the
    // obstacles cannot pass through one, so it stays outside: only the others are tested for
    // inside.
    std::vector<std::size_t> trying;
    std::fill(near.begin(), near.end(), 0);
    for (std::size_t i : movers) {
      const std::uint32_t v = part[i];
      const double step = norm(sub(to[i], from[i]));
      const double clearance = in.clearance[topo.vertex_mesh[v]];
      if (obstacles && lower[i] - step < clearance) {
        lower[i] = distance(from[i]);
        double next = distance(to[i]);
        if (next < clearance && next < lower[i] && lower[i] > 0.0) {
          const auto c = obstacles->tree.closest_point(
              TreeKernel::Point_3(from[i][0], from[i][1], from[i][2]));
          const Vec3 n = scale(sub(from[i], Vec3{c.x(), c.y(), c.z()}), 1.0 / lower[i]);
          Vec3 d = sub(to[i], from[i]);
          const double toward = dot(d, n);
          if (toward < 0.0) d = sub(d, scale(n, toward));
          Vec3 slid = add(from[i], d);
          if (in.round) slid = in.round(slid);
          const double there = distance(slid);
          if (slid != from[i] && there >= std::min(clearance, lower[i])) {
            to[i] = slid;
            next = there;
          }
        }
        if (next < clearance && next < lower[i]) {
          ++result.held;
          continue;
        }
        if (step >= lower[i]) near[v] = 1;
      }
      trying.push_back(i);
    }

    // Apply, then hold what the exact tests refuse, until what is left is clean.
    for (std::size_t i : trying) {
      topo.points[part[i]] = to[i];
      changed[part[i]] = 1;
      hold[i] = 0;
    }
    std::vector<std::uint8_t> refit = changed;  // what moved since the hierarchy's last refit
    bool clean = false;
    for (int pass = 0; pass < kHoldPasses && !clean; ++pass) {
      hierarchy.update(topo, refit);
      std::fill(refit.begin(), refit.end(), 0);
      const CrossingSet found = update_crossings(topo, in.detect, hierarchy, none, changed);
      find_inside_vertices(topo, measures.role, in.winding, near, in.threads, inside);
      std::vector<std::uint8_t> bad(topo.points.size(), 0);
      for (const RawCrossing& x : found.items) {
        for (std::uint32_t v : topo.edges[x.edge]) bad[v] = 1;
        for (std::uint32_t v : topo.tris[x.face]) bad[v] = 1;
      }
      clean = true;
      for (std::size_t i : trying) {
        const std::uint32_t v = part[i];
        if (hold[i] || !(bad[v] || inside[v] != kNone)) continue;
        hold[i] = 1;
        topo.points[v] = from[i];
        refit[v] = 1;
        ++result.held;
        clean = false;
      }
      // A crossing between vertices of which none moved this sweep cannot be: every vertex of a
      // crossing found here either moved (and now holds) or did not; if all its moved vertices
      // hold and it remains, the next pass finds it again and the loop ends undoing the sweep.
    }
    if (!clean) {
      // Still not clean after kHoldPasses: undo the whole sweep and stop.
      for (std::size_t i : trying) {
        topo.points[part[i]] = from[i];
        refit[part[i]] = 1;
      }
      hierarchy.update(topo, refit);
      find_inside_vertices(topo, measures.role, in.winding, near, in.threads, inside);
      for (std::size_t i : trying) changed[part[i]] = 0;
      break;
    }
    std::size_t accepted = 0;
    for (std::size_t i : trying) {
      changed[part[i]] = 0;
      if (hold[i]) {
        ++refused[i];
        continue;
      }
      ++accepted;
      refused[i] = 0;
      moved[part[i]] = 1;
      relaxed[i] = 1;
      if (obstacles) lower[i] -= norm(sub(to[i], from[i]));
    }
    if (accepted == 0) break;
  }
  for (std::size_t i = 0; i < part.size(); ++i) result.relaxed += relaxed[i];
  return result;
}

}  // namespace untangle
