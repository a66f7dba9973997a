// The continuation (continuation.h): the plan from the depths of the inside vertices, then the
// repairs along the way back to the obstacles' true shape.
#include "resolve/continuation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "geometry/point_grid.h"
#include "geometry/vec3.h"
#include "resolve/inside_vertices.h"
#include "resolve/repair_loop.h"
#include "resolve/scene_measures.h"
#include "resolve/surface_queries.h"
#include "topology/scene_topology.h"
#include "untangle/intersections.h"

namespace untangle {
namespace {

// A movable vertex ends the first step this many of its mesh's mean edges outside the shrunk
// obstacle (before the repair's clearance).
constexpr double kMargin = 0.5;
// The shrink asked by a vertex at depth d (plus the margin) holds within twice that of its
// closest point and tapers to nothing at kReach times it (plus two of the obstacle's edges), so
// that the shrunk surface stays smooth under the garment.
constexpr double kReach = 4.0;
// At most this fraction of the obstacle's thickness behind a vertex (along its inward normal).
constexpr double kThickness = 0.4;
// Each step grows the obstacles back by at most this many mean edges of the movable meshes.
constexpr double kStepEdges = 0.1;
// The clearance of every step but the last is this many times a step's growth (at least the
// run's clearance), so that a garment laid at it is still outside after the obstacles grow by one
// step: with the run's clearance (0.05 mean edges) every step pushed the whole contact region
// inside again, and the steps' repairs had thousands of crossings to undo.
constexpr double kStepClearance = 1.5;
constexpr int kMinSteps = 2;
constexpr double kFinestStep = 1.0 / 8.0;  // of a planned step: the smallest growth retried
constexpr int kMaxRuns = 32;              // repairs in one continuation at most
constexpr int kIterationShare = 2;  // iterations of all steps but the last: this many times the cap
constexpr int kStepIterationShare = 4;  // a step but the last: the cap over this
constexpr int kMaxSteps = 16;
// A step ends unresolved, then its half, quarter and eighth: the growth cannot be made smaller,
// and what follows, from a state the repair could not clean, stalled in every case measured
// (the sheet over the cow's rump: 31 repairs, none clean, 250 s against the direct run's 0.5 s;
// male_casualsuit01 on its body x 1.05: 21, none clean). Where a continuation ended clean, at
// most one repair in a row had ended unresolved (the six MakeHuman garments on their bodies x 1.02
// and x 1.05).
constexpr int kGiveUpAfter = 4;
// The scaled plan's factors: 1 - k/64 for k = 1 to kScaleLadder, then halved steps around the
// best down to kScaleFinest (powers of two: the factors are exact).
constexpr double kScaleStep = 1.0 / 64.0;
constexpr int kScaleLadder = 10;
constexpr double kScaleFinest = 1.0 / 512.0;

// The mean edge length of each of the scene's `count` meshes (0 for one without edges).
std::vector<double> mean_edges(const SceneTopology& topo, std::size_t count) {
  std::vector<double> sum(count, 0.0);
  std::vector<std::size_t> edges(count, 0);
  for (const auto& e : topo.edges) {
    const std::uint32_t m = topo.vertex_mesh[e[0]];
    sum[m] += norm(sub(topo.points[e[0]], topo.points[e[1]]));
    ++edges[m];
  }
  for (std::size_t m = 0; m < count; ++m)
    if (edges[m] > 0) sum[m] /= static_cast<double>(edges[m]);
  return sum;
}

// A movable vertex inside an obstacle: the closest point on the obstacle, and how far to shrink
// there.
struct Ask {
  Vec3 at;
  double shrink;
  double radius;
};

}  // namespace

ContinuationPlan plan_continuation(const std::vector<Mesh>& meshes, const FixOptions& options,
                                   const PinMask& pins) {
  ContinuationPlan plan;
  const SceneTopology topo = build_topology(meshes);
  const SceneMeasures measures = measure_scene(topo, meshes, pins, options.threads);
  const ObstacleWinding winding(topo, measures.role, options.threads);
  if (!winding.any()) return plan;

  std::vector<std::uint32_t> obstacle_tris;
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
    if (measures.role[topo.tri_mesh[t]] == Role::kObstacle && !measures.buried[t])
      obstacle_tris.push_back(t);
  if (obstacle_tris.empty()) return plan;
  const std::unique_ptr<MeshTree> tree = build_tree(topo, obstacle_tris);
  double obstacle_edge = 0.0;
  for (std::size_t m = 0; m < meshes.size(); ++m)
    if (measures.role[m] == Role::kObstacle) obstacle_edge = std::max(obstacle_edge, measures.mean_edge[m]);

  // The asks of the movable vertices inside a closed obstacle.
  std::vector<std::uint32_t> inside;
  find_inside_vertices(topo, measures.role, winding, {}, options.threads, inside);
  std::vector<Ask> asks;
  double movable_edge = INFINITY;
  for (std::uint32_t v = 0; v < topo.points.size(); ++v) {
    if (inside[v] == kNone || !measures.free[v]) continue;
    const Vec3& p = topo.points[v];
    const Vec3 q = closest_on(*tree, p).point;
    const double depth = norm(sub(p, q));
    const double edge = measures.mean_edge[topo.vertex_mesh[v]];
    movable_edge = std::min(movable_edge, edge);
    plan.deepest = std::max(plan.deepest, depth);
    const double shrink = depth + kMargin * edge;
    asks.push_back({q, shrink, kReach * shrink + 2.0 * obstacle_edge});
  }
  if (asks.empty()) return plan;

  // The obstacles' welded vertices with an outward normal: each closed component's faces turned
  // by their orientation, its sign from the volume they enclose (about the component's first
  // corner: volume6).
  std::vector<double> outward(topo.component_mesh.size(), 0.0);
  std::vector<Vec3> about(topo.component_mesh.size());
  std::vector<std::uint8_t> seen(topo.component_mesh.size(), 0);
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
    if (measures.role[topo.tri_mesh[t]] != Role::kObstacle) continue;
    const auto& f = topo.tris[t];
    const std::uint32_t k = topo.tri_component(t);
    if (!seen[k]) about[k] = topo.points[f[0]];
    seen[k] = 1;
    const double volume =
        volume6(about[k], topo.points[f[0]], topo.points[f[1]], topo.points[f[2]]);
    outward[k] += measures.orientation[t] < 0 ? -volume : volume;
  }
  // Obstacle vertices binned in a grid of the largest ask's radius.
  double cell = 0.0;
  for (const Ask& a : asks) cell = std::max(cell, a.radius);
  if (!(cell > 0.0) || !std::isfinite(cell)) return plan;  // degenerate meshes: no plan
  PointGrid grid(cell);
  for (std::uint32_t v = 0; v < topo.points.size(); ++v)
    if (measures.role[topo.vertex_mesh[v]] == Role::kObstacle) grid.add(topo.points[v], v);
  std::vector<double> shrink(topo.points.size(), 0.0);
  for (const Ask& a : asks) {
    grid.for_each_near(a.at, [&](std::uint32_t v) {
      const double d = norm(sub(topo.points[v], a.at));
      if (d >= a.radius) return;
      const double hold = 2.0 * a.shrink;
      double f = 1.0;
      if (d > hold) {
        const double t = (d - hold) / (a.radius - hold);
        f = (1.0 - t * t) * (1.0 - t * t);
      }
      shrink[v] = std::max(shrink[v], a.shrink * f);
    });
  }
  plan.inward.assign(meshes.size(), {});
  std::vector<Vec3> inward(topo.points.size(), Vec3{0.0, 0.0, 0.0});
  for (std::uint32_t v = 0; v < topo.points.size(); ++v) {
    if (!(shrink[v] > 0.0)) continue;
    const double sign = outward[topo.vertex_component[v]];
    if (sign == 0.0) continue;
    const Vec3 n = scale(oriented_vertex_normal(topo, measures, v), sign > 0.0 ? 1.0 : -1.0);
    if (n == Vec3{0.0, 0.0, 0.0}) continue;
    // The thickness behind v: the first surface a ray inward meets, from just inside.
    const double eps = 1e-4 * measures.vertex_edge[v];
    const Vec3 from = sub(topo.points[v], scale(n, eps));
    double thickness = INFINITY;
    Vec3 hit;
    if (first_ray_hit(*tree, from, scale(n, -1.0), hit)) thickness = norm(sub(hit, from)) + eps;
    const double s = std::min(shrink[v], kThickness * thickness);
    if (!(s > 0.0)) continue;
    inward[v] = scale(n, -s);
    plan.largest_shrink = std::max(plan.largest_shrink, s);
    ++plan.shrunk_vertices;
  }
  for (std::uint32_t m = 0; m < meshes.size(); ++m) {
    if (measures.role[m] != Role::kObstacle) continue;
    plan.inward[m].resize(meshes[m].positions.size());
    for (std::uint32_t i = 0; i < meshes[m].positions.size(); ++i)
      plan.inward[m][i] = inward[topo.welded[m][i]];
  }
  if (plan.shrunk_vertices == 0) return plan;
  plan.movable_edge = movable_edge;
  plan.steps = continuation_steps(plan.largest_shrink, movable_edge);
  plan.give_up_after = kGiveUpAfter;
  return plan;
}

ScaledPlans plan_scaled_continuation(const std::vector<Mesh>& meshes, const FixOptions& options,
                                     const ObstacleWinding* earlier) {
  ScaledPlans plans;
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  bool any_obstacle = false, any_movable = false;
  for (const Mesh& m : meshes) {
    if (m.role != Role::kObstacle) {
      any_movable = any_movable || m.role == Role::kMovable;
      continue;
    }
    for (const Vec3& p : m.positions)
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], p[k]);
        hi[k] = std::max(hi[k], p[k]);
      }
    any_obstacle = any_obstacle || !m.positions.empty();
  }
  if (!any_obstacle || !any_movable) return plans;
  const Vec3 centre = scale(add(lo, hi), 0.5);
  const SceneTopology topo = build_topology(meshes);
  const std::vector<double> mean_edge = mean_edges(topo, meshes.size());
  double movable_edge = INFINITY;
  for (std::size_t m = 0; m < meshes.size(); ++m)
    if (meshes[m].role == Role::kMovable && mean_edge[m] > 0.0)
      movable_edge = std::min(movable_edge, mean_edge[m]);
  if (!std::isfinite(movable_edge)) return plans;
  // How deep the movable vertices lie inside the obstacles scaled by `factor`: each vertex moved
  // by the inverse scaling asked of the obstacles at their input positions (their winding numbers
  // and closest-point tree built once), its depth scaled back, in its mesh's mean edges.
  std::vector<Role> role(meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) role[m] = meshes[m].role;
  std::vector<std::uint32_t> obstacle_tris;
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t)
    if (role[topo.tri_mesh[t]] == Role::kObstacle) obstacle_tris.push_back(t);
  const ObstacleWinding winding(topo, role, options.threads, earlier);
  const std::unique_ptr<MeshTree> tree = build_tree(topo, obstacle_tris);
  const auto depth_at = [&](double factor) {
    double sum = 0.0;
    for (std::uint32_t v = 0; v < topo.points.size(); ++v) {
      const std::uint32_t m = topo.vertex_mesh[v];
      if (role[m] != Role::kMovable || !(mean_edge[m] > 0.0)) continue;
      const Vec3 q = add(centre, scale(sub(topo.points[v], centre), 1.0 / factor));
      if (winding.inside(q) == kNone) continue;
      sum += factor * norm(sub(q, closest_on(*tree, q).point)) / mean_edge[m];
    }
    return sum;
  };
  DetectOptions detect;
  detect.threads = options.threads;
  detect.skip_obstacle_pairs = true;
  detect.separation = false;
  // Crossings against the obstacles and inside vertices with the obstacles scaled by `factor`
  // (the scene copied once; each trial rewrites the obstacles' positions from `meshes`).
  std::vector<Mesh> trial = meshes;
  const auto illegal_at = [&](double factor) {
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      if (meshes[m].role != Role::kObstacle) continue;
      for (std::size_t i = 0; i < meshes[m].positions.size(); ++i)
        trial[m].positions[i] = add(centre, scale(sub(meshes[m].positions[i], centre), factor));
    }
    const Intersections found = find_intersections(trial, detect);
    std::size_t against = 0;
    for (const Crossing& c : found.crossings)
      if (trial[c.edge_mesh].role == Role::kObstacle || trial[c.face_mesh].role == Role::kObstacle)
        ++against;
    return against + found.counts.inside_vertices;
  };
  // Each factor measured once for both choices (the factors are exact dyadic numbers).
  struct Measured {
    double factor, depth;
    std::size_t illegal;
  };
  std::vector<Measured> measured;
  const auto measure = [&](double factor) {
    for (const Measured& m : measured)
      if (m.factor == factor) return m;
    measured.push_back({factor, depth_at(factor), illegal_at(factor)});
    return measured.back();
  };
  // The search of one choice: `better(a, b)` whether a is better than b; `done(best)` whether no
  // refinement can improve on it.
  const auto search = [&](auto better, auto done) {
    Measured best{0.0, INFINITY, SIZE_MAX};
    const auto consider = [&](double factor) {
      const Measured m = measure(factor);
      if (better(m, best)) best = m;
    };
    for (int k = 1; k <= kScaleLadder; ++k) consider(1.0 - kScaleStep * k);
    for (double step = 0.5 * kScaleStep; step >= kScaleFinest && !done(best); step *= 0.5) {
      const double around = best.factor;
      if (around + step < 1.0) consider(around + step);
      consider(around - step);
    }
    return best.factor;
  };
  const auto plan_at = [&](double factor) {
    ContinuationPlan plan;
    if (!(factor > 0.0)) return plan;
    plan.inward.assign(meshes.size(), {});
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      if (meshes[m].role != Role::kObstacle) continue;
      plan.inward[m].resize(meshes[m].positions.size());
      for (std::size_t i = 0; i < meshes[m].positions.size(); ++i) {
        plan.inward[m][i] = scale(sub(meshes[m].positions[i], centre), factor - 1.0);
        plan.largest_shrink = std::max(plan.largest_shrink, norm(plan.inward[m][i]));
        ++plan.shrunk_vertices;
      }
    }
    plan.factor = factor;
    plan.movable_edge = movable_edge;
    plan.steps = continuation_steps(plan.largest_shrink, movable_edge);
    plan.give_up_after = kGiveUpAfter;
    return plan;
  };
  // The count alone chose 0.842 for female_casualsuit01 on its body x 1.08, where its inside
  // vertices lie 80 mean edges deep in sum and the first step stalls; the depth chooses 0.912 (the
  // body it was made on is at 0.926) and the plan ends free of crossings. On the male garments
  // the two choices lie within 1/256 of each other.
  plans.by_depth = plan_at(search(
      [](const Measured& a, const Measured& b) {
        return a.depth < b.depth || (a.depth == b.depth && a.illegal < b.illegal);
      },
      [](const Measured& best) { return best.depth == 0.0 && best.illegal == 0; }));
  plans.by_count =
      plan_at(search([](const Measured& a, const Measured& b) { return a.illegal < b.illegal; },
                     [](const Measured& best) { return best.illegal == 0; }));
  return plans;
}

int continuation_steps(double largest_shrink, double movable_edge) {
  return std::clamp(static_cast<int>(std::ceil(largest_shrink / (kStepEdges * movable_edge))) + 1,
                    kMinSteps, kMaxSteps);
}

DisplacementStats displacement_against(const std::vector<Mesh>& from,
                                       const std::vector<Mesh>& meshes) {
  DisplacementStats stats;
  double sum = 0.0;
  const std::vector<double> mean_edge = mean_edges(build_topology(from), meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    if (meshes[m].role != Role::kMovable) continue;
    for (std::size_t i = 0; i < meshes[m].positions.size(); ++i) {
      if (meshes[m].positions[i] == from[m].positions[i]) continue;
      const double d = norm(sub(meshes[m].positions[i], from[m].positions[i]));
      ++stats.moved_vertices;
      sum += d;
      if (d > stats.max) {
        stats.max = d;
        stats.max_over_mean_edge = mean_edge[m] > 0.0 ? d / mean_edge[m] : 0.0;
      }
    }
  }
  if (stats.moved_vertices > 0) stats.mean = sum / static_cast<double>(stats.moved_vertices);
  return stats;
}

FixResult run_continuation(std::vector<Mesh>& meshes, const ContinuationPlan& plan,
                           const FixOptions& options, const PinMask& pins, const Rounding& round,
                           const FixProgress& progress, std::vector<ContinuationStep>& runs,
                           int stage, bool* gave_up) {
  const std::vector<Mesh> rest = meshes;
  FixOptions step = options;
  step.retries = 0;
  bool cancelled = false;
  const FixProgress watch = [&](const IterationRecord& record) {
    IterationRecord r = record;
    r.stage = stage;
    if (progress && !progress(r)) cancelled = true;
    return !cancelled;
  };
  FixResult result;
  std::vector<IterationRecord> history;
  double detect = 0, contours = 0, resolve = 0, regions = 0, displace = 0, relax = 0;
  // From the full shrink (share 1) down to the true shape (share 0) in steps of 1 / (steps - 1);
  // a step that ends unresolved is undone and tried again at half its growth, down to
  // kFinestStep, within kMaxRuns repairs in all (counted, not timed: the same result on every
  // machine). What the finest step leaves goes on to the next step.
  const double full = plan.steps > 1 ? 1.0 / (plan.steps - 1) : 1.0;
  double growth = full;
  double share = 1.0;
  bool first = true;
  std::vector<Mesh> accepted = meshes;
  int runs_left = kMaxRuns;
  // Iterations over all steps: a step that stalls runs its stages to the cap, and on a scene
  // that stalls at every step (a sheet through the cow, whose tail passes through its rump) 32
  // such steps took over ten minutes. Once spent, the next step is the last.
  int iterations_left = kIterationShare * options.max_iterations;
  int unresolved_in_row = 0;
  bool giving_up = false;
  while (!cancelled) {
    // A share within rounding of 0 (sums of 1 / (steps - 1)) is the last step, not one more.
    const double target = first ? 1.0 : share - growth;
    const bool final_step =
        target <= 1e-9 * full || runs_left <= 1 || iterations_left <= 0;
    const double at = final_step ? 0.0 : target;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
      if (plan.inward[m].empty()) continue;
      for (std::size_t i = 0; i < meshes[m].positions.size(); ++i)
        meshes[m].positions[i] = at == 0.0 ? rest[m].positions[i]
                                           : add(rest[m].positions[i], scale(plan.inward[m][i], at));
    }
    const double grown = first ? growth : share - at;
    step.max_iterations = final_step ? options.max_iterations
                                     : std::max(1, options.max_iterations / kStepIterationShare);
    step.stages = final_step ? options.stages : 1;
    step.clearance = final_step ? options.clearance
                                : std::max(options.clearance, kStepClearance * grown *
                                                                  plan.largest_shrink /
                                                                  plan.movable_edge);
    result = run_repair(meshes, step, pins, round, watch, &rest);
    --runs_left;
    iterations_left -= result.iterations;
    runs.push_back({at, result.before.crossings, result.before.inside_vertices,
                    result.after.crossings, result.after.inside_vertices, result.iterations,
                    result.clean});
    for (IterationRecord r : result.history) {
      r.stage = stage;
      history.push_back(r);
    }
    detect += result.detect_ms;
    contours += result.contours_ms;
    resolve += result.resolve_ms;
    regions += result.regions_ms;
    displace += result.displace_ms;
    relax += result.relax_ms;
    unresolved_in_row = result.clean ? 0 : unresolved_in_row + 1;
    if (plan.give_up_after > 0 && unresolved_in_row >= plan.give_up_after) {
      giving_up = true;
      break;
    }
    // The last step too is undone and taken in halves when it ends unresolved, while runs and
    // iterations are left: on male_casualsuit04 in the body x 1.05 (six decimals), with a version
    // of the relaxation that held contacts in place along the body, the step from 0.077 of the
    // shrink to none started at 386 crossings and stalled there; halved, it ends clean.
    const bool spent = runs_left <= 1 || iterations_left <= 0;
    if (final_step && (result.clean || spent || first || grown <= kFinestStep * full)) break;
    if (!result.clean && !first && grown > kFinestStep * full) {
      meshes = accepted;  // undo, and grow by half as much
      growth = grown * 0.5;
      continue;
    }
    accepted = meshes;
    share = at;
    first = false;
    if (result.clean) growth = std::min(full, growth * 2.0);
  }
  if (gave_up != nullptr) *gave_up = giving_up;
  if (cancelled || giving_up) {
    // Cancelled or given up between shrunk steps: the obstacles go back, and the result is not
    // clean.
    for (std::size_t m = 0; m < meshes.size(); ++m)
      if (!plan.inward[m].empty()) meshes[m].positions = rest[m].positions;
    result.clean = false;
  }
  result.history = std::move(history);
  result.detect_ms = detect;
  result.contours_ms = contours;
  result.resolve_ms = resolve;
  result.regions_ms = regions;
  result.displace_ms = displace;
  result.relax_ms = relax;
  result.quality = measure_quality(rest, meshes);
  // Displacements against the input, over the movable meshes.
  result.displacement = displacement_against(rest, meshes);
  return result;
}

}  // namespace untangle
