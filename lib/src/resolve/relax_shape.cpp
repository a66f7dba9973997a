// Shape relaxation after a clean repair (relax_shape.h). The repair moves each illegal vertex to
// just beyond the other surface and leaves its neighbours where they were: a push of a fraction of
// an edge is a step in the cloth, a push of a few edges a shard. Each sweep solves for the shape
// nearest the input's (as-rigid-as-possible, shape_solve.h) with what holds fixed and the body as
// contact planes, and moves halfway to it; what the exact tests refuse takes a shorter step or
// holds, and the rest is solved again around it, so that what moves always fits what holds.
// Measured on the six MakeHuman garments on their bodies (largest edge-length ratio, flipped
// faces, p95 edge-length change): male_casualsuit01 1.41 / 0 / 0.009, female_casualsuit01
// 1.34 / 0 / 0.045, female_sportsuit01 1.30 / 0 / 0.043, female_elegantsuit01 1.21 / 0 / 0.023,
// male_casualsuit02 1.07, male_casualsuit04 1.08; relaxing takes 0.4 to 3 s. With vertices held for good after three refused
// sweeps, slides that stopped at the clearance and one contact plane offset for all, they were
// 1.70 / 2, 1.52 / 0, 1.37, 1.25, 1.10 and 1.11 (two of six beyond the bounds); averaging the
// neighbours' displacements (the sweep before the solve) gave 2.22 / 1 and 1.67 / 1.
#include "resolve/relax_shape.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>

#include "detect/pair_list.h"
#include "geometry/vec3.h"
#include "resolve/shape_solve.h"
#include "resolve/surface_queries.h"

namespace untangle {
namespace {

constexpr int kRelaxRings = 6;      // rings around the moved vertices that relax with them
constexpr double kStill = 3e-3;  // a vertex whose proposal is shorter (in mean edges) has settled
constexpr int kHoldPasses = 8;      // detection passes per sweep before the whole sweep is undone
constexpr int kArapIterations = 10;  // local–global iterations of the first solve
// Local–global iterations of every later solve, started from the last solve's targets: what holds
// and the contacts change little between passes and sweeps. On the six MakeHuman garments 3 in
// place of 10 took their relaxations from 8.1 to 5.7 s (one thread), largest edge ratios within
// 0.03 of ten's; with the scalar solve (shape_solve.cpp) 2.5 s (DESIGN §5).
constexpr int kWarmIterations = 3;
constexpr double kFraction = 0.5;   // of the way to the solved shape per sweep
constexpr double kShrinkLeast = 0.2;  // a step refused until shorter than this fraction holds
// The relaxation stops when a sweep leaves more than (1 - kPlateau) of the strain two sweeps
// before it: on the MakeHuman garments the largest edge ratio is reached within 4 to 8 sweeps,
// and the sweeps after that (up to 40) moved a few retried vertices for seconds.
constexpr double kPlateau = 0.01;
// The reach of the relaxation's list of candidate pairs, in the part's shortest mean edge.
constexpr double kListReach = 0.25;
// The contact plane of a vertex whose step an obstacle refused lies this many clearances out from
// then on. Per-vertex planes keep vertices out, not the edges between them: over a forearm or a
// neck a cuff's or a collar's edge dips below its ends' planes by more than the clearance, and its
// ends were refused sweep after sweep, their neighbours pulled in around them (female_casualsuit01's
// cuff edges at 0.66 of their length, stretch 1.52, now 1.36; twice is enough: 3 or 4 times gave
// the same largest ratio and a larger p95).
constexpr double kRefusedMargin = 2.0;
// No sweep starts after the relaxation's solves have factored this many unknowns in
// all (counted, not timed, so the result does not depend on the machine): the six MakeHuman
// garments on their bodies use 0.2 to 0.8 million, but two garments worn together that end
// distorted relaxed 9,335 moved vertices over 31,668 unknowns for 228 s.
constexpr std::size_t kFactoredBudget = 2'000'000;

// The free vertices the repair moved and kRelaxRings rings of free vertices around them,
// ascending.
std::vector<std::uint32_t> relaxing_vertices(const SceneTopology& topo,
                                             const SceneMeasures& measures,
                                             const std::vector<Vec3>& moved_from) {
  std::vector<std::uint8_t> in(topo.points.size(), 0);
  std::vector<std::uint32_t> front;
  for (std::uint32_t v = 0; v < topo.points.size(); ++v)
    if (measures.free[v] && topo.points[v] != moved_from[v]) {
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

// The sum over the edges of `part`'s vertices (each edge once per end in part) of the squared
// relative change of its length against `input`.
double strain(const SceneTopology& topo, const std::vector<Vec3>& input,
              const std::vector<std::uint32_t>& part) {
  double sum = 0.0;
  for (std::uint32_t v : part)
    for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
      const std::uint32_t w = topo.vertex_neighbors[j];
      const double rest = norm(sub(input[v], input[w]));
      if (!(rest > 0.0)) continue;
      const double change = norm(sub(topo.points[v], topo.points[w])) / rest - 1.0;
      sum += change * change;
    }
  return sum;
}

}  // namespace

RelaxShapeResult relax_shape(const RelaxShapeInputs& in, SceneTopology& topo,
                             SceneHierarchy& hierarchy, std::vector<std::uint32_t>& inside,
                             std::vector<std::uint8_t>& moved) {
  RelaxShapeResult result;
  const SceneMeasures& measures = in.measures;
  const std::vector<std::uint32_t> part =
      relaxing_vertices(topo, measures, in.moved_from ? *in.moved_from : in.input);
  if (part.empty()) return result;

  // Distances to the obstacles' surfaces (their buried faces left out: a point near one is inside)
  // keep the clearance. lower[i] is a lower bound of part[i]'s distance: the distance last measured
  // less the way moved since, so that only a vertex that may have come near is measured again.
  std::vector<std::uint32_t> obstacle_tris;
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
    if (measures.role[topo.tri_mesh[t]] == Role::kObstacle && !measures.buried[t])
      obstacle_tris.push_back(t);
  std::unique_ptr<MeshTree> own;
  const MeshTree* obstacles = nullptr;
  if (!obstacle_tris.empty() && in.trees != nullptr) {
    obstacles = &in.trees->obstacle_tree(obstacle_tris);
  } else if (!obstacle_tris.empty()) {
    own = build_tree(topo, obstacle_tris);
    obstacles = own.get();
  }
  // One closest-point query answers both questions about a position (closest_on gives the point
  // and its squared distance), and a sweep asks about the same positions again and again: a
  // vertex's start in every pass, the same target in every pass that kept its goal and its step, a
  // slide's distance and then its closest point. The answers of part[i]'s last kKnown positions
  // are kept, keyed by the position's bits.
  constexpr int kKnown = 4;
  struct Known {
    Vec3 at, closest;
    double squared = 0.0;  // from `at` to `closest`
  };
  std::vector<std::array<Known, kKnown>> known(obstacles ? part.size() : 0);
  std::vector<std::uint8_t> known_count(known.size(), 0), known_next(known.size(), 0);
  auto known_of = [&](std::size_t i, const Vec3& p) -> const Known& {
    std::array<Known, kKnown>& slots = known[i];
    for (int k = 0; k < known_count[i]; ++k)
      if (std::memcmp(slots[k].at.data(), p.data(), sizeof(Vec3)) == 0) return slots[k];
    const Closest c = closest_on(*obstacles, p);
    Known& slot = slots[known_next[i]];
    slot.at = p;
    slot.closest = c.point;
    slot.squared = c.squared;
    known_next[i] = static_cast<std::uint8_t>((known_next[i] + 1) % kKnown);
    if (known_count[i] < kKnown) ++known_count[i];
    return slot;
  };
  auto closest = [&](std::size_t i, const Vec3& p) { return known_of(i, p).closest; };
  auto distance = [&](std::size_t i, const Vec3& p) { return std::sqrt(known_of(i, p).squared); };
  std::vector<double> lower(part.size(), INFINITY);
  if (obstacles)
    for (std::size_t i = 0; i < part.size(); ++i) lower[i] = distance(i, topo.points[part[i]]);

  // The candidate pairs of the triangles the part moves, kept while their corners stay within a
  // quarter of the part's shortest mean edge of their references (pair_list.h): the passes and
  // sweeps test those pairs instead of descending the hierarchies again. Only the speed depends
  // on the reach.
  std::vector<std::uint32_t> part_triangles;
  double reach = 0.0;
  {
    std::vector<std::uint8_t> in_part(topo.points.size(), 0);
    double shortest = INFINITY;
    for (const std::uint32_t v : part) {
      in_part[v] = 1;
      shortest = std::min(shortest, measures.mean_edge[topo.vertex_mesh[v]]);
    }
    for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
      const auto& tri = topo.tris[t];
      if (in_part[tri[0]] || in_part[tri[1]] || in_part[tri[2]]) part_triangles.push_back(t);
    }
    part_triangles.shrink_to_fit();
    if (!(shortest > 0.0) || !std::isfinite(shortest)) shortest = 0.0;
    reach = kListReach * shortest;
  }
  PairList pairs(std::move(part_triangles), reach);

  ShapeSolve solve(topo, in.input, part, in.threads);
  std::vector<double> strains;  // after each accepted sweep
  bool failed = false;          // the last sweep could not be made clean
  std::vector<Vec3> from(part.size()), to(part.size()), goals;
  // sit_out: refused in a sweep that could not be made clean; held through the next one.
  std::vector<std::uint8_t> sit_out(part.size(), 0), relaxed(part.size(), 0);
  std::vector<std::uint8_t> blocked(part.size(), 0), trying(part.size(), 0);
  std::vector<ShapeSolve::Contact> contacts(part.size());
  std::vector<double> shrink(part.size(), 1.0);
  std::vector<double> margin(part.size(), 1.0);  // contact plane offset, in clearances
  // away: a part vertex away from where the sweep started (trying); stepped: moved since the
  // pass before.
  std::vector<std::uint8_t> away(topo.points.size(), 0), stepped(topo.points.size(), 0);
  std::vector<std::uint8_t> refit(topo.points.size(), 0);
  std::vector<std::uint8_t> near(topo.points.size(), 0);
  std::vector<Vec3> start;  // the positions at the sweep's start (topo.points: the last pass's)
  for (int sweep = 0; sweep < in.max_sweeps && solve.factored_unknowns() <= kFactoredBudget;
       ++sweep) {
    start = topo.points;
    // Contact planes of the vertices near an obstacle: the tangent plane at the closest point,
    // moved out by the clearance.
    for (std::size_t i = 0; i < part.size(); ++i) {
      const std::uint32_t v = part[i];
      from[i] = topo.points[v];
      blocked[i] = sit_out[i];
      contacts[i].active = false;
      if (!obstacles) continue;
      const double clearance = in.clearance[topo.vertex_mesh[v]];
      if (lower[i] > clearance + 2.0 * measures.vertex_edge[v]) continue;
      const Vec3 q = closest(i, from[i]);
      const double d = norm(sub(from[i], q));
      lower[i] = d;
      if (!(d > 0.0)) continue;
      contacts[i].active = true;
      contacts[i].normal = scale(sub(from[i], q), 1.0 / d);
      contacts[i].point = add(q, scale(contacts[i].normal, margin[i] * clearance));
    }
    // Passes: solve with what is blocked, move, block what the exact tests refuse, and solve
    // again from the sweep's start, so that what moves always fits around what holds.
    bool clean = false, any = false, settled = false;
    // The crossings of the last pass's positions among the triangles that moved in this sweep:
    // each pass is detected from the one before, so that a pass that only shortened some steps
    // (the goals kept) tests only those vertices' triangles again. Each sweep starts empty.
    CrossingSet carried;
    std::fill(near.begin(), near.end(), 0);
    std::fill(shrink.begin(), shrink.end(), 1.0);
    std::vector<std::uint8_t> solved_with;
    for (int pass = 0; pass < kHoldPasses && !clean; ++pass) {
      if (solved_with != blocked) {  // a pass that only shortened steps keeps the goals
        if (goals.empty())
          solve.targets(start, blocked, contacts, kArapIterations, goals);
        else
          solve.targets(start, blocked, contacts, kWarmIterations, goals, &goals);
        solved_with = blocked;
      }
      double largest = 0.0;
      std::fill(trying.begin(), trying.end(), 0);
      any = false;
      for (std::size_t i = 0; i < part.size(); ++i) {
        if (blocked[i]) continue;
        const std::uint32_t v = part[i];
        Vec3 target = add(from[i], scale(sub(goals[i], from[i]), kFraction * shrink[i]));
        if (in.round) target = in.round(target);
        const double step = norm(sub(target, from[i]));
        largest = std::max(largest, step / measures.mean_edge[topo.vertex_mesh[v]]);
        if (target == from[i] || step / measures.mean_edge[topo.vertex_mesh[v]] < kStill) continue;
        // Clearance: slide along the obstacle, or hold.
        const double clearance = in.clearance[topo.vertex_mesh[v]];
        if (obstacles && lower[i] - step < clearance) {
          // lower[i] may be a bound from an earlier sweep: the slide below needs the distance.
          lower[i] = distance(i, from[i]);
          double next = distance(i, target);
          if (next < clearance && next < lower[i] && lower[i] > 0.0) {
            const Vec3 n = scale(sub(from[i], closest(i, from[i])), 1.0 / lower[i]);
            Vec3 d = sub(target, from[i]);
            const double toward = dot(d, n);
            if (toward < 0.0) d = sub(d, scale(n, toward));
            Vec3 slid = add(from[i], d);
            if (in.round) slid = in.round(slid);
            const double there = distance(i, slid);
            if (slid != from[i] && there >= std::min(clearance, lower[i])) {
              target = slid;
              next = there;
            } else if (slid != from[i] && there > 0.0) {
              // Over a curved or concave stretch of the obstacle the tangent step comes nearer
              // than the clearance: the point under the slid one, lifted out by the clearance.
              // Without it the collar of male_casualsuit01 held where the repair left it, its
              // edges around the neck stretched 1.7 times.
              const Vec3 q2 = closest(i, slid);
              const Vec3 n2 = scale(sub(slid, q2), 1.0 / there);
              if (dot(n2, n) > 0.0) {
                Vec3 lifted = add(q2, scale(n2, clearance));
                if (in.round) lifted = in.round(lifted);
                const double up = distance(i, lifted);
                if (lifted != from[i] && up >= std::min(clearance, lower[i])) {
                  target = lifted;
                  next = up;
                }
              }
            }
          }
          if (next < clearance && next < lower[i]) {
            blocked[i] = 1;
            ++result.held;
            continue;
          }
          if (norm(sub(target, from[i])) >= lower[i]) near[v] = 1;
        }
        to[i] = target;
        trying[i] = 1;
        any = true;
      }
      if (pass == 0 && (!any || largest < kStill)) {
        settled = true;
        break;
      }
      if (!any) break;
      for (std::size_t i = 0; i < part.size(); ++i) {
        const std::uint32_t v = part[i];
        const Vec3& p = trying[i] ? to[i] : from[i];
        stepped[v] = p != topo.points[v];
        if (stepped[v]) refit[v] = 1;
        topo.points[v] = p;
        away[v] = trying[i];
      }
      hierarchy.update(topo, refit);
      std::fill(refit.begin(), refit.end(), 0);
      if (pairs.reach() > 0.0) {
        pairs.prepare(topo, in.detect, hierarchy);
        carried = update_crossings(topo, in.detect, pairs, carried, stepped);
      } else {
        carried = update_crossings(topo, in.detect, hierarchy, carried, stepped);
      }
      find_inside_vertices(topo, measures.role, in.winding, near, in.threads, inside);
      // What a detection from the sweep's start over the trying vertices reports: the crossings
      // whose face, or the triangle that owns the edge (its lowest), has a corner away from the
      // start. A crossing the start already had among triangles that did not move is not this
      // sweep's (an unresolved state's remaining ones), even when a pass before moved them.
      auto away_triangle = [&](std::uint32_t t) {
        for (std::uint32_t v : topo.tris[t])
          if (away[v]) return true;
        return false;
      };
      auto moved_corner = [&](const RawCrossing& x) {
        return away_triangle(topo.edge_faces[topo.edge_face_begin[x.edge]]) ||
               away_triangle(x.face);
      };
      std::vector<std::uint8_t> bad(topo.points.size(), 0), against(topo.points.size(), 0);
      for (const RawCrossing& x : carried.items) {
        if (!moved_corner(x)) continue;
        for (std::uint32_t v : topo.edges[x.edge]) bad[v] = 1;
        for (std::uint32_t v : topo.tris[x.face]) bad[v] = 1;
        if (measures.role[topo.edge_mesh(x.edge)] == Role::kObstacle ||
            measures.role[topo.tri_mesh[x.face]] == Role::kObstacle) {
          for (std::uint32_t v : topo.edges[x.edge]) against[v] = 1;
          for (std::uint32_t v : topo.tris[x.face]) against[v] = 1;
        }
      }
      clean = true;
      for (std::size_t i = 0; i < part.size(); ++i) {
        const std::uint32_t v = part[i];
        if (!trying[i] || !(bad[v] || inside[v] != kNone)) continue;
        shrink[i] *= 0.5;
        if (shrink[i] < kShrinkLeast) blocked[i] = 1;
        if (against[v]) margin[i] = kRefusedMargin;
        ++result.held;
        clean = false;
      }
    }
    std::fill(away.begin(), away.end(), 0);
    if (!clean) {
      // Back to the sweep's start.
      for (std::size_t i = 0; i < part.size(); ++i)
        if (topo.points[part[i]] != from[i]) {
          topo.points[part[i]] = from[i];
          refit[part[i]] = 1;
        }
      hierarchy.update(topo, refit);
      std::fill(refit.begin(), refit.end(), 0);
      find_inside_vertices(topo, measures.role, in.winding, near, in.threads, inside);
      // Nothing left to move, or a second sweep in a row that could not be made clean: stop.
      // After a first, what the exact tests refused sits the next sweep out, and the rest of
      // the part moves around it (a vertex held for good after three refusals, as before, kept
      // female_casualsuit01's cuffs and male_casualsuit01's collar where the repair left them).
      if (settled || failed) break;
      failed = true;
      for (std::size_t i = 0; i < part.size(); ++i) sit_out[i] = shrink[i] < 1.0 || blocked[i];
      continue;
    }
    failed = false;
    std::fill(sit_out.begin(), sit_out.end(), 0);
    ++result.sweeps;
    std::size_t accepted = 0;
    for (std::size_t i = 0; i < part.size(); ++i) {
      if (!trying[i]) continue;
      ++accepted;
      moved[part[i]] = 1;
      relaxed[i] = 1;
      if (obstacles) lower[i] -= norm(sub(to[i], from[i]));
    }
    if (accepted == 0) break;
    // The strain (the sum over the part's edges of the squared relative length change) has
    // stopped falling: what sweeps after this one would move is a few retried vertices.
    strains.push_back(strain(topo, in.input, part));
    const std::size_t n = strains.size();
    if (n > 2 && strains[n - 1] > (1.0 - kPlateau) * strains[n - 3]) break;
  }
  for (std::size_t i = 0; i < part.size(); ++i) result.relaxed += relaxed[i];
  return result;
}

}  // namespace untangle
