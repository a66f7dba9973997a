// The stage loop of the repair (run_repair) and the dispatch of one step to the move kinds.
//
// Stages: a run starts in stage 1 from the input. When it stalls with crossings left (method
// region), stage 2 starts again from the input with each track's own pieces as further candidate
// sides of self contours, flaps beyond the other surface's edge, and only measured moves on
// contours whose two sides both move. When that stalls too, stage 3 runs the same rules from the
// best state of the two: from the input the measured moves work on the whole tangle, from the best
// state on what the first two left. A single mesh tangled with itself, alone in the scene, takes
// stage 2 first and stage 1 second (order()). Only the best state is ever written, so the later
// stages can cost time but never leave more crossings.
#include "resolve/repair_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>

#include "check/summarize.h"
#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "detect/triangle_bvh.h"
#include "resolve/inside_vertices.h"
#include "resolve/measured_move.h"
#include "resolve/move_kinds.h"
#include "resolve/quality_stats.h"
#include "resolve/region_analysis.h"
#include "resolve/relax_shape.h"
#include "resolve/scene_measures.h"
#include "resolve/surface_queries.h"
#include "topology/describe_mesh.h"
#include "topology/scene_topology.h"

namespace untangle {
namespace {

using Clock = std::chrono::steady_clock;

double ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// Whether one side of a contour is an obstacle (its crossings all join the same two components).
bool touches_obstacle(const SceneTopology& topo, const SceneMeasures& measures,
                      const CrossingSet& set, const Contour& c) {
  if (c.crossings.empty()) return false;
  const RawCrossing& x = set.items[c.crossings.front()];
  return measures.role[topo.tri_mesh[x.face]] == Role::kObstacle ||
         measures.role[topo.edge_mesh(x.edge)] == Role::kObstacle;
}

class RepairLoop {
 public:
  RepairLoop(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins,
             const Rounding& round, const std::vector<Mesh>* rest, std::vector<MeshInfo>* described)
      : meshes_(meshes),
        options_(options),
        round_(round),
        topo_(build_topology(meshes)),
        measures_(measure_scene(topo_, meshes, pins, options.threads)),
        winding_(topo_, measures_.role, options.threads),
        trees_(topo_, measures_),
        measured_(topo_),
        scratch_(topo_.points.size()) {
    detect_.threads = options.threads;
    region_settings_.outside_closed_obstacles = options.outside_closed_obstacles;
    for (const Mesh& mesh : meshes_) {
      const bool obstacle = mesh.role == Role::kObstacle;
      detect_.skip_among.push_back(obstacle);
      region_settings_.obstacle.push_back(obstacle);
    }
    region_settings_.orientation = measures_.closed;
    region_settings_.winding = &winding_;
    moved_.assign(topo_.points.size(), 0);
    start_points_ = topo_.points;
    if (described != nullptr)
      for (std::uint32_t m = 0; m < meshes_.size(); ++m)
        described->push_back(describe_mesh_in(topo_, m, meshes_[m]));
    if (rest != nullptr) {
      rest_points_ = start_points_;
      for (std::uint32_t m = 0; m < meshes_.size(); ++m)
        for (std::uint32_t i = 0; i < topo_.welded[m].size(); ++i)
          rest_points_[topo_.welded[m][i]] = (*rest)[m].positions[i];
    }
    diagonal_ = input_diagonals();
    obstacle_bvh_ = std::make_unique<TriangleBvh>(topo_, detect_.skip_among);
    detect_.skipped_bvh = obstacle_bvh_.get();
    // Their triangles' planes for the pruning test, found once too: a triangle of the body near
    // the garment is in pairs of every update.
    obstacle_planes_.resize(topo_.tris.size());
    for (std::uint32_t t = 0; t < topo_.tris.size(); ++t)
      if (detect_.skip_among[topo_.tri_mesh[t]])
        obstacle_planes_[t] = triangle_plane(topo_.points, topo_.detect_tris()[t]);
    detect_.skipped_planes = &obstacle_planes_;
  }

  // The obstacles' winding numbers, built once at the start (the obstacles never move).
  const ObstacleWinding& winding() const { return winding_; }

  FixResult run(const FixProgress& progress) {
    FixResult result;
    const auto start = Clock::now();
    result.obstacle_crossing_pairs = measures_.obstacle_crossing_pairs;
    std::size_t best_crossings = static_cast<std::size_t>(-1);  // and inside vertices
    double best_length = INFINITY;
    std::size_t written_illegal = static_cast<std::size_t>(-1);
    double written_length = INFINITY;
    int since_best = 0;
    // After the first iteration only what moved is tested again (update_crossings), on per-mesh
    // hierarchies refitted to the new positions.
    std::unique_ptr<SceneHierarchy> hierarchy;
    CrossingSet set;
    IntersectionCounts counts;  // of the current positions
    std::vector<Vec3> before_step;
    std::vector<std::uint8_t> changed(topo_.points.size(), 0);
    bool cancelled = false;  // by `progress`: nothing more is computed
    stage_index_ = 0;
    stage_ = options_.method == FixMethod::kRegion ? order()[0] : 1;
    for (int iteration = 0;; ++iteration) {
      const auto t0 = Clock::now();
      if (!hierarchy) {
        set = detect_crossings(topo_, detect_);
        hierarchy = std::make_unique<SceneHierarchy>(topo_, detect_);
        find_inside_by_parts(topo_, measures_.role, winding_, set, options_.threads, inside_);
      } else {
        for (std::size_t v = 0; v < changed.size(); ++v)
          changed[v] = topo_.points[v] != before_step[v] ? 1 : 0;
        hierarchy->update(topo_, changed);
        set = update_crossings(topo_, detect_, *hierarchy, set, changed);
        find_inside_by_parts(topo_, measures_.role, winding_, set, options_.threads, inside_);
      }
      const auto t1 = Clock::now();
      const std::vector<TracedContour> traced = build_contours(topo_, set);
      const auto t2 = Clock::now();
      result.detect_ms += ms(t0, t1);
      result.contours_ms += ms(t1, t2);
      counts = summarize(topo_, set, traced).counts;
      counts.inside_by_mesh = inside_per_mesh(topo_, inside_);
      for (std::size_t n : counts.inside_by_mesh) counts.inside_vertices += n;
      // A vertex inside an obstacle counts like a crossing (DESIGN §4): the best state has the
      // fewest of both together, then the shortest contours.
      const std::size_t illegal = counts.crossings + counts.inside_vertices;
      const CrossingKinds kinds = crossing_kinds(set, counts);
      if (iteration == 0) {
        result.before = counts;
        input_kinds_ = kinds;
      }
      if ((illegal < written_illegal ||
           (illegal == written_illegal && counts.contour_length < written_length)) &&
          no_worse_than_input(kinds)) {
        written_points_ = topo_.points;  // the state written if the run ends unresolved
        written_counts_ = counts;
        written_illegal = illegal;
        written_length = counts.contour_length;
      }
      IterationRecord record;
      record.iteration = iteration;
      record.crossings = counts.crossings;
      record.contour_length = counts.contour_length;
      record.elapsed_ms = ms(start, Clock::now());
      record.stage = stage_;
      result.history.push_back(record);
      result.iterations = iteration;
      if (progress && !progress(record)) {
        cancelled = true;
        break;
      }
      if (set.items.empty() && counts.inside_vertices == 0) {
        result.clean = true;
        break;
      }
      if (illegal < best_crossings ||
          (illegal == best_crossings && counts.contour_length < best_length))
        best_points_ = topo_.points;  // where stage 3 starts
      if (illegal < best_crossings || counts.contour_length < best_length * (1.0 - 1e-3)) {
        best_crossings = std::min(best_crossings, illegal);
        best_length = std::min(best_length, counts.contour_length);
        since_best = 0;
      } else if (++since_best >= options_.stall_iterations) {
        if (escalate(hierarchy, since_best)) continue;
        result.stalled = true;
        break;
      }
      if (iteration >= options_.max_iterations) break;
      before_step = topo_.points;
      measured_.start_step(set, *hierarchy, topo_.tris.size());
      const bool moved = step(set, traced, result);
      result.resolve_ms += ms(t2, Clock::now());
      result.displace_ms = result.resolve_ms - result.regions_ms;
      if (!moved) {
        if (escalate(hierarchy, since_best)) continue;
        result.stalled = true;
        break;
      }
    }
    // Unresolved: the best state no worse than the input is what is written (never_worse). Its
    // counts are the loop's own; the written file is detected once more by the caller (the
    // written files are the truth).
    const std::vector<Vec3> last_detected = result.clean ? std::vector<Vec3>{} : topo_.points;
    if (!result.clean && !written_points_.empty()) {
      topo_.points = written_points_;
      counts = written_counts_;
    }
    result.after = counts;
    result.clean = counts.crossings == 0 && counts.inside_vertices == 0;
    if (options_.relax && hierarchy) {
      const auto t0 = Clock::now();
      if (result.clean) {
        relax(measures_, *hierarchy, result);
      } else if (!cancelled && rest_points_.empty() &&
                 std::find(moved_.begin(), moved_.end(), 1) != moved_.end()) {
        // Not in a continuation's steps (those with a rest shape of their own): one that ends
        // unresolved is undone or superseded, and never written.
        relax_unresolved(last_detected, *hierarchy, result);
      }
      result.relax_ms = ms(t0, Clock::now());
    }
    result.quality = quality_stats(topo_, start_points_, measures_.role);
    write_back(result);
    return result;
  }

 private:
  // A state's crossings by what they join, and its inside vertices.
  struct CrossingKinds {
    std::size_t obstacle = 0;  // a movable mesh against an obstacle
    std::size_t self = 0;      // a mesh against itself
    std::size_t between = 0;   // two movable meshes
    std::size_t inside = 0;    // movable vertices inside an obstacle
  };

  CrossingKinds crossing_kinds(const CrossingSet& set, const IntersectionCounts& counts) const {
    CrossingKinds k;
    for (const RawCrossing& x : set.items) {
      const std::uint32_t a = topo_.edge_mesh(x.edge), b = topo_.tri_mesh[x.face];
      if (measures_.role[a] == Role::kObstacle || measures_.role[b] == Role::kObstacle)
        ++k.obstacle;
      else if (a == b)
        ++k.self;
      else
        ++k.between;
    }
    k.inside = counts.inside_vertices;
    return k;
  }

  // Per mesh, its input bounding box's diagonal (0 for an empty mesh).
  std::vector<double> input_diagonals() const {
    std::vector<Vec3> lo(meshes_.size(), Vec3{INFINITY, INFINITY, INFINITY});
    std::vector<Vec3> hi(meshes_.size(), Vec3{-INFINITY, -INFINITY, -INFINITY});
    for (std::uint32_t v = 0; v < start_points_.size(); ++v) {
      const std::uint32_t m = topo_.vertex_mesh[v];
      for (int k = 0; k < 3; ++k) {
        lo[m][k] = std::min(lo[m][k], start_points_[v][k]);
        hi[m][k] = std::max(hi[m][k], start_points_[v][k]);
      }
    }
    std::vector<double> out(meshes_.size(), 0.0);
    for (std::size_t m = 0; m < out.size(); ++m)
      if (lo[m][0] <= hi[m][0]) out[m] = norm(sub(hi[m], lo[m]));
    return out;
  }

  // The relaxation of the state left (clean, or the written state of an unresolved run), toward
  // the input's shape; `measures` may hold vertices that are free in the scene.
  void relax(const SceneMeasures& measures, SceneHierarchy& hierarchy, FixResult& result) {
    const bool other_rest = !rest_points_.empty();
    RelaxShapeInputs relax{measures, other_rest ? rest_points_ : start_points_, round_, detect_,
                           winding_, {}, options_.threads, other_rest ? &start_points_ : nullptr};
    for (double e : measures.mean_edge) relax.clearance.push_back(options_.clearance * e);
    relax.max_sweeps = options_.relax_sweeps;
    relax.trees = &trees_;
    const RelaxShapeResult relaxed = relax_shape(relax, topo_, hierarchy, inside_, moved_);
    result.relax_sweeps = relaxed.sweeps;
    result.relaxed_vertices = relaxed.relaxed;
  }

  // An unresolved run relaxes the state it writes too, around what is left: the vertices of every
  // crossing and every vertex inside an obstacle hold, the rest relaxes as after a clean repair,
  // each sweep accepted only where it makes no crossing and puts no vertex inside (so the
  // crossings left can only go, never come). The best state of the repair's iterations is the
  // shape its moves left, unrelaxed: male_casualsuit01 on its body scaled 1.05 wrote 301
  // crossings with an edge stretched 29 times and 173 faces turned over. A relaxed state that is
  // no longer no worse than the input (the part turned or slid beyond max_written_move: 3 of 400
  // random tangles) is undone. result.after becomes the relaxed state's counts.
  void relax_unresolved(const std::vector<Vec3>& last_detected, SceneHierarchy& hierarchy,
                        FixResult& result) {
    std::vector<std::uint8_t> refit(topo_.points.size(), 0);
    for (std::size_t v = 0; v < refit.size(); ++v) refit[v] = topo_.points[v] != last_detected[v];
    hierarchy.update(topo_, refit);
    const CrossingSet left = detect_crossings(topo_, detect_);
    find_inside_by_parts(topo_, measures_.role, winding_, left, options_.threads, inside_);
    SceneMeasures held = measures_;
    for (const RawCrossing& x : left.items) {
      for (std::uint32_t v : topo_.edges[x.edge]) held.free[v] = 0;
      for (std::uint32_t v : topo_.tris[x.face]) held.free[v] = 0;
    }
    for (std::size_t v = 0; v < inside_.size(); ++v)
      if (inside_[v] != kNone) held.free[v] = 0;
    const std::vector<Vec3> unrelaxed = topo_.points;
    const std::vector<std::uint8_t> moved = moved_;
    const std::vector<std::uint32_t> inside = inside_;
    relax(held, hierarchy, result);
    const CrossingSet after = detect_crossings(topo_, detect_);
    find_inside_by_parts(topo_, measures_.role, winding_, after, options_.threads, inside_);
    IntersectionCounts relaxed = summarize(topo_, after, build_contours(topo_, after)).counts;
    relaxed.inside_by_mesh = inside_per_mesh(topo_, inside_);
    for (std::size_t n : relaxed.inside_by_mesh) relaxed.inside_vertices += n;
    if (no_worse_than_input(crossing_kinds(after, relaxed))) {
      result.after = relaxed;
      return;
    }
    for (std::size_t v = 0; v < refit.size(); ++v) refit[v] = topo_.points[v] != unrelaxed[v];
    topo_.points = unrelaxed;
    hierarchy.update(topo_, refit);
    moved_ = moved;
    inside_ = inside;
    result.relax_sweeps = 0;
    result.relaxed_vertices = 0;
  }

  // Never worse than the input (DESIGN §5): a state may be written only if it has no more
  // crossings of any kind (against obstacles, of a mesh with itself, between movable meshes) and
  // no more inside vertices than the input, and moves no vertex further than
  // options_.max_written_move diagonals of its mesh's input bounding box. The input qualifies.
  bool no_worse_than_input(const CrossingKinds& k) const {
    if (k.obstacle > input_kinds_.obstacle || k.self > input_kinds_.self ||
        k.between > input_kinds_.between || k.inside > input_kinds_.inside)
      return false;
    for (std::uint32_t v = 0; v < topo_.points.size(); ++v) {
      if (topo_.points[v] == start_points_[v]) continue;
      const double diagonal = diagonal_[topo_.vertex_mesh[v]];
      if (norm(sub(topo_.points[v], start_points_[v])) > options_.max_written_move * diagonal)
        return false;
    }
    return true;
  }

  // The order of the stages: 1, 2, 3; for a single mesh tangled with itself (no other mesh) 2,
  // 1, 3, as the second stage's rules (track pieces as sides, measured moves where both sides
  // move) undo a fold through itself in a few iterations where the first stage's shear stalls
  // (Wicke's configurations subdivided: 1 to 4 iterations against 10 to 40). A run uses the
  // first options_.stages of its order; stages 1 and 2 start from the input, stage 3 from the
  // best state.
  static constexpr int kOrder[2][3] = {{1, 2, 3}, {2, 1, 3}};
  const int* order() const { return kOrder[meshes_.size() == 1 ? 1 : 0]; }
  int stages() const {
    return options_.method == FixMethod::kRegion ? std::max(1, std::min(3, options_.stages)) : 1;
  }

  bool escalate(std::unique_ptr<SceneHierarchy>& hierarchy, int& since_best) {
    if (stage_index_ + 1 >= stages() || best_points_.empty()) return false;
    stage_ = order()[++stage_index_];
    topo_.points = stage_ == 3 ? best_points_ : start_points_;
    hierarchy.reset();  // positions jumped: the next detection is a full one
    since_best = 0;
    return true;
  }

  // One step: every move kind adds its proposals to one Moves, then they are applied. Returns
  // false when nothing could move.
  bool step(const CrossingSet& set, const std::vector<TracedContour>& traced, FixResult& result) {
    const auto regions_start = Clock::now();
    const RegionAnalysis analysis = analyse_regions(topo_, set, traced, region_settings_);
    result.regions_ms += ms(regions_start, Clock::now());
    const RepairContext ctx{topo_, measures_, options_, detect_, round_, stage_};
    StepTools tools{trees_, measured_, scratch_};
    Moves moves(topo_.points.size());

    // Layers and coincident copies are told by their parallel crossings (region method only).
    const bool region = options_.method == FixMethod::kRegion;
    ParallelCounts parallel;
    ComponentPairs layered;
    if (region) {
      parallel = parallel_crossings(topo_, set, traced);
      layered = layered_pairs(ctx, trees_, parallel, layer_orders_);
    }
    // Which illegal sets move: movable surfaces only; between two movable surfaces, the side with
    // the smaller illegal area (the other keeps its shape).
    std::vector<const IllegalSet*> moving;
    for (const IllegalSet& s : analysis.illegal) {
      // A component against itself has no other surface to move across: its labels steer the
      // DRN. Layers keep their order instead (lay_layer).
      if (!measures_.movable_component(topo_, s.component) || s.component == s.partner) continue;
      if (layered.count({std::min(s.component, s.partner), std::max(s.component, s.partner)}))
        continue;
      bool smaller = true;
      for (const IllegalSet& o : analysis.illegal) {
        if (o.component == s.partner && o.partner == s.component &&
            measures_.movable_component(topo_, o.component) &&
            (o.area < s.area || (o.area == s.area && o.component < s.component)))
          smaller = false;
      }
      if (!smaller) continue;
      bool any_free = false;
      for (std::uint32_t v : s.vertices) any_free = any_free || measures_.free[v];
      if (!any_free) continue;
      moving.push_back(&s);
      if (s.rule == RegionRule::kInside)
        ++result.illegal_regions_by_inside;
      else
        ++result.illegal_regions_by_area;
    }

    std::vector<std::uint8_t> in_moving_set(topo_.points.size(), 0);
    FreshTrees trees;  // movable partners, this step
    if (region) {
      for (const IllegalSet* s : moving) {
        const MeshTree& tree = trees_.component_tree(s->partner, trees);
        for (std::uint32_t v : s->vertices) in_moving_set[v] = 1;
        move_regions(ctx, scratch_, topo_.component_mesh[s->component],
                     measures_.closed[s->partner], s->vertices, tree, moves);
      }
    }
    // Inside an obstacle with no contour to move it (either method).
    inside_move(ctx, scratch_, trees_, set, inside_, in_moving_set, moves);
    if (region) {
      // Self contours longest first (equal ones in the order they were walked, which follows the
      // canonical numbering): a vertex moves for the first contour that claims it, so the order
      // decides what moves where contours meet. In walk order, Wicke's crossing contours
      // subdivided three times (symmetric: many contours of one length) ended clean within 5
      // iterations under 8 of 8 jitters of 1e-7 with vertices sorted by position and 3 of 8 sorted
      // by distance (turned as in the tests: 6 and 0); longest first, 8 of 8 in all four. Most
      // crossings first did as well there but distorted female_elegantsuit01 on its body.
      std::vector<std::uint32_t> longest_first(traced.size());
      std::iota(longest_first.begin(), longest_first.end(), 0u);
      std::stable_sort(longest_first.begin(), longest_first.end(),
                       [&](std::uint32_t a, std::uint32_t b) {
                         return traced[a].contour.length > traced[b].contour.length;
                       });
      for (std::uint32_t k : longest_first)
        self_contour_move(ctx, tools, set, traced[k], analysis, in_moving_set, moves);
      separate_coincident_layers(ctx, trees_, set, traced, parallel, layered, layer_orders_,
                                 analysis, in_moving_set, moves);
      for (const TracedContour& t : traced)
        flap_move(ctx, tools, set, t, trees, in_moving_set, moves);
    }

    // The DRN: every crossing (paper method), or those of contours that no moving illegal region
    // touches (region method).
    for (const TracedContour& t : traced) {
      const Contour& c = t.contour;
      bool covered = false;
      if (region) {
        for (std::uint32_t ci : c.crossings) {
          const RawCrossing& x = set.items[ci];
          for (std::uint32_t v : topo_.edges[x.edge]) covered = covered || in_moving_set[v];
          for (std::uint32_t v : topo_.tris[x.face]) covered = covered || in_moving_set[v];
        }
      }
      if (covered) continue;
      // Layers are laid, not sheared: the DRN would push the inner layer into what lies beneath.
      const std::uint32_t ca = track_component(topo_, set, t, 0),
                          cb = track_component(topo_, set, t, 1);
      if (layered.count({std::min(ca, cb), std::max(ca, cb)})) continue;
      // Stages 2-3 make only measured moves where both sides move (a self contour, two movable
      // components): on a finely subdivided fold the DRN's shear is what tangles it further.
      // Against an obstacle the DRN acts.
      if (ctx.pieces() && !touches_obstacle(topo_, measures_, set, c))
        measured_drn_move(ctx, tools, set, t, analysis, in_moving_set, moves);
      else
        drn_moves(ctx, set, t, analysis, moves);
    }

    const SettledMoves settled = settle_moves(ctx, moves);
    for (std::size_t i = 0; i < settled.movers.size(); ++i) {
      topo_.points[settled.movers[i]] = settled.next[i];
      moved_[settled.movers[i]] = 1;
    }
    return !settled.movers.empty();
  }

  // Copies moved welded positions to every input vertex of their group; displacement statistics.
  void write_back(FixResult& result) {
    double sum = 0.0;
    std::size_t count = 0;
    for (std::uint32_t m = 0; m < meshes_.size(); ++m) {
      std::vector<Vec3>& positions = meshes_[m].positions;
      for (std::uint32_t i = 0; i < positions.size(); ++i) {
        const std::uint32_t v = topo_.welded[m][i];
        if (!moved_[v] || topo_.points[v] == start_points_[v]) continue;
        const double d = norm(sub(topo_.points[v], positions[i]));
        positions[i] = topo_.points[v];
        ++count;
        sum += d;
        if (d > result.displacement.max) {
          result.displacement.max = d;
          result.displacement.max_over_mean_edge =
              measures_.mean_edge[m] > 0 ? d / measures_.mean_edge[m] : 0.0;
        }
      }
    }
    result.displacement.moved_vertices = count;
    result.displacement.mean = count > 0 ? sum / static_cast<double>(count) : 0.0;
  }

  std::vector<Mesh>& meshes_;
  const FixOptions& options_;
  Rounding round_;
  SceneTopology topo_;
  SceneMeasures measures_;
  ObstacleWinding winding_;  // the obstacles never move: built once
  std::vector<std::uint32_t> inside_;  // per welded vertex: the obstacle it is inside, or kNone
  DetectSettings detect_;
  RegionSettings region_settings_;
  std::unique_ptr<TriangleBvh> obstacle_bvh_;  // the obstacles never move: built once
  std::vector<TriPlane> obstacle_planes_;       // per triangle, the obstacles' (detect_)
  SurfaceTrees trees_;
  MeasuredMoves measured_;
  Scratch scratch_;
  LayerOrders layer_orders_;
  int stage_ = 1;        // the rules of this stage are in force (RepairContext::pieces)
  int stage_index_ = 0;  // its place in order()
  std::vector<std::uint8_t> moved_;  // per welded vertex: moved at least once
  std::vector<Vec3> start_points_;
  std::vector<double> diagonal_;  // per mesh: input_diagonals
  std::vector<Vec3> rest_points_;  // welded: the shape relaxed toward, when not the input's
  CrossingKinds input_kinds_;
  std::vector<Vec3> best_points_;     // the fewest crossings and inside vertices so far
  std::vector<Vec3> written_points_;  // the same among the states no worse than the input
  IntersectionCounts written_counts_;
};

}  // namespace

FixResult run_repair(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins,
                     const Rounding& round, const FixProgress& progress,
                     const std::vector<Mesh>* rest, std::vector<MeshInfo>* described,
                     std::shared_ptr<const ObstacleWinding>* winding) {
  RepairLoop loop(meshes, options, pins, round, rest, described);
  FixResult result = loop.run(progress);
  if (winding != nullptr) *winding = std::make_shared<const ObstacleWinding>(loop.winding());
  return result;
}

}  // namespace untangle
