// fix_meshes: detect -> contours -> regions -> displacements, until clean, capped or stalled.
#include "untangle/fix.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <unordered_set>

#include "check/summarize.h"
#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "detect/orientation.h"
#include "detect/triangle_bvh.h"
#include "resolve/buried_faces.h"
#include "resolve/region_analysis.h"
#include "resolve/trial_move.h"
#include "resolve/triangle_tree.h"
#include "topology/scene_topology.h"

namespace untangle {
namespace {

using Kernel = TreeKernel;
using TriangleList = TreeTriangleList;
using Tree = TriangleTree;
using Clock = std::chrono::steady_clock;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 add(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
Vec3 unit(const Vec3& a) {
  const double n = norm(a);
  return n > 0.0 ? scale(a, 1.0 / n) : Vec3{0.0, 0.0, 0.0};
}

double ms(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

// The closest-point structure of one mesh at the current positions.
struct MeshTree {
  TriangleList triangles;
  std::vector<std::uint32_t> ids;  // global triangle id per entry
  Tree tree;
};

std::unique_ptr<MeshTree> build_tree(const SceneTopology& topo, const std::vector<std::uint32_t>& tris) {
  auto out = std::make_unique<MeshTree>();
  for (std::uint32_t t : tris) {
    const auto& tri = topo.tris[t];
    auto p = [&](int k) {
      const Vec3& v = topo.points[tri[k]];
      return Kernel::Point_3(v[0], v[1], v[2]);
    };
    out->triangles.emplace_back(p(0), p(1), p(2));
    out->ids.push_back(t);
  }
  if (out->triangles.empty()) return out;
  out->tree.insert(out->triangles.begin(), out->triangles.end());
  out->tree.accelerate_distance_queries();
  return out;
}

Vec3 face_normal(const SceneTopology& topo, std::uint32_t t) {
  const auto& tri = topo.tris[t];
  return unit(cross(sub(topo.points[tri[1]], topo.points[tri[0]]),
                    sub(topo.points[tri[2]], topo.points[tri[0]])));
}

// Accumulated moves of one iteration, per welded vertex.
struct Moves {
  std::vector<Vec3> region;
  std::vector<std::uint8_t> has_region;
  std::vector<Vec3> crossing;
  std::vector<std::uint32_t> crossing_count;

  explicit Moves(std::size_t n)
      : region(n, Vec3{0, 0, 0}), has_region(n, 0), crossing(n, Vec3{0, 0, 0}), crossing_count(n, 0) {}

  void push(std::uint32_t v, const Vec3& d) {
    crossing[v] = add(crossing[v], d);
    ++crossing_count[v];
  }
};

// Rings of neighbours around the other track's crossings that stand for "the other surface" of
// a self contour.
constexpr int kPatchRings = 3;
// How far (in mean edge lengths) a vertex of the outer layer that dips through the inner one is
// still laid back on its side.
constexpr double kLayerReach = 2.0;
// The largest set of vertices whose moves are measured before they are made (TrialMove).
constexpr std::size_t kMeasuredVertices = 2500;
// A contour's neighbourhood relaxed in the second stage (relax_choice): up to this many rings
// around its vertices, this many smoothing sweeps.
constexpr int kRelaxRings = 4;
constexpr int kRelaxSweeps = 10;
// Relaxations measure at most 1/kRelaxShare of the mesh's triangles (and 5,000) per step: where
// they help, a few small ones do; on two whole garments the step's budget goes to the moves.
constexpr std::size_t kRelaxShare = 20;

class Solver {
 public:
  Solver(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins,
         const std::function<Vec3(const Vec3&)>& round)
      : meshes_(meshes), options_(options), round_(round), topo_(build_topology(meshes)) {
    const std::size_t nv = topo_.points.size();
    free_.assign(nv, 0);
    for (std::uint32_t v = 0; v < nv; ++v)
      free_[v] = meshes_[topo_.vertex_mesh[v]].role == Role::kMovable ? 1 : 0;
    for (std::size_t m = 0; m < pins.size() && m < meshes_.size(); ++m) {
      for (std::size_t i = 0; i < pins[m].size() && i < topo_.welded[m].size(); ++i)
        if (pins[m][i]) free_[topo_.welded[m][i]] = 0;
    }
    // Mean edge length per mesh and per vertex (fixed at the start: steps stay relative to the
    // asset's own scale).
    mean_edge_.assign(meshes_.size(), 0.0);
    std::vector<std::size_t> edge_count(meshes_.size(), 0);
    vertex_edge_.assign(nv, 0.0);
    std::vector<std::uint32_t> incident(nv, 0);
    for (const auto& e : topo_.edges) {
      const double len = norm(sub(topo_.points[e[0]], topo_.points[e[1]]));
      const std::uint32_t m = topo_.vertex_mesh[e[0]];
      mean_edge_[m] += len;
      ++edge_count[m];
      for (std::uint32_t v : e) {
        vertex_edge_[v] += len;
        ++incident[v];
      }
    }
    for (std::size_t m = 0; m < meshes_.size(); ++m)
      if (edge_count[m] > 0) mean_edge_[m] /= static_cast<double>(edge_count[m]);
    for (std::uint32_t v = 0; v < nv; ++v)
      vertex_edge_[v] = incident[v] > 0 ? vertex_edge_[v] / incident[v] : mean_edge_[topo_.vertex_mesh[v]];
    settings_.threads = options.threads;
    region_settings_.outside_closed_obstacles = options.outside_closed_obstacles;
    for (std::uint32_t m = 0; m < meshes_.size(); ++m) {
      const bool obstacle = meshes_[m].role == Role::kObstacle;
      settings_.skip_among.push_back(obstacle);
      region_settings_.obstacle.push_back(obstacle);
    }
    region_settings_.orientation = closed_orientations(topo_);
    oriented_.assign(topo_.component_mesh.size(), 0);
    orientation_ = face_orientations(topo_);
    for (std::uint32_t t = 0; t < topo_.tris.size(); ++t)
      if (orientation_[t] != 0) oriented_[topo_.tri_component(t)] = 1;
    moved_.assign(nv, 0);
    component_size_.assign(topo_.component_mesh.size(), 0);
    for (std::uint32_t v = 0; v < nv; ++v) ++component_size_[topo_.vertex_component[v]];
    start_points_ = topo_.points;
    member_.assign(nv, 0);
    measured_.assign(nv, 0);
    seen_.assign(nv, 0);
    normal_.assign(nv, Vec3{0, 0, 0});
    trial_ = std::make_unique<TrialMove>(topo_);
    obstacle_bvh_ = std::make_unique<TriangleBvh>(topo_, settings_.skip_among);
    settings_.skipped_bvh = obstacle_bvh_.get();
    find_buried_obstacle_faces();
  }

  FixResult run(const FixProgress& progress) {
    FixResult result;
    const auto start = Clock::now();
    result.obstacle_crossing_pairs = obstacle_crossing_pairs_;
    std::size_t best_crossings = static_cast<std::size_t>(-1);
    double best_length = INFINITY;
    int since_best = 0;
    // After the first iteration only what moved is tested again (update_crossings), on per-mesh
    // hierarchies refitted to the new positions.
    std::unique_ptr<SceneHierarchy> hierarchy;
    CrossingSet set;
    std::vector<Vec3> before_step;
    std::vector<std::uint8_t> changed(topo_.points.size(), 0);
    for (int iteration = 0;; ++iteration) {
      const auto t0 = Clock::now();
      if (!hierarchy) {
        set = detect_crossings(topo_, settings_);
        hierarchy = std::make_unique<SceneHierarchy>(topo_, settings_);
      } else {
        for (std::size_t v = 0; v < changed.size(); ++v)
          changed[v] = topo_.points[v] != before_step[v] ? 1 : 0;
        hierarchy->update(topo_, changed);
        set = update_crossings(topo_, settings_, *hierarchy, set, changed);
      }
      const auto t1 = Clock::now();
      const std::vector<TracedContour> traced = build_contours(topo_, set);
      const auto t2 = Clock::now();
      result.detect_ms += ms(t0, t1);
      result.contours_ms += ms(t1, t2);
      IntersectionCounts counts = summarize(topo_, set, traced).counts;
      if (iteration == 0) result.before = counts;
      IterationRecord record;
      record.iteration = iteration;
      record.crossings = counts.crossings;
      record.contour_length = counts.contour_length;
      record.elapsed_ms = ms(start, Clock::now());
      record.stage = stage_;
      result.history.push_back(record);
      result.iterations = iteration;
      if (progress && !progress(record)) break;
      if (set.items.empty()) {
        result.clean = true;
        break;
      }
      if (counts.crossings < best_crossings ||
          (counts.crossings == best_crossings && counts.contour_length < best_length)) {
        best_points_ = topo_.points;  // the state written if the run ends unresolved
      }
      if (counts.crossings < best_crossings || counts.contour_length < best_length * (1.0 - 1e-3)) {
        best_crossings = std::min(best_crossings, counts.crossings);
        best_length = std::min(best_length, counts.contour_length);
        since_best = 0;
      } else if (++since_best >= options_.stall_iterations) {
        if (escalate(hierarchy, since_best)) continue;
        result.stalled = true;
        break;
      }
      if (iteration >= options_.max_iterations) break;
      before_step = topo_.points;
      hierarchy_ = hierarchy.get();
      trial_->sync(set);
      wide_tried_ = false;
      for (std::uint32_t v : measured_list_) measured_[v] = 0;
      measured_list_.clear();
      trial_budget_ = 2 * topo_.tris.size() + 20000;
      relax_budget_ = topo_.tris.size() / kRelaxShare + 5000;
      const bool moved = step(set, traced, result);
      result.resolve_ms += ms(t2, Clock::now());
      result.displace_ms = result.resolve_ms - result.regions_ms;
      if (!moved) {
        if (escalate(hierarchy, since_best)) continue;
        result.stalled = true;
        break;
      }
    }
    if (result.clean) {
      // The last detection (equal to a full one) found nothing on the current positions.
      result.remaining = summarize(topo_, set, {});
      result.after = result.remaining.counts;
      write_back(result);
      return result;
    }
    if (!best_points_.empty()) topo_.points = best_points_;
    // The state written is detected from scratch: it is what the result reports.
    set = detect_crossings(topo_, settings_);
    const std::vector<TracedContour> traced = build_contours(topo_, set);
    result.remaining = summarize(topo_, set, traced);
    result.after = result.remaining.counts;
    result.clean = set.items.empty();
    write_back(result);
    return result;
  }

 private:
  // The second stage of the region method, once: when the run stalls with crossings left, it
  // starts again from the input with each track's own pieces as further candidate sides of the
  // self contours (self_contour_move), flaps beyond the other surface's edge (flap_move), and only
  // measured moves (the crossing step or the neighbourhood relaxed) on contours whose two sides
  // both move. When that stalls too, a third stage, once, with the same rules from the best state
  // of the two: from the input the measured moves work on the whole tangle, from the best state
  // on what the first two left (random tangles, seeds 0 to 399: 277 -> 288 clean). Only the best
  // state is ever written, so the later stages can cost time but never leave more crossings.
  // The second and third stages: track pieces are candidates, and only measured moves act where
  // both sides of a contour move.
  bool pieces() const { return stage_ >= 2; }

  bool escalate(std::unique_ptr<SceneHierarchy>& hierarchy, int& since_best) {
    if (stage_ >= 3 || best_points_.empty() || options_.method != FixMethod::kRegion) return false;
    ++stage_;
    topo_.points = stage_ == 2 ? start_points_ : best_points_;
    hierarchy.reset();  // positions jumped: the next detection is a full one
    since_best = 0;
    return true;
  }

  // One displacement step. Returns false when nothing could move.
  bool step(const CrossingSet& set, const std::vector<TracedContour>& traced, FixResult& result) {
    const auto regions_start = Clock::now();
    const RegionAnalysis analysis = analyse_regions(topo_, set, traced, region_settings_);
    result.regions_ms += ms(regions_start, Clock::now());
    Moves moves(topo_.points.size());

    // Which illegal sets move: movable surfaces only; between two movable surfaces, the side with
    // the smaller illegal area (the other keeps its shape).
    // Layers and coincident copies are told by their parallel crossings (region method only).
    const bool region = options_.method == FixMethod::kRegion;
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::array<std::size_t, 2>> parallel;
    std::set<std::pair<std::uint32_t, std::uint32_t>> layered;
    if (region) {
      parallel = parallel_crossings(set, traced);
      layered = layered_pairs(parallel);
    }
    std::vector<const IllegalSet*> moving;
    for (const IllegalSet& s : analysis.illegal) {
      // A component against itself has no other surface to move across: its labels steer the
      // crossing rule. Layers keep their order instead (lay_layer).
      if (!movable_component(s.component) || s.component == s.partner) continue;
      if (layered.count({std::min(s.component, s.partner), std::max(s.component, s.partner)})) continue;
      bool smaller = true;
      for (const IllegalSet& o : analysis.illegal) {
        if (o.component == s.partner && o.partner == s.component && movable_component(o.component) &&
            (o.area < s.area || (o.area == s.area && o.component < s.component)))
          smaller = false;
      }
      if (!smaller) continue;
      bool any_free = false;
      for (std::uint32_t v : s.vertices) any_free = any_free || free_[v];
      if (!any_free) continue;
      moving.push_back(&s);
      if (s.rule == RegionRule::kInside) ++result.illegal_regions_by_inside;
      else ++result.illegal_regions_by_area;
    }

    std::vector<std::uint8_t> in_moving_set(topo_.points.size(), 0);
    if (region) {
      std::map<std::uint32_t, std::unique_ptr<MeshTree>> trees;  // movable partners, this step
      for (const IllegalSet* s : moving) {
        const MeshTree& tree = component_tree(s->partner, trees);
        for (std::uint32_t v : s->vertices) in_moving_set[v] = 1;
        move_regions(topo_.component_mesh[s->component], region_settings_.orientation[s->partner],
                     s->vertices, tree, moves);
      }
      for (const TracedContour& t : traced) self_contour_move(set, t, analysis, in_moving_set, moves);
      separate_coincident_layers(set, traced, parallel, layered, analysis, in_moving_set, moves);
      for (const TracedContour& t : traced) flap_move(set, t, trees, in_moving_set, moves);
    }

    // Per-crossing rule: every crossing (paper method), or those of contours that no moving
    // illegal region touches (region method).
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
      // Layers are laid, not sheared: the per-crossing rule would push the inner layer into
      // what lies beneath it.
      const std::uint32_t ca = track_component(topo_, set, t, 0), cb = track_component(topo_, set, t, 1);
      if (layered.count({std::min(ca, cb), std::max(ca, cb)})) continue;
      // The second stage makes only measured moves where both sides move (a self contour, two
      // movable components): on a finely subdivided fold the per-crossing rule's shear is what
      // tangles it further. Against an obstacle the per-crossing rule acts.
      if (pieces() && !touches_obstacle(set, c)) measured_crossing_move(set, t, analysis, in_moving_set, moves);
      else crossing_moves(set, t, analysis, moves);
    }

    return apply(moves);
  }

  // The closest-point tree of a whole component: kept for the run when the component is an
  // obstacle (it never moves), built into `fresh` for this step otherwise. A closed obstacle that
  // passes through itself (the cow's tail through its rump) leaves out its buried faces: a point
  // on one, or a ray's exit through one, is still inside the obstacle.
  const MeshTree& component_tree(std::uint32_t component,
                                 std::map<std::uint32_t, std::unique_ptr<MeshTree>>& fresh) {
    const bool fixed = meshes_[topo_.component_mesh[component]].role == Role::kObstacle;
    std::unique_ptr<MeshTree>& tree = fixed ? obstacle_trees_[component] : fresh[component];
    if (!tree) {
      std::vector<std::uint32_t> tris;
      const std::uint32_t m = topo_.component_mesh[component];
      for (std::uint32_t t = topo_.mesh_tri_begin[m]; t < topo_.mesh_tri_begin[m + 1]; ++t)
        if (topo_.tri_component(t) == component) tris.push_back(t);
      if (fixed && region_settings_.orientation[component] != 0) {
        std::vector<std::uint32_t> exposed;
        for (std::uint32_t t : tris)
          if (!buried_[t]) exposed.push_back(t);
        if (!exposed.empty()) tris = std::move(exposed);
      }
      tree = build_tree(topo_, tris);
    }
    return *tree;
  }

  // buried_ and obstacle_crossing_pairs_, once (constructor): per triangle, 1 for a buried face of
  // a closed obstacle component (buried_faces: inside an obstacle, or on a curve where the closed
  // obstacles pass through themselves or each other), and how many triangle pairs of theirs cross.
  // Those crossings are reported and left alone; region moves never aim at the buried faces.
  void find_buried_obstacle_faces() {
    buried_.assign(topo_.tris.size(), 0);
    std::vector<ClosedSurface> surfaces;
    std::vector<std::uint32_t> of_component(topo_.component_mesh.size(), kNone);
    for (std::uint32_t c = 0; c < topo_.component_mesh.size(); ++c) {
      if (movable_component(c) || region_settings_.orientation[c] == 0) continue;
      of_component[c] = static_cast<std::uint32_t>(surfaces.size());
      surfaces.push_back({{}, region_settings_.orientation[c]});
    }
    for (std::uint32_t t = 0; t < topo_.tris.size(); ++t) {
      const std::uint32_t s = of_component[topo_.tri_component(t)];
      if (s != kNone) surfaces[s].triangles.push_back(t);
    }
    const std::vector<std::vector<std::uint8_t>> flags =
        buried_faces(topo_, surfaces, options_.threads, &obstacle_crossing_pairs_);
    for (std::size_t s = 0; s < surfaces.size(); ++s)
      for (std::size_t k = 0; k < surfaces[s].triangles.size(); ++k)
        buried_[surfaces[s].triangles[k]] = flags[s][k];
  }

  // Per pair of different components that cross (lower index first): how many of their crossings
  // join nearly parallel faces (|cos| > 0.95 between the face's normal and that of a face on the
  // crossing edge), and how many crossings they have.
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::array<std::size_t, 2>> parallel_crossings(
      const CrossingSet& set, const std::vector<TracedContour>& traced) const {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::array<std::size_t, 2>> parallel;
    for (const TracedContour& t : traced) {
      const std::uint32_t a = track_component(topo_, set, t, 0);
      const std::uint32_t b = track_component(topo_, set, t, 1);
      if (a == b) continue;
      auto& count = parallel[{std::min(a, b), std::max(a, b)}];
      for (std::uint32_t ci : t.contour.crossings) {
        const RawCrossing& x = set.items[ci];
        const Vec3 nf = face_normal(topo_, x.face);
        const Vec3 ne = face_normal(topo_, topo_.edge_faces[topo_.edge_face_begin[x.edge]]);
        ++count[1];
        if (std::abs(dot(nf, ne)) > 0.95) ++count[0];
      }
    }
    return parallel;
  }

  bool movable_component(std::uint32_t c) const {
    return meshes_[topo_.component_mesh[c]].role == Role::kMovable;
  }

  // Layers: two movable, open, orientable components at least half of whose crossings join
  // nearly parallel faces, and whose vertices near each other lie on both sides of each other
  // with no clear majority (interleaved: a dress over a t-shirt, made for the same body at the
  // same offset). Their contours are the noise of two surfaces a fraction of an edge apart, so
  // the area rule has no large legal region to trust; the order of most of their overlap is kept
  // instead (lay_layer). Layers with a clear majority (a shirt's hem over the trousers' waist) are
  // left to the area rule, which also moves their deep dips whole.
  std::set<std::pair<std::uint32_t, std::uint32_t>> layered_pairs(
      const std::map<std::pair<std::uint32_t, std::uint32_t>, std::array<std::size_t, 2>>& parallel) {
    std::set<std::pair<std::uint32_t, std::uint32_t>> out;
    for (const auto& [key, count] : parallel) {
      // Decided once, where first seen: as the layers part, their last crossings need not be
      // parallel nor their vertices interleaved.
      auto found = layer_orders_.find(key);
      if (found == layer_orders_.end()) {
        if (2 * count[0] < count[1]) continue;
        // A closed surface (a ball through a sheet) is not a layer, however flat the crossing.
        auto layer = [&](std::uint32_t c) {
          return movable_component(c) && oriented_[c] && region_settings_.orientation[c] == 0;
        };
        if (!layer(key.first) || !layer(key.second)) continue;
        found = layer_orders_.emplace(key, decide_layer_order(key.first, key.second)).first;
      }
      if (found->second.interleaved) out.insert(key);
    }
    return out;
  }

  // The unit normal of triangle t turned by its orientation sign (face_orientations).
  Vec3 oriented_normal(std::uint32_t t) const {
    return scale(face_normal(topo_, t), orientation_[t] < 0 ? -1.0 : 1.0);
  }

  // Adds to delta[v] what it lacks of `length` along the unit direction `along` (each vertex keeps
  // the longest push asked of it along a direction).
  static void push_along(std::map<std::uint32_t, Vec3>& delta, std::uint32_t v, const Vec3& along,
                         double length) {
    Vec3& d = delta[v];
    const double have = dot(d, along);
    if (have < length) d = add(d, scale(along, length - have));
  }

  // A vertex of one component near another: its closest point there, that face's normal, the
  // signed distance along it.
  struct NearPoint {
    std::uint32_t v;
    std::uint32_t face;
    Vec3 c, n;
    double side;
  };

  // The vote of near vertices' sides weighted by their areas (a third of their faces'), over
  // their total area: from -1 (all on the negative side) to 1. A garment finer in one place than
  // another still votes by how much of it lies on each side.
  double area_vote(const std::vector<NearPoint>& near) const {
    double sum = 0.0, total = 0.0;
    for (const NearPoint& x : near) {
      double area = 0.0;  // twice the vertex area: each face is met through both its edges at v
      for (std::uint32_t j = topo_.vertex_edge_begin[x.v]; j < topo_.vertex_edge_begin[x.v + 1]; ++j) {
        const std::uint32_t e = topo_.vertex_edges[j];
        for (std::uint32_t k = topo_.edge_face_begin[e]; k < topo_.edge_face_begin[e + 1]; ++k) {
          const auto& tri = topo_.tris[topo_.edge_faces[k]];
          area += norm(cross(sub(topo_.points[tri[1]], topo_.points[tri[0]]),
                             sub(topo_.points[tri[2]], topo_.points[tri[0]])));
        }
      }
      sum += x.side > 0 ? area : x.side < 0 ? -area : 0.0;
      total += area;
    }
    return total > 0.0 ? sum / total : 0.0;
  }

  // The vertices of `component` within `near` of `tree`, and the vote of their sides (+1 for each
  // on the positive side of the closest face, -1 for each on the negative side).
  std::vector<NearPoint> near_points(std::uint32_t component, const MeshTree& tree, double near,
                                     long long& vote) const {
    std::vector<NearPoint> out;
    vote = 0;
    const std::uint32_t mesh = topo_.component_mesh[component];
    for (std::uint32_t v = topo_.mesh_vertex_begin[mesh]; v < topo_.mesh_vertex_begin[mesh + 1]; ++v) {
      if (topo_.vertex_component[v] != component) continue;
      const Vec3& p = topo_.points[v];
      const auto hit = tree.tree.closest_point_and_primitive(Kernel::Point_3(p[0], p[1], p[2]));
      const Vec3 c{hit.first.x(), hit.first.y(), hit.first.z()};
      if (norm(sub(p, c)) > near) continue;
      const std::uint32_t face = tree.ids[static_cast<std::size_t>(hit.second - tree.triangles.begin())];
      const Vec3 n = oriented_normal(face);
      const double side = dot(sub(p, c), n);
      vote += side > 0 ? 1 : side < 0 ? -1 : 0;
      out.push_back({v, face, c, n, side});
    }
    return out;
  }

  // Whether point `c` on triangle t lies on one of its boundary edges (the mesh's hem).
  bool on_boundary(std::uint32_t t, const Vec3& c) const {
    for (std::uint32_t e : topo_.tri_edges[t]) {
      if (!topo_.is_boundary(e)) continue;
      const Vec3& a = topo_.points[topo_.edges[e][0]];
      const Vec3 ab = sub(topo_.points[topo_.edges[e][1]], a);
      const double len2 = dot(ab, ab);
      const double u = len2 > 0.0 ? std::clamp(dot(sub(c, a), ab) / len2, 0.0, 1.0) : 0.0;
      if (norm(sub(c, add(a, scale(ab, u)))) <= 1e-9 * std::sqrt(len2)) return true;
    }
    return false;
  }

  // The normal of vertex v: the sum of its faces' area vectors, each turned by its orientation
  // sign (face_orientations).
  Vec3 oriented_vertex_normal(std::uint32_t v) const {
    Vec3 sum{0.0, 0.0, 0.0};
    for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
      const std::uint32_t e = topo_.vertex_edges[j];
      for (std::uint32_t k = topo_.edge_face_begin[e]; k < topo_.edge_face_begin[e + 1]; ++k) {
        const std::uint32_t t = topo_.edge_faces[k];
        const auto& tri = topo_.tris[t];
        const Vec3 area = cross(sub(topo_.points[tri[1]], topo_.points[tri[0]]),
                                sub(topo_.points[tri[2]], topo_.points[tri[0]]));
        sum = add(sum, scale(area, orientation_[t] < 0 ? -1.0 : 1.0));  // each face twice: no matter
      }
    }
    return unit(sum);
  }

  // The point of the nearest closed obstacle component to `p`, if the scene has one.
  bool nearest_obstacle_point(const Vec3& p, Vec3& out) {
    double best = INFINITY;
    std::map<std::uint32_t, std::unique_ptr<MeshTree>> unused;  // obstacles' trees are kept
    for (std::uint32_t c = 0; c < topo_.component_mesh.size(); ++c) {
      if (movable_component(c) || region_settings_.orientation[c] == 0) continue;
      const MeshTree& tree = component_tree(c, unused);
      if (tree.triangles.empty()) continue;
      const auto q = tree.tree.closest_point(Kernel::Point_3(p[0], p[1], p[2]));
      const Vec3 point{q.x(), q.y(), q.z()};
      const double d = norm(sub(p, point));
      if (d < best) {
        best = d;
        out = point;
      }
    }
    return std::isfinite(best);
  }

  // The order of a pair of layers, decided once from the positions where it is first seen: which
  // component moves (the outer one) and on which side of the other it goes.
  struct LayerOrder {
    bool interleaved = false;  // no clear majority of sides: lay_layer rather than the area rule
    std::uint32_t mover = 0;
    double side = 1.0;  // the mover's side of the other's faces
    // Whether the two layers' face normals mostly agree, or mostly disagree, where they are near
    // (a tie, as between an exact copy and its original, leaves the inner layer's bulges alone).
    bool normals_decided = false;
  };

  LayerOrder decide_layer_order(std::uint32_t a, std::uint32_t b) {
    std::map<std::uint32_t, std::unique_ptr<MeshTree>> trees;
    const MeshTree& tree_a = component_tree(a, trees);
    const MeshTree& tree_b = component_tree(b, trees);
    if (tree_a.triangles.empty() || tree_b.triangles.empty()) return {};
    const double near_a = 0.5 * mean_edge_[topo_.component_mesh[a]];
    const double near_b = 0.5 * mean_edge_[topo_.component_mesh[b]];
    long long vote_a = 0, vote_b = 0;
    const std::vector<NearPoint> a_near = near_points(a, tree_b, near_a, vote_a);
    const std::vector<NearPoint> b_near = near_points(b, tree_a, near_b, vote_b);
    // Around a closed obstacle (a body) the outer layer moves and the inner one stays against the
    // body. Each component's faces near the other face away from the body (their normals point
    // away from its nearest point) mostly on one side, `outward`; the other lies on that side by
    // a margin (its area vote, turned by that sign). Interleaved layers lie on
    // both sides of each other, and from each one's faces the other can look outer (a dress and
    // a t-shirt made at one offset: 746 of 1,240 dress vertices outside the t-shirt's faces, 690
    // of 1,276 t-shirt vertices outside the dress's), so both views are weighed and the one with
    // the larger margin is outer, whichever comes first. The mover is laid on the inner one's
    // outer side. Without an obstacle the component with the higher index moves, to the side
    // most of its near vertices lie on.
    auto outward_of = [&](const std::vector<NearPoint>& near) {
      long long outward = 0;
      for (const NearPoint& x : near) {
        Vec3 body{};
        if (!nearest_obstacle_point(x.c, body)) break;
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
      const double b_outer = area_vote(b_near) * out_a;
      const double a_outer = area_vote(a_near) * out_b;
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
      const double c = dot(oriented_vertex_normal(x.v), x.n);
      aligned += c > 0 ? 1 : c < 0 ? -1 : 0;
    }
    order.normals_decided = aligned != 0;
    // Interleaved: a quarter or more of the near vertices on the minority side.
    const std::size_t near = a_near.size() + b_near.size();
    order.interleaved = near > 0 && 2 * static_cast<std::size_t>(std::llabs(vote_a) + std::llabs(vote_b)) <= near;
    return order;
  }

  // Whether a vertex of one of the contour's crossings (its edge's ends, its face's corners) is a
  // key of `moved`.
  bool touches(const CrossingSet& set, const TracedContour& t,
               const std::map<std::uint32_t, Vec3>& moved) const {
    for (std::uint32_t ci : t.contour.crossings) {
      const RawCrossing& x = set.items[ci];
      for (std::uint32_t v : topo_.edges[x.edge])
        if (moved.count(v)) return true;
      for (std::uint32_t v : topo_.tris[x.face])
        if (moved.count(v)) return true;
    }
    return false;
  }

  // The move one crossing of a layered pair asks for, at most `limit` long, added to `delta`
  // (push_along): a mover edge through an inner face has its ends laid on the face's outer side
  // at the clearance; an inner edge through a mover face pushes that face's corners outward until
  // the edge's ends lie the clearance beneath its plane. Outward is taken from the inner layer's faces each time: the mover's own normals turn
  // over where it folds (a turned-down collar).
  void lay_crossing(const RawCrossing& x, const LayerOrder& order, std::uint32_t inner,
                    double clearance, double limit, std::map<std::uint32_t, Vec3>& delta) const {
    auto push = [&](std::uint32_t v, const Vec3& along, double length) {
      push_along(delta, v, along, std::min(length, limit));
    };
    // Where the mover belongs, seen from face f of the inner layer.
    auto oriented = [&](std::uint32_t f) { return scale(oriented_normal(f), order.side); };
    const auto& tri = topo_.tris[x.face];
    const Vec3& corner = topo_.points[tri[0]];
    if (topo_.tri_component(x.face) == inner) {
      const Vec3 out = oriented(x.face);
      for (std::uint32_t v : topo_.edges[x.edge])
        push(v, out, clearance - dot(sub(topo_.points[v], corner), out));
      return;
    }
    Vec3 out{0.0, 0.0, 0.0};
    for (std::uint32_t k = topo_.edge_face_begin[x.edge]; k < topo_.edge_face_begin[x.edge + 1];
         ++k)
      out = add(out, oriented(topo_.edge_faces[k]));
    out = unit(out);
    Vec3 m = face_normal(topo_, x.face);
    if (dot(m, out) < 0.0) m = scale(m, -1.0);
    const double facing = dot(m, out);
    if (facing < 0.2) return;  // the faces nearly perpendicular: not a layer over another
    double length = 0.0;
    for (std::uint32_t v : topo_.edges[x.edge])
      length = std::max(length, (dot(sub(topo_.points[v], corner), m) + clearance) / facing);
    for (std::uint32_t v : tri) push(v, out, length);
  }

  // Lays the outer component of a layered pair (layered_pairs) on its side of the inner one at
  // the clearance: every vertex of it closer than half an edge and not that far on its side goes
  // to the closest point plus the clearance; the corners of its faces that a vertex of the inner
  // one comes closer to than the clearance (a bulge poking through a flat triangle) move away by
  // the difference; a contour between them that none of these moves touches moves by its
  // crossings (lay_crossing), at most half an edge per step.
  void lay_layer(const CrossingSet& set, const std::vector<TracedContour>& traced, std::uint32_t a,
                 std::uint32_t b, std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
    std::map<std::uint32_t, std::unique_ptr<MeshTree>> trees;
    const MeshTree& tree_a = component_tree(a, trees);
    const MeshTree& tree_b = component_tree(b, trees);
    if (tree_a.triangles.empty() || tree_b.triangles.empty()) return;
    const LayerOrder& order = layer_orders_.at({a, b});
    const std::uint32_t mover = order.mover;
    const std::uint32_t other = mover == a ? b : a;
    const MeshTree& mover_tree = mover == a ? tree_a : tree_b;
    const MeshTree& other_tree = mover == a ? tree_b : tree_a;
    const std::uint32_t mesh = topo_.component_mesh[mover];
    const double clearance = options_.clearance * mean_edge_[mesh];
    long long unused = 0;
    std::map<std::uint32_t, Vec3> delta;  // ordered: the result does not depend on hashing
    const double near = 0.5 * mean_edge_[mesh];
    for (const NearPoint& x : near_points(mover, other_tree, kLayerReach * mean_edge_[mesh], unused)) {
      // Half the clearance is enough to leave a vertex alone (one laid at the clearance stays).
      if (order.side * x.side >= 0.5 * clearance) continue;
      // A vertex on the wrong side whose closest point is the other's hem lies past it (a collar
      // above a lower neckline), not over it: it is left alone. Beyond half an edge only a dip
      // through the other's faces is laid back.
      const bool past_hem = order.side * x.side < 0.0 && on_boundary(x.face, x.c);
      if (past_hem || (norm(sub(topo_.points[x.v], x.c)) > near && order.side * x.side >= 0.0)) continue;
      delta[x.v] = sub(add(x.c, scale(x.n, order.side * clearance)), topo_.points[x.v]);
    }
    if (order.normals_decided) {
      const std::uint32_t other_mesh = topo_.component_mesh[other];
      for (const NearPoint& x :
           near_points(other, mover_tree, 0.5 * mean_edge_[other_mesh], unused)) {
        // Outward is the inner vertex's own normal turned to the mover's side: the mover's face
        // normals turn over where it folds (a turned-down collar), and pushing along them took
        // the collar into the body.
        const Vec3 along = scale(oriented_vertex_normal(x.v), order.side);
        const double gap = dot(sub(x.c, topo_.points[x.v]), along);
        if (gap >= 0.5 * clearance) continue;
        for (std::uint32_t v : topo_.tris[x.face]) push_along(delta, v, along, clearance - gap);
      }
    }
    // Where the layers cross although no vertex above was moved (an edge of one through a face
    // of the other between vertices that each lie on their side of their closest point, over a
    // crease or a spike longer than the reach), the crossings themselves say what moves.
    std::vector<const TracedContour*> untouched;
    for (const TracedContour& t : traced) {
      const std::uint32_t ca = track_component(topo_, set, t, 0);
      const std::uint32_t cb = track_component(topo_, set, t, 1);
      if (std::min(ca, cb) == a && std::max(ca, cb) == b && !touches(set, t, delta))
        untouched.push_back(&t);
    }
    for (const TracedContour* t : untouched)
      for (std::uint32_t ci : t->contour.crossings)
        lay_crossing(set.items[ci], order, other, clearance, near, delta);
    for (const auto& [v, d] : delta) {
      if (!free_[v] || moves.has_region[v]) continue;
      moves.region[v] = d;
      moves.has_region[v] = 1;
      in_moving_set[v] = 1;
    }
  }

  // Two components that cross but where neither side has an illegal region (a garment and an
  // exact or nearly exact copy of it; sheets lying in one plane; a garment lying on an obstacle):
  // the contours separate nothing, so the layers are told apart by index. The movable component
  // with the higher index is laid on the side of the other where most of its near vertices lie
  // (an exact copy: the positive side of the other's face normals) at the clearance, wherever it
  // is closer than half an edge. Layered pairs of movable components go to lay_layer instead.
  void separate_coincident_layers(
      const CrossingSet& set, const std::vector<TracedContour>& traced,
      const std::map<std::pair<std::uint32_t, std::uint32_t>, std::array<std::size_t, 2>>& parallel,
      const std::set<std::pair<std::uint32_t, std::uint32_t>>& layered, const RegionAnalysis& analysis,
      std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
    for (const auto& [key, count] : parallel) {
      const auto [a, b] = key;
      if (layered.count(key)) {
        lay_layer(set, traced, a, b, in_moving_set, moves);
        continue;
      }
      if (2 * count[0] < count[1]) continue;  // surfaces crossing at an angle: not layers
      bool decided = false;
      for (const IllegalSet& s : analysis.illegal)
        if ((s.component == a && s.partner == b) || (s.component == b && s.partner == a)) decided = true;
      if (decided) continue;
      if (!movable_component(a) && !movable_component(b)) continue;
      const std::uint32_t mover = movable_component(b) ? b : a;
      const std::uint32_t other = mover == b ? a : b;
      const std::uint32_t mesh = topo_.component_mesh[mover];
      std::map<std::uint32_t, std::unique_ptr<MeshTree>> trees;
      const MeshTree* tree = &component_tree(other, trees);
      if (tree->triangles.empty()) continue;
      const double clearance = options_.clearance * mean_edge_[mesh];
      long long vote = 0;
      const std::vector<NearPoint> close = near_points(mover, *tree, 0.5 * mean_edge_[mesh], vote);
      const double sign = vote < 0 ? -1.0 : 1.0;
      for (const NearPoint& x : close) {
        if (!free_[x.v] || moves.has_region[x.v] || sign * x.side >= clearance) continue;
        moves.region[x.v] = sub(add(x.c, scale(x.n, sign * clearance)), topo_.points[x.v]);
        moves.has_region[x.v] = 1;
        in_moving_set[x.v] = 1;
      }
    }
  }

  // A patch of one mesh near a contour: `seeds` grown by `rings` rings of neighbours, never into
  // the vertices flagged in `excluded` (indexed v - the mesh's first vertex); `in_sheet` receives
  // the patch's vertices, the result its triangles (all three corners in it), ascending. The cost
  // follows the patch, not the mesh.
  std::vector<std::uint32_t> local_sheet(std::uint32_t mesh, const std::vector<std::uint32_t>& seeds,
                                         const std::vector<std::uint8_t>& excluded, int rings,
                                         std::vector<std::uint8_t>& in_sheet) const {
    const std::uint32_t base = topo_.mesh_vertex_begin[mesh];
    in_sheet.assign(topo_.mesh_vertex_begin[mesh + 1] - base, 0);
    std::vector<std::uint32_t> members;
    auto add = [&](std::uint32_t v) {
      if (in_sheet[v - base] || excluded[v - base]) return;
      in_sheet[v - base] = 1;
      members.push_back(v);
    };
    for (std::uint32_t v : seeds) add(v);
    std::size_t ring_start = 0;
    for (int ring = 0; ring < rings; ++ring) {
      const std::size_t ring_end = members.size();
      for (std::size_t i = ring_start; i < ring_end; ++i) {
        const std::uint32_t v = members[i];
        for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
          add(topo_.vertex_neighbors[j]);
        }
      }
      ring_start = ring_end;
    }
    std::vector<std::uint32_t> tris;
    for (std::uint32_t v : members)
      for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
        const std::uint32_t e = topo_.vertex_edges[j];
        for (std::uint32_t k = topo_.edge_face_begin[e]; k < topo_.edge_face_begin[e + 1]; ++k) {
          const auto& tri = topo_.tris[topo_.edge_faces[k]];
          if (in_sheet[tri[0] - base] && in_sheet[tri[1] - base] && in_sheet[tri[2] - base])
            tris.push_back(topo_.edge_faces[k]);
        }
      }
    std::sort(tris.begin(), tris.end());
    tris.erase(std::unique(tris.begin(), tris.end()), tris.end());
    return tris;
  }

  // Rings from `seeds` to every vertex of `mesh` (indexed v - the mesh's first vertex), counted up
  // to `limit`; farther vertices get limit + 1.
  std::vector<int> ring_distance(std::uint32_t mesh, const std::vector<std::uint32_t>& seeds, int limit) const {
    const std::uint32_t base = topo_.mesh_vertex_begin[mesh];
    std::vector<int> d(topo_.mesh_vertex_begin[mesh + 1] - base, limit + 1);
    std::vector<std::uint32_t> front;
    for (std::uint32_t v : seeds)
      if (d[v - base] != 0) {
        d[v - base] = 0;
        front.push_back(v);
      }
    for (int ring = 1; ring <= limit && !front.empty(); ++ring) {
      std::vector<std::uint32_t> next;
      for (std::uint32_t v : front)
        for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
          const std::uint32_t w = topo_.vertex_neighbors[j];
          if (d[w - base] > ring) {
            d[w - base] = ring;
            next.push_back(w);
          }
        }
      front = std::move(next);
    }
    return d;
  }

  // The corners of the crossings on track k of a contour: endpoints of its crossing edges, corners
  // of the faces the other track's edges pass through; loop vertices left out (where the two sides
  // meet: a barrier, never part of a flap). Ascending.
  std::vector<std::uint32_t> track_corners(const CrossingSet& set, const TracedContour& t, int k) const {
    const Contour& c = t.contour;
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < c.crossings.size(); ++i) {
      const RawCrossing& x = set.items[c.crossings[i]];
      if (t.edge_track[i] == k)
        for (std::uint32_t v : topo_.edges[x.edge]) out.push_back(v);
      else
        for (std::uint32_t v : topo_.tris[x.face]) out.push_back(v);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    out.erase(std::remove_if(out.begin(), out.end(),
                             [&](std::uint32_t v) {
                               return std::find(t.loop_vertex_ids.begin(), t.loop_vertex_ids.end(), v) !=
                                      t.loop_vertex_ids.end();
                             }),
              out.end());
    return out;
  }

  // The pieces of a self contour's track k: its crossing edges cut the component, and the
  // vertices reachable from their endpoints on one side of the other track's faces, without
  // crossing a cut edge or passing a loop vertex, form a piece when they never reach the other
  // side's endpoints and stay within `limit` vertices. Unlike the labels (which combine every
  // contour of the component), a piece follows this track alone: where two self contours cross, the
  // labels split a flap into slivers and the piece is still the whole flap. Each ascending.
  std::vector<std::vector<std::uint32_t>> track_pieces(const CrossingSet& set, const TracedContour& t,
                                                       int k, std::size_t limit) const {
    const Contour& c = t.contour;
    std::vector<std::uint32_t> cut;
    std::vector<std::uint32_t> seeds[2];
    for (std::size_t i = 0; i < c.crossings.size(); ++i) {
      if (t.edge_track[i] != k) continue;
      const RawCrossing& x = set.items[c.crossings[i]];
      const auto& f = topo_.tris[x.face];
      cut.push_back(x.edge);
      for (std::uint32_t v : topo_.edges[x.edge]) {
        if (v == f[0] || v == f[1] || v == f[2]) continue;
        seeds[orient_sos(topo_.points, f[0], f[1], f[2], v) > 0 ? 0 : 1].push_back(v);
      }
    }
    std::sort(cut.begin(), cut.end());
    auto is_loop = [&](std::uint32_t v) {
      return std::find(t.loop_vertex_ids.begin(), t.loop_vertex_ids.end(), v) != t.loop_vertex_ids.end();
    };
    std::vector<std::vector<std::uint32_t>> out;
    for (int s = 0; s < 2; ++s) {
      std::unordered_set<std::uint32_t> other(seeds[1 - s].begin(), seeds[1 - s].end());
      std::unordered_set<std::uint32_t> seen;
      std::vector<std::uint32_t> piece;
      bool ok = true;
      for (std::uint32_t v : seeds[s]) {
        if (other.count(v) || is_loop(v)) {
          ok = false;  // an endpoint on both sides: the cut separates nothing here
          break;
        }
        if (seen.insert(v).second) piece.push_back(v);
      }
      for (std::size_t i = 0; ok && i < piece.size(); ++i) {
        const std::uint32_t v = piece[i];
        for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
          const std::uint32_t w = topo_.vertex_neighbors[j];
          if (std::binary_search(cut.begin(), cut.end(), topo_.vertex_edges[j]) || is_loop(w)) continue;
          if (!seen.insert(w).second) continue;
          if (other.count(w) || piece.size() >= limit) {
            ok = false;  // the piece leaks round the track's end, or is a side of the surface
            break;
          }
          piece.push_back(w);
        }
      }
      if (!ok || piece.empty()) continue;
      std::sort(piece.begin(), piece.end());
      out.push_back(std::move(piece));
    }
    return out;
  }

  // Vertices of `mesh` (indexed v - the mesh's first vertex) on this side of a self contour for
  // the wide patch: this side's corners `own` and every vertex nearer (in rings) to them than to
  // the other track's corners `others`, counted up to `rings`.
  std::vector<std::uint8_t> own_side_of(std::uint32_t mesh, const std::vector<std::uint32_t>& own,
                                        const std::vector<std::uint32_t>& others, int rings) const {
    const std::vector<int> near_own = ring_distance(mesh, own, rings + 1);
    const std::vector<int> near_other = ring_distance(mesh, others, rings + 1);
    std::vector<std::uint8_t> own_side(near_own.size(), 0);
    for (std::size_t i = 0; i < own_side.size(); ++i)
      own_side[i] = near_own[i] == 0 || (near_own[i] < near_other[i] && near_own[i] <= rings + 1) ? 1 : 0;
    return own_side;
  }

  // A contour of a component with itself (a fold through the cloth, a hem's inner layer pushed
  // through its outer layer): the illegal side next to each track, by the component's labels,
  // may move across the sheet of the other track. Every side is measured (TrialMove) against the
  // narrow sheet (the other track's faces at the crossings grown by two rings, the side's own
  // vertices left out) and, when that leaves crossings of this contour, once per step against the
  // wide one (every vertex nearer to the other track than to this side): a side reaching beyond
  // the narrow sheet (a flap of a finely subdivided sheet diving far through its base) finds its
  // closest points on the sheet's rim and would collapse onto it. The move that removes most is made. When none helps, the per-crossing rule
  // acts; when nothing could be measured (the step's budget is spent), the smaller side moves.
  void self_contour_move(const CrossingSet& set, const TracedContour& traced,
                         const RegionAnalysis& analysis, std::vector<std::uint8_t>& in_moving_set,
                         Moves& moves) {
    const std::uint32_t component = track_component(topo_, set, traced, 0);
    if (component != track_component(topo_, set, traced, 1)) return;
    const std::uint32_t mesh = topo_.component_mesh[component];
    if (meshes_[mesh].role != Role::kMovable) return;
    const std::uint32_t base = topo_.mesh_vertex_begin[mesh];
    const std::uint32_t end = topo_.mesh_vertex_begin[mesh + 1];
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
        for (std::uint32_t v : topo_.edges[set.items[c.crossings[i]].edge]) {
          if (illegal[v - base] != 1 || seen[v - base]) continue;
          seen[v - base] = 1;
          side.push_back(v);
        }
      }
      for (std::size_t i = 0; i < side.size(); ++i) {
        const std::uint32_t v = side[i];
        for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
          const std::uint32_t w = topo_.vertex_neighbors[j];
          if (illegal[w - base] == 1 && !seen[w - base]) {
            seen[w - base] = 1;
            side.push_back(w);
          }
        }
      }
      if (side.empty()) continue;
      std::sort(side.begin(), side.end());
      double area = 0.0;
      for (std::uint32_t v : side) area += vertex_edge_[v] * vertex_edge_[v];
      sides.push_back({k, std::move(side), area, nullptr, nullptr});
    }
    if (pieces()) {
      // The second stage: each track's own pieces, as further sides.
      const std::size_t limit = std::min(kMeasuredVertices, component_size_[component] / 2);
      for (int k = 0; k < 2; ++k)
        for (std::vector<std::uint32_t>& piece : track_pieces(set, traced, k, limit)) {
          if (std::any_of(sides.begin(), sides.end(), [&](const Side& s) { return s.vertices == piece; }))
            continue;
          double area = 0.0;
          for (std::uint32_t v : piece) area += vertex_edge_[v] * vertex_edge_[v];
          sides.push_back({k, std::move(piece), area, nullptr, nullptr});
        }
    }
    if (sides.empty()) {
      // Nothing labelled illegal (a fold lying over itself, crossed where it touches): the fold's
      // outer sheet may still be laid outside its inner one.
      Choice fold = fold_layer_choice(set, traced, moves);
      if (fold.gain > 0) make_measured_move(fold, in_moving_set, moves);
      return;
    }

    // The other track's sheet for a side of track k: the faces its crossing edges pass through and
    // the other track's crossing edges, grown by `rings`, never into the moving side nor into
    // `own_side` (the wide patch's limit).
    auto sheet = [&](const Side& side, int rings, const std::vector<std::uint8_t>* own_side) {
      std::vector<std::uint8_t> excluded = own_side != nullptr ? *own_side : std::vector<std::uint8_t>(end - base, 0);
      for (std::uint32_t v : side.vertices) excluded[v - base] = 1;
      std::vector<std::uint32_t> seeds;
      for (std::size_t i = 0; i < c.crossings.size(); ++i) {
        const RawCrossing& x = set.items[c.crossings[i]];
        if (traced.edge_track[i] == side.track) {
          for (std::uint32_t v : topo_.tris[x.face]) seeds.push_back(v);
        } else {
          for (std::uint32_t v : topo_.edges[x.edge]) seeds.push_back(v);
        }
      }
      std::vector<std::uint8_t> in_sheet;
      return build_tree(topo_, local_sheet(mesh, seeds, excluded, rings, in_sheet));
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
    Choice chosen = measured_choice(set, candidates);
    if (chosen.gain < all && !wide_tried_) {
      wide_tried_ = true;
      const int rings = static_cast<int>(component_size_[component]);
      std::vector<std::uint8_t> own_side[2];
      for (int k = 0; k < 2; ++k)
        own_side[k] = own_side_of(mesh, track_corners(set, traced, k), track_corners(set, traced, 1 - k), rings);
      for (Side& side : sides) side.wide = sheet(side, rings, &own_side[side.track]);
      take_better(chosen, measured_choice(set, candidates_of(true)));
    }
    if (chosen.gain <= 0) {
      Choice fold = fold_layer_choice(set, traced, moves);
      if (fold.gain > 0) chosen = std::move(fold);
    }
    if (chosen.gain > 0) {
      make_measured_move(chosen, in_moving_set, moves);
      return;
    }
    if (!chosen.part.empty()) return;  // measured, and no side helps: the per-crossing rule acts
    const Side* smaller = nullptr;
    for (const Side& side : sides)
      if (smaller == nullptr || side.area < smaller->area) smaller = &side;
    if (smaller == nullptr) return;
    for (const Candidate& candidate : candidates) {
      if (candidate.tree != smaller->narrow.get()) continue;
      for (std::uint32_t v : candidate.vertices) in_moving_set[v] = 1;
      move_regions(mesh, 0, candidate.vertices, *candidate.tree, moves);
    }
  }

  // A set of vertices that could move across another surface (`tree`), as a region.
  struct Candidate {
    std::uint32_t mesh;
    int orientation;
    std::vector<std::uint32_t> vertices;
    const MeshTree* tree;
  };
  struct Choice {
    long long gain = std::numeric_limits<long long>::min();  // crossings removed
    double strain = INFINITY;
    std::vector<std::uint32_t> part;
    std::vector<Vec3> delta;
    std::vector<Vec3> at;  // the part's positions after the move
  };

  // A fold of one component lying over itself near a closed obstacle (a turned-down collar over
  // its neck band, a hem turned up inside a skirt), crossed where the two sheets touch: the region
  // rules see no illegal side there, and the per-crossing rule shears the fold into the body. The
  // contour's two sheets are laid one outside the other instead, outward meaning away from the
  // nearest closed obstacle: an outer edge through an inner face has its ends laid outside the
  // face at the clearance, an inner edge through an outer face pushes that face's corners out until
  // the edge lies the clearance beneath it (as lay_crossing does for two layers), at most half an
  // edge per vertex. Each track is tried as the inner one; the move is measured (TrialMove) and the
  // one that removes most crossings is returned (none when the scene has no closed obstacle).
  Choice fold_layer_choice(const CrossingSet& set, const TracedContour& traced, const Moves& moves) {
    Choice best;
    const Contour& c = traced.contour;
    if (c.crossings.empty()) return best;
    const std::uint32_t mesh = topo_.tri_mesh[set.items[c.crossings[0]].face];
    const double clearance = options_.clearance * mean_edge_[mesh];
    const double limit = 0.5 * mean_edge_[mesh];
    // Away from the body at each crossing.
    std::vector<Vec3> outward;
    for (std::uint32_t ci : c.crossings) {
      Vec3 body{};
      if (!nearest_obstacle_point(set.items[ci].point, body)) return best;
      outward.push_back(unit(sub(set.items[ci].point, body)));
    }
    // face_normal(t) turned to agree with o.
    auto facing = [&](std::uint32_t t, const Vec3& o) {
      const Vec3 n = face_normal(topo_, t);
      return dot(n, o) < 0.0 ? scale(n, -1.0) : n;
    };
    for (int inner = 0; inner < 2; ++inner) {
      std::map<std::uint32_t, Vec3> delta;  // ordered: the result does not depend on hashing
      auto push = [&](std::uint32_t v, const Vec3& along, double length) {
        push_along(delta, v, along, std::min(length, limit));
      };
      for (std::size_t i = 0; i < c.crossings.size(); ++i) {
        const RawCrossing& x = set.items[c.crossings[i]];
        const auto& tri = topo_.tris[x.face];
        const Vec3& corner = topo_.points[tri[0]];
        if (traced.edge_track[i] != inner) {
          const Vec3 out = facing(x.face, outward[i]);
          for (std::uint32_t v : topo_.edges[x.edge])
            push(v, out, clearance - dot(sub(topo_.points[v], corner), out));
          continue;
        }
        Vec3 out{0.0, 0.0, 0.0};
        for (std::uint32_t k = topo_.edge_face_begin[x.edge]; k < topo_.edge_face_begin[x.edge + 1]; ++k)
          out = add(out, facing(topo_.edge_faces[k], outward[i]));
        out = unit(out);
        const Vec3 m = facing(x.face, out);
        const double cosine = dot(m, out);
        if (cosine < 0.2) continue;  // the sheets nearly perpendicular: not a fold lying over itself
        double length = 0.0;
        for (std::uint32_t v : topo_.edges[x.edge])
          length = std::max(length, (dot(sub(topo_.points[v], corner), m) + clearance) / cosine);
        for (std::uint32_t v : tri) push(v, out, length);
      }
      Choice option;
      option.strain = 0.0;
      for (const auto& [v, d] : delta) {
        if (!free_[v] || measured_[v] || moves.has_region[v]) continue;
        Vec3 at = add(topo_.points[v], d);
        if (round_) at = round_(at);
        if (at == topo_.points[v]) continue;
        option.part.push_back(v);
        option.delta.push_back(sub(at, topo_.points[v]));
        option.at.push_back(at);
      }
      if (option.part.empty() || 3 * option.part.size() > trial_budget_) continue;
      trial_budget_ -= 3 * option.part.size();
      const TrialCount count = trial_->count(settings_, *hierarchy_, set, option.part, option.at, true);
      option.gain = static_cast<long long>(count.before) - static_cast<long long>(count.after);
      if (option.gain > best.gain) best = std::move(option);
    }
    return best;
  }

  // Makes a measured move and lets later measurements in this step see it.
  void make_measured_move(const Choice& chosen, std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
    for (std::uint32_t v : chosen.part) in_moving_set[v] = measured_[v] = 1;
    measured_list_.insert(measured_list_.end(), chosen.part.begin(), chosen.part.end());
    add_region_move(chosen.part, chosen.delta, moves);
    trial_->commit(chosen.part, chosen.at);
  }

  // Every connected part of every candidate with every move of part_moves, counted exactly
  // (TrialMove): the one that removes most crossings, the least strain breaking ties.
  Choice measured_choice(const CrossingSet& set, const std::vector<Candidate>& candidates) {
    Choice chosen;
    for (const Candidate& candidate : candidates) {
      // Measuring a move costs about what re-detecting the triangles it touches does, the budget's
      // unit (some two per vertex, three with the ring around). A step measures at most a few
      // detections' worth, in contour order; sets larger than kMeasuredVertices (a side of a
      // sheet rather than a flap) go unmeasured.
      if (candidate.vertices.size() > kMeasuredVertices || 3 * candidate.vertices.size() > trial_budget_) continue;
      for (PartMoves& p : part_moves(candidate.mesh, candidate.orientation, candidate.vertices, *candidate.tree)) {
        // A vertex moves once per step: parts with a vertex a measured move already took wait.
        if (std::any_of(p.part.begin(), p.part.end(), [&](std::uint32_t v) { return measured_[v] != 0; }))
          continue;
        for (std::size_t o = 0; o < p.options.size(); ++o) {
          if (3 * p.part.size() > trial_budget_) break;
          trial_budget_ -= 3 * p.part.size();
          std::vector<Vec3> at(p.part.size());
          for (std::size_t i = 0; i < p.part.size(); ++i) {
            at[i] = add(topo_.points[p.part[i]], p.options[o][i]);
            if (round_) at[i] = round_(at[i]);
          }
          const TrialCount count = trial_->count(settings_, *hierarchy_, set, p.part, at, true);
          const long long gain = static_cast<long long>(count.before) - static_cast<long long>(count.after);
          if (gain > chosen.gain || (gain == chosen.gain && p.strain[o] < chosen.strain)) {
            chosen.gain = gain;
            chosen.strain = p.strain[o];
            chosen.part = p.part;
            chosen.delta = p.options[o];
            chosen.at = at;
          }
        }
      }
    }
    return chosen;
  }

  // One connected part of a set to move and its candidate displacements (per vertex of `part`,
  // ascending), each with its strain.
  struct PartMoves {
    std::vector<std::uint32_t> part;
    std::vector<std::vector<Vec3>> options;
    std::vector<double> strain;
    std::size_t least_strain() const {
      return static_cast<std::size_t>(std::min_element(strain.begin(), strain.end()) - strain.begin());
    }
  };

  // Moves every connected part of an illegal set across the partner surface by the candidate that
  // strains the part's edges least (part_moves).
  void move_regions(std::uint32_t mesh, int orientation, const std::vector<std::uint32_t>& vertices,
                    const MeshTree& tree, Moves& moves) {
    for (const PartMoves& p : part_moves(mesh, orientation, vertices, tree))
      add_region_move(p.part, p.options[p.least_strain()], moves);
  }

  void add_region_move(const std::vector<std::uint32_t>& part, const std::vector<Vec3>& delta, Moves& moves) {
    for (std::size_t i = 0; i < part.size(); ++i) {
      moves.region[part[i]] = add(moves.region[part[i]], delta[i]);
      moves.has_region[part[i]] = 1;
    }
  }

  // The connected parts of a set and, for each, the candidate moves across the partner surface:
  //  - to the closest point of the partner, plus the clearance (a thin layer stays thin);
  //  - mirrored through that closest point (a part sticking far through folds back, keeping its
  //    shape instead of collapsing onto the surface);
  //  - along the part's own normal to where that ray leaves the partner, either way (a sheet cut
  //    through the middle of a closed body bulges over it instead of being squeezed sideways).
  std::vector<PartMoves> part_moves(std::uint32_t mesh, int orientation,
                                    const std::vector<std::uint32_t>& vertices, const MeshTree& tree) {
    std::vector<PartMoves> out;
    if (tree.triangles.empty()) return out;
    const double clearance = options_.clearance * mean_edge_[mesh];
    // Scratch flags and normals indexed by welded vertex, cleared again before returning: the
    // cost follows the set, not the mesh.
    std::vector<std::uint8_t>& member = member_;
    for (std::uint32_t v : vertices) member[v] = 1;

    // Vertex normals (area weighted) at the set and its neighbours, from the triangles it touches
    // in ascending order.
    const std::vector<std::uint32_t> touching = topo_.triangles_at(vertices);
    std::vector<Vec3>& normal = normal_;
    for (std::uint32_t t : touching) {
      const auto& tri = topo_.tris[t];
      const Vec3 n = cross(sub(topo_.points[tri[1]], topo_.points[tri[0]]),
                           sub(topo_.points[tri[2]], topo_.points[tri[0]]));
      for (std::uint32_t v : tri) normal[v] = add(normal[v], n);
    }
    std::vector<std::uint8_t>& seen = seen_;

    // Connected parts of the set.
    for (std::uint32_t seed : vertices) {
      if (seen[seed]) continue;
      std::vector<std::uint32_t> part{seed};
      seen[seed] = 1;
      for (std::size_t i = 0; i < part.size(); ++i) {
        const std::uint32_t v = part[i];
        for (std::uint32_t k = topo_.vertex_edge_begin[v]; k < topo_.vertex_edge_begin[v + 1]; ++k) {
          const std::uint32_t w = topo_.vertex_neighbors[k];
          if (member[w] && !seen[w]) {
            seen[w] = 1;
            part.push_back(w);
          }
        }
      }
      std::sort(part.begin(), part.end());

      const std::size_t n = part.size();
      std::vector<Vec3> closest(n), mirror(n), ray_up(n), ray_down(n), across(n);
      bool up_ok = true, down_ok = true, across_differs = false;
      for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = topo_.points[part[i]];
        const Kernel::Point_3 query(p[0], p[1], p[2]);
        const auto hit = tree.tree.closest_point_and_primitive(query);
        const Vec3 c{hit.first.x(), hit.first.y(), hit.first.z()};
        const std::uint32_t face =
            tree.ids[static_cast<std::size_t>(hit.second - tree.triangles.begin())];
        const Vec3 to = sub(c, p);
        Vec3 dir = unit(to);
        if (norm(to) == 0.0) dir = scale(face_normal(topo_, face), orientation >= 0 ? 1.0 : -1.0);
        closest[i] = add(to, scale(dir, clearance));
        const Vec3 nv = unit(normal[part[i]]);
        // A part mirrored through a flat partner may land in the plane of its own mesh (a flat
        // strip folded onto itself): the clearance along its own normal keeps the fold open.
        mirror[i] = add(add(scale(to, 2.0), scale(dir, clearance)), scale(nv, clearance));
        if (pieces()) {
          // Reflected across the plane of the closest face: the same as mirrored where the
          // closest point lies inside the face; beyond the partner's edge the part turns round
          // the edge instead of onto it.
          const Vec3 nf = face_normal(topo_, face);
          const Vec3 to_plane = scale(nf, dot(nf, sub(topo_.points[topo_.tris[face][0]], p)));
          Vec3 side = unit(to_plane);
          if (norm(to_plane) == 0.0) side = dir;
          across[i] = add(add(scale(to_plane, 2.0), scale(side, clearance)), scale(nv, clearance));
          across_differs = across_differs || across[i] != mirror[i];
        }
        for (int sign : {1, -1}) {
          bool& ok = sign > 0 ? up_ok : down_ok;
          if (!ok) continue;
          const Vec3 d = scale(nv, sign);
          if (norm(d) == 0.0) {
            ok = false;
            continue;
          }
          const auto exit = tree.tree.first_intersection(
              Kernel::Ray_3(query, Kernel::Vector_3(d[0], d[1], d[2])));
          const Kernel::Point_3* point = nullptr;
          if (exit) point = boost::get<Kernel::Point_3>(&exit->first);
          if (point == nullptr) {
            ok = false;
            continue;
          }
          const Vec3 x{point->x(), point->y(), point->z()};
          (sign > 0 ? ray_up : ray_down)[i] = add(sub(x, p), scale(d, clearance));
        }
      }
      PartMoves p;
      p.options.push_back(std::move(closest));
      p.options.push_back(std::move(mirror));
      if (up_ok) p.options.push_back(std::move(ray_up));
      if (down_ok) p.options.push_back(std::move(ray_down));
      if (across_differs) p.options.push_back(std::move(across));
      for (const std::vector<Vec3>& option : p.options) p.strain.push_back(strain(part, member, 0, option));
      p.part = std::move(part);
      out.push_back(std::move(p));
    }
    for (std::uint32_t v : vertices) member[v] = seen[v] = 0;
    for (std::uint32_t t : touching)
      for (std::uint32_t v : topo_.tris[t]) normal[v] = Vec3{0, 0, 0};
    return out;
  }

  // How much a candidate move of `part` strains the mesh: relative length change of every edge
  // touching the part, plus a heavy penalty for each triangle it collapses.
  double strain(const std::vector<std::uint32_t>& part, const std::vector<std::uint8_t>& member,
                std::uint32_t base, const std::vector<Vec3>& delta) const {
    auto moved = [&](std::uint32_t v) {
      if (!member[v - base]) return topo_.points[v];
      const auto it = std::lower_bound(part.begin(), part.end(), v);
      if (it == part.end() || *it != v) return topo_.points[v];  // another part: unchanged here
      return add(topo_.points[v], delta[static_cast<std::size_t>(it - part.begin())]);
    };
    double score = 0.0;
    for (std::uint32_t v : part) {
      for (std::uint32_t k = topo_.vertex_edge_begin[v]; k < topo_.vertex_edge_begin[v + 1]; ++k) {
        const std::uint32_t e = topo_.vertex_edges[k];
        const auto& ed = topo_.edges[e];
        const double before = norm(sub(topo_.points[ed[0]], topo_.points[ed[1]]));
        const double after = norm(sub(moved(ed[0]), moved(ed[1])));
        if (before > 0.0) score += std::abs(after - before) / before;
        for (std::uint32_t i = topo_.edge_face_begin[e]; i < topo_.edge_face_begin[e + 1]; ++i) {
          const auto& tri = topo_.tris[topo_.edge_faces[i]];
          const double a0 = norm(cross(sub(topo_.points[tri[1]], topo_.points[tri[0]]),
                                       sub(topo_.points[tri[2]], topo_.points[tri[0]])));
          const Vec3 q0 = moved(tri[0]);
          const double a1 = norm(cross(sub(moved(tri[1]), q0), sub(moved(tri[2]), q0)));
          if (a1 < 0.05 * a0) score += 5.0;
        }
      }
    }
    return score;
  }

  // A BI/BI contour between two components (two sheets overlapping at a corner, a sleeve's cuff
  // through a hem) separates nothing, so no region holds its labels; the paper slides it toward the
  // other mesh's boundary one small step per iteration, which takes about one iteration per
  // crossing and, being a shear of both meshes, is sensitive to rounding. Here the contour's flap
  // moves instead: on each side of the contour, the vertices next to it that lie on one side of the
  // other surface and over it (their closest point on it is not on its boundary), grown from the
  // crossing edges. Each flap's parts and their candidate moves across the other surface are
  // measured (TrialMove, exact): the move that removes most crossings is made. When none removes
  // any, the flap with the least area moves as a region. What remains near the boundary goes to
  // the per-crossing rule.
  //
  // A contour of one component with itself that separates nothing (a flap of a sheet through its
  // own base across the base's edge, contours through loop vertices) is treated the same way, with
  // a local patch as "the other surface": the other track's faces and edges at the crossings,
  // grown by a few rings, never into this side's own crossing corners; its rim counts as boundary.
  // A loop vertex (where the two tracks meet) is a barrier: never in a flap, never crossed by its
  // growth (the flap of a contour that only touches one elsewhere must not take the pinch along).
  // A contour through a loop vertex moves a flap only when the measurement says it helps, and is
  // otherwise left to the per-crossing rule: unmeasured flaps next to a pinch resolved the small
  // figure-eight and loop-to-loop cases but left more crossings on the MakeHuman garments
  // (casualsuit01 at x1.02: 174 -> 336).
  void flap_move(const CrossingSet& set, const TracedContour& t,
                 std::map<std::uint32_t, std::unique_ptr<MeshTree>>& trees,
                 std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
    const Contour& c = t.contour;
    if (c.closed) return;
    const std::uint32_t components[2] = {track_component(topo_, set, t, 0),
                                         track_component(topo_, set, t, 1)};
    const bool self = components[0] == components[1];
    // A track that separates but cuts no edge encloses no vertex (a sliver of a base's edge inside
    // a flap's triangles): self_contour_move finds no side there. The second stage gives such a
    // contour a flap too.
    auto separates_vertices = [&](const Track& track) {
      return track.separates && (!pieces() || track.cut_edges > 0);
    };
    if (self) {
      if (separates_vertices(c.tracks[0]) || separates_vertices(c.tracks[1])) return;  // self_contour_move's case
    } else if (c.tracks[0].type != TrackType::kBI || c.tracks[1].type != TrackType::kBI) {
      return;
    }
    for (std::uint32_t ci : c.crossings) {
      const RawCrossing& x = set.items[ci];
      for (std::uint32_t v : topo_.edges[x.edge])
        if (in_moving_set[v]) return;
      for (std::uint32_t v : topo_.tris[x.face])
        if (in_moving_set[v]) return;
    }
    auto corners_of = [&](int k) { return track_corners(set, t, k); };
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
        const std::uint32_t mesh = topo_.component_mesh[own];
        if (meshes_[mesh].role != Role::kMovable) continue;
        const std::vector<std::uint32_t> seeds = corners_of(k);
        std::set<std::pair<std::uint32_t, std::uint32_t>> rim;  // a self patch's edges of one face
        std::vector<std::uint8_t> in_patch;
        const std::uint32_t base = topo_.mesh_vertex_begin[mesh];
        if (self) {
          const int rings = wide ? static_cast<int>(component_size_[own]) : kPatchRings;
          // The patch never reaches this side's corners, nor vertices nearer (in rings) to them than
          // to the other track's corners: on a sheet folded at a loop vertex the two sides are
          // joined, and the patch must not grow over the fold into the flap it is to judge.
          const std::vector<std::uint32_t> others = corners_of(1 - k);
          const std::vector<std::uint32_t> tris =
              local_sheet(mesh, others, own_side_of(mesh, seeds, others, rings), rings, in_patch);
          std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
          for (std::uint32_t f : tris) {
            const auto& tri = topo_.tris[f];
            for (int e = 0; e < 3; ++e)
              ++uses[{std::min(tri[e], tri[(e + 1) % 3]), std::max(tri[e], tri[(e + 1) % 3])}];
          }
          if (tris.empty()) continue;
          for (const auto& [edge, count] : uses)
            if (count == 1) rim.insert(edge);
          patches[wide][k] = build_tree(topo_, tris);
        }
        const MeshTree& tree = self ? *patches[wide][k] : component_tree(other, trees);
        if (tree.triangles.empty()) continue;
        auto beyond_edge = [&](std::uint32_t a, std::uint32_t b) {
          if (self) return rim.count({std::min(a, b), std::max(a, b)}) > 0;
          return topo_.is_boundary(topo_.find_edge(a, b));
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
          const Vec3& p = topo_.points[v];
          const auto hit = tree.tree.closest_point_and_primitive(Kernel::Point_3(p[0], p[1], p[2]));
          const std::uint32_t face =
              tree.ids[static_cast<std::size_t>(hit.second - tree.triangles.begin())];
          const auto& f = topo_.tris[face];
          const Vec3 q{hit.first.x(), hit.first.y(), hit.first.z()};
          // A corner of the closest face lies on the other surface (a fold vertex shared by both
          // sides of a sheet).
          int result = f[0] == v || f[1] == v || f[2] == v ? 0 : orient_sos(topo_.points, f[0], f[1], f[2], v);
          // In the second stage a vertex beyond the other surface's edge keeps the side of the
          // closest face's plane: the part of a flap that dives beyond a base's edge moves with the
          // flap, instead of holding its triangles through the edge (reflected across that plane).
          for (int e = 0; e < 3 && result != 0 && !pieces(); ++e) {
            // Closest point on edge (f[e], f[e+1]) of the other surface's boundary: not over it.
            const Vec3& a = topo_.points[f[e]];
            const Vec3& b = topo_.points[f[(e + 1) % 3]];
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
        const std::size_t component_size = component_size_[own];
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
            for (std::uint32_t e = topo_.vertex_edge_begin[v]; e < topo_.vertex_edge_begin[v + 1]; ++e) {
              const std::uint32_t w = topo_.vertex_neighbors[e];
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
            any_free = any_free || free_[v];
            area += vertex_edge_[v] * vertex_edge_[v];
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
          out.push_back({topo_.component_mesh[components[flap.track]],
                         self ? 0 : region_settings_.orientation[components[1 - flap.track]],
                         flap.vertices, flap.tree});
      return out;
    };
    collect(0);
    const std::vector<Candidate> candidates = candidates_of(false);
    Choice chosen = measured_choice(set, candidates);
    // A self contour whose narrow patch offers no helpful flap (a flap of a finely subdivided
    // sheet reaches beyond it) tries the wide patch, within the step's budget.
    // Building a wide patch walks and indexes about half the component: one per step.
    if (self && chosen.gain <= 0 && !wide_tried_) {
      wide_tried_ = true;
      collect(1);
      Choice wide = measured_choice(set, candidates_of(true));
      if (!wide.part.empty() && wide.gain > 0) chosen = std::move(wide);
    }
    if (candidates.empty() && chosen.part.empty()) return;
    // A move that adds crossings is never made; one that changes nothing only on a contour
    // without a loop vertex (it slides toward the boundary). Otherwise the per-crossing rule acts.
    if (!chosen.part.empty()) {
      if (chosen.gain < 0 || (chosen.gain == 0 && c.loop_vertices > 0)) return;
      make_measured_move(chosen, in_moving_set, moves);
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
    move_regions(smallest.mesh, smallest.orientation, smallest.vertices, *smallest.tree, moves);
  }

  // The per-crossing rule's step for one contour, measured (TrialMove) and made when it removes
  // crossings: a pinch between two triangles next to a moved flap is undone, a shear that would
  // tangle a fold further is not made. When the step removes nothing, the contour's neighbourhood
  // relaxed (relax_choice) is made if it does.
  void measured_crossing_move(const CrossingSet& set, const TracedContour& t, const RegionAnalysis& analysis,
                              std::vector<std::uint8_t>& in_moving_set, Moves& moves) {
    if (!crossing_scratch_) crossing_scratch_ = std::make_unique<Moves>(topo_.points.size());
    Moves& scratch = *crossing_scratch_;
    crossing_moves(set, t, analysis, scratch);
    std::vector<std::uint32_t> touched;
    for (std::uint32_t ci : t.contour.crossings) {
      const RawCrossing& x = set.items[ci];
      for (std::uint32_t v : topo_.edges[x.edge]) touched.push_back(v);
      for (std::uint32_t v : topo_.tris[x.face]) touched.push_back(v);
    }
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    Choice step;
    for (std::uint32_t v : touched) {
      if (scratch.crossing_count[v] == 0 || !free_[v] || measured_[v] || moves.has_region[v]) continue;
      Vec3 at = add(topo_.points[v], crossing_step(scratch, v));
      if (round_) at = round_(at);
      if (at == topo_.points[v]) continue;
      step.part.push_back(v);
      step.delta.push_back(sub(at, topo_.points[v]));
      step.at.push_back(at);
    }
    for (std::uint32_t v : touched) {
      scratch.crossing[v] = Vec3{0, 0, 0};
      scratch.crossing_count[v] = 0;
    }
    // The step; when it removes nothing, the neighbourhood relaxed.
    Choice chosen;
    if (!step.part.empty() && 3 * step.part.size() <= trial_budget_) {
      trial_budget_ -= 3 * step.part.size();
      const TrialCount count = trial_->count(settings_, *hierarchy_, set, step.part, step.at, true);
      step.gain = static_cast<long long>(count.before) - static_cast<long long>(count.after);
      chosen = std::move(step);
    }
    if (chosen.gain <= 0) chosen = relax_choice(set, touched, moves);
    if (chosen.gain > 0) make_measured_move(chosen, in_moving_set, moves);
  }

  // Whether one side of a contour is an obstacle (its crossings all join the same two components).
  bool touches_obstacle(const CrossingSet& set, const Contour& c) const {
    if (c.crossings.empty()) return false;
    const RawCrossing& x = set.items[c.crossings.front()];
    return meshes_[topo_.tri_mesh[x.face]].role == Role::kObstacle ||
           meshes_[topo_.edge_mesh(x.edge)].role == Role::kObstacle;
  }

  bool on_boundary(std::uint32_t v) const {
    for (std::uint32_t k = topo_.vertex_edge_begin[v]; k < topo_.vertex_edge_begin[v + 1]; ++k)
      if (topo_.is_boundary(topo_.vertex_edges[k])) return true;
    return false;
  }

  // The neighbourhood of a contour relaxed: the contour's vertices (`seeds`, ascending) grown by 0
  // to kRelaxRings rings, each vertex moved kRelaxSweeps times halfway to the mean of its
  // neighbours (a boundary vertex to that of its boundary neighbours, so a rim stays a rim), the
  // ring around held. Where a fine sheet was pressed into a sliver or pinched through a loop
  // vertex, no side or crossing step helps; relaxing the crumpled triangles opens them again.
  // Each size is measured (TrialMove); the one that removes most crossings is returned.
  Choice relax_choice(const CrossingSet& set, const std::vector<std::uint32_t>& seeds, const Moves& moves) {
    Choice best;
    std::vector<std::uint32_t> region = seeds;  // ascending
    std::vector<std::uint32_t> front = seeds;
    for (int rings = 0; rings <= kRelaxRings; ++rings) {
      if (rings > 0) {
        std::vector<std::uint32_t> next;
        for (std::uint32_t v : front)
          for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j)
            next.push_back(topo_.vertex_neighbors[j]);
        std::sort(next.begin(), next.end());
        next.erase(std::unique(next.begin(), next.end()), next.end());
        front.clear();
        std::set_difference(next.begin(), next.end(), region.begin(), region.end(), std::back_inserter(front));
        if (front.empty()) break;
        std::vector<std::uint32_t> grown;
        std::merge(region.begin(), region.end(), front.begin(), front.end(), std::back_inserter(grown));
        region = std::move(grown);
      }
      std::vector<std::uint32_t> part;  // ascending
      for (std::uint32_t v : region)
        if (free_[v] && !measured_[v] && !moves.has_region[v]) part.push_back(v);
      if (part.empty() || 3 * part.size() > trial_budget_ || 3 * part.size() > relax_budget_) continue;
      std::vector<Vec3> at(part.size());
      for (std::size_t i = 0; i < part.size(); ++i) at[i] = topo_.points[part[i]];
      auto position = [&](const std::vector<Vec3>& now, std::uint32_t w) {
        const auto it = std::lower_bound(part.begin(), part.end(), w);
        return it != part.end() && *it == w ? now[static_cast<std::size_t>(it - part.begin())] : topo_.points[w];
      };
      for (int sweep = 0; sweep < kRelaxSweeps; ++sweep) {
        std::vector<Vec3> next(part.size());
        for (std::size_t i = 0; i < part.size(); ++i) {
          const std::uint32_t v = part[i];
          const bool rim = on_boundary(v);
          Vec3 sum{0.0, 0.0, 0.0};
          int count = 0;
          for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
            if (rim && !topo_.is_boundary(topo_.vertex_edges[j])) continue;
            sum = add(sum, position(at, topo_.vertex_neighbors[j]));
            ++count;
          }
          next[i] = count > 0 ? add(scale(at[i], 0.5), scale(sum, 0.5 / count)) : at[i];
        }
        at = std::move(next);
      }
      Choice option;
      option.strain = 0.0;
      for (std::size_t i = 0; i < part.size(); ++i) {
        Vec3 to = at[i];
        if (round_) to = round_(to);
        if (to == topo_.points[part[i]]) continue;
        option.part.push_back(part[i]);
        option.delta.push_back(sub(to, topo_.points[part[i]]));
        option.at.push_back(to);
      }
      if (option.part.empty()) continue;
      trial_budget_ -= 3 * option.part.size();
      relax_budget_ -= 3 * option.part.size();
      const TrialCount count = trial_->count(settings_, *hierarchy_, set, option.part, option.at, true);
      option.gain = static_cast<long long>(count.before) - static_cast<long long>(count.after);
      if (option.gain > best.gain) best = std::move(option);
    }
    return best;
  }

  // Label of welded vertex v with respect to component `partner` (-1 undecided).
  int label(const RegionAnalysis& analysis, std::uint32_t v, std::uint32_t partner) const {
    const std::uint32_t component = topo_.vertex_component[v];
    auto it = analysis.labels.find({component, partner});
    if (it == analysis.labels.end()) return -1;
    return it->second[v - topo_.mesh_vertex_begin[topo_.component_mesh[component]]];
  }

  void crossing_moves(const CrossingSet& set, const TracedContour& t, const RegionAnalysis& analysis,
                      Moves& moves) {
    const Contour& c = t.contour;
    const std::size_t n = c.crossings.size();
    // Which end of an open contour lies on each mesh's boundary (for the BI rule).
    auto end_on_boundary_of = [&](std::size_t index, std::uint32_t mesh) {
      const RawCrossing& x = set.items[c.crossings[index]];
      return topo_.is_boundary(x.edge) && topo_.edge_mesh(x.edge) == mesh;
    };
    for (std::size_t i = 0; i < n; ++i) {
      const RawCrossing& x = set.items[c.crossings[i]];
      const std::uint32_t q_mesh = topo_.tri_mesh[x.face];
      const std::uint32_t a = topo_.edges[x.edge][0], b = topo_.edges[x.edge][1];
      const auto& f = topo_.tris[x.face];
      // Unit vectors from x to its neighbours on the contour.
      Vec3 r_prev{0, 0, 0}, r_next{0, 0, 0};
      if (i > 0 || c.closed) r_prev = unit(sub(set.items[c.crossings[(i + n - 1) % n]].point, x.point));
      if (i + 1 < n || c.closed) r_next = unit(sub(set.items[c.crossings[(i + 1) % n]].point, x.point));
      const Vec3 in_plane = scale(add(r_prev, r_next), options_.lambda);
      const double local = 0.5 * (norm(sub(topo_.points[a], topo_.points[b])) +
                                  mean_edge_[q_mesh]);
      const double len = options_.step * local;

      Vec3 d{0, 0, 0};
      bool face_side = false;  // the face's mesh holds the labels: it moves along +d
      const std::uint32_t p_component = topo_.vertex_component[a];
      const std::uint32_t q_component = topo_.tri_component(x.face);
      const int la = label(analysis, a, q_component);
      const int lb = label(analysis, b, q_component);
      int f_legal = 0, f_illegal = 0;
      Vec3 f_legal_sum{0, 0, 0};
      for (std::uint32_t v : f) {
        const int l = label(analysis, v, p_component);
        if (l == 0) {
          ++f_legal;
          f_legal_sum = add(f_legal_sum, topo_.points[v]);
        }
        if (l == 1) ++f_illegal;
      }
      const Vec3 nf = face_normal(topo_, x.face);
      const int q_orientation = region_settings_.orientation[q_component];
      if (la >= 0 && lb >= 0 && la != lb) {
        // e has a legal endpoint: n_r is f's normal turned toward it (Eq. 1).
        const std::uint32_t legal = la == 0 ? a : b;
        const int s = orient_sos(topo_.points, f[0], f[1], f[2], legal);
        d = add(scale(nf, s), in_plane);
      } else if (f_legal > 0 && f_illegal > 0) {
        // The face side holds the illegal region: the normal of P near e, toward f's legal side.
        Vec3 ne{0, 0, 0};
        for (std::uint32_t k = topo_.edge_face_begin[x.edge]; k < topo_.edge_face_begin[x.edge + 1]; ++k)
          ne = add(ne, face_normal(topo_, topo_.edge_faces[k]));
        ne = unit(ne);
        const Vec3 toward = sub(scale(f_legal_sum, 1.0 / f_legal), x.point);
        d = add(scale(ne, dot(ne, toward) >= 0 ? 1.0 : -1.0), in_plane);
        face_side = true;
      } else if (!c.self && q_orientation != 0 && options_.outside_closed_obstacles &&
                 meshes_[q_mesh].role == Role::kObstacle) {
        // A closed obstacle: e's endpoint outside it is the legal one.
        const int s = orient_sos(topo_.points, f[0], f[1], f[2], a) * q_orientation;
        const std::uint32_t legal = s > 0 ? a : b;
        d = add(scale(nf, orient_sos(topo_.points, f[0], f[1], f[2], legal)), in_plane);
      } else if (!c.closed && !c.self &&
                 ((end_on_boundary_of(0, q_mesh)) || end_on_boundary_of(n - 1, q_mesh))) {
        // BI rule: slide e toward the end of the contour on the other mesh's boundary.
        d = end_on_boundary_of(n - 1, q_mesh) ? r_next : r_prev;
        if (norm(d) == 0.0) d = end_on_boundary_of(n - 1, q_mesh) ? scale(r_prev, -1.0) : scale(r_next, -1.0);
      } else {
        // Nothing decides: the shallower endpoint of e is taken as the one that went through.
        const double da = std::abs(dot(nf, sub(topo_.points[a], topo_.points[f[0]])));
        const double db = std::abs(dot(nf, sub(topo_.points[b], topo_.points[f[0]])));
        const std::uint32_t legal = da < db ? b : a;
        d = add(scale(nf, orient_sos(topo_.points, f[0], f[1], f[2], legal)), in_plane);
      }
      d = scale(unit(d), len);
      // Action and reaction, split by mass: obstacles and pinned vertices take nothing.
      bool e_free = free_[a] || free_[b];
      bool f_free = free_[f[0]] || free_[f[1]] || free_[f[2]];
      double we = e_free ? (f_free ? 0.5 : 1.0) : 0.0;
      double wf = f_free ? (e_free ? 0.5 : 1.0) : 0.0;
      const Vec3 de = scale(d, face_side ? -we : we);
      const Vec3 df = scale(d, face_side ? wf : -wf);
      for (std::uint32_t v : {a, b})
        if (free_[v]) moves.push(v, de);
      for (std::uint32_t v : f)
        if (free_[v]) moves.push(v, df);
    }
  }

  // Vertex v's per-crossing step: the mean of its crossing moves, at most max_step times its mean
  // incident edge length.
  Vec3 crossing_step(const Moves& moves, std::uint32_t v) const {
    const Vec3 d = scale(moves.crossing[v], 1.0 / moves.crossing_count[v]);
    const double len = norm(d), cap = options_.max_step * vertex_edge_[v];
    return len > cap ? scale(d, cap / len) : d;
  }

  // Applies the moves with a per-vertex cap and a guard against inverted triangles.
  bool apply(const Moves& moves) {
    const std::size_t nv = topo_.points.size();
    std::vector<Vec3> delta(nv, Vec3{0, 0, 0});
    std::vector<std::uint8_t> active(nv, 0);
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (!free_[v]) continue;
      // A region moves whole, as far as it must; per-crossing steps are capped.
      Vec3 d{0, 0, 0};
      if (moves.has_region[v]) d = moves.region[v];
      else if (moves.crossing_count[v] > 0) d = crossing_step(moves, v);
      if (norm(d) == 0.0) continue;
      delta[v] = d;
      active[v] = 1;
    }
    // Triangles that would flip (or turn by more than ~85 degrees) halve their corners' moves;
    // every round first finds all such triangles, then halves each corner once, so the result does
    // not depend on the order of triangles. Triangles touched by a region move are left alone: a
    // region's move was chosen whole (by least strain) and may fold it over on purpose.
    std::vector<std::uint8_t> halve(nv, 0);
    for (int round = 0; round < 6; ++round) {
      bool any = false;
      for (std::uint32_t t = 0; t < topo_.tris.size(); ++t) {
        const auto& tri = topo_.tris[t];
        if (!active[tri[0]] && !active[tri[1]] && !active[tri[2]]) continue;
        if (moves.has_region[tri[0]] || moves.has_region[tri[1]] || moves.has_region[tri[2]]) continue;
        const Vec3 n0 = cross(sub(topo_.points[tri[1]], topo_.points[tri[0]]),
                              sub(topo_.points[tri[2]], topo_.points[tri[0]]));
        const Vec3 q0 = add(topo_.points[tri[0]], delta[tri[0]]);
        const Vec3 n1 = cross(sub(add(topo_.points[tri[1]], delta[tri[1]]), q0),
                              sub(add(topo_.points[tri[2]], delta[tri[2]]), q0));
        if (dot(n0, n1) > 0.1 * norm(n0) * norm(n1)) continue;
        any = true;
        for (std::uint32_t v : tri) halve[v] = 1;
      }
      if (!any) break;
      for (std::uint32_t v = 0; v < nv; ++v) {
        if (!halve[v]) continue;
        delta[v] = round < 5 ? scale(delta[v], 0.5) : Vec3{0, 0, 0};
        halve[v] = 0;
      }
    }
    std::vector<Vec3> next;  // the new position of each vertex that moves
    std::vector<std::uint32_t> movers;
    for (std::uint32_t v = 0; v < nv; ++v) {
      if (!active[v] || norm(delta[v]) == 0.0) continue;
      Vec3 p = add(topo_.points[v], delta[v]);
      if (round_) p = round_(p);
      if (p == topo_.points[v]) continue;
      movers.push_back(v);
      next.push_back(p);
    }
    hold_back_coincident(movers, next);
    for (std::size_t i = 0; i < movers.size(); ++i) {
      topo_.points[movers[i]] = next[i];
      moved_[movers[i]] = 1;
    }
    return !movers.empty();
  }

  // Two vertices of one mesh must never land on one position: read back, they would weld into
  // one and the written surface would pinch or lose an edge (a closest-point or mirrored move can
  // put two vertices on one point, most easily on grid-snapped input). A mover that would share
  // its new position with another vertex of its mesh stays where it is; repeated until no
  // position is shared (positions before the step are all distinct, so this ends).
  void hold_back_coincident(std::vector<std::uint32_t>& movers, std::vector<Vec3>& next) const {
    if (movers.empty()) return;
    for (;;) {
      std::vector<std::uint32_t> mover_of(topo_.points.size(), kNone);
      for (std::size_t i = 0; i < movers.size(); ++i) mover_of[movers[i]] = static_cast<std::uint32_t>(i);
      // Every vertex of a mesh with a mover, at its position after the step, sorted by position.
      std::vector<std::uint8_t> mesh_moves(meshes_.size(), 0);
      for (std::uint32_t v : movers) mesh_moves[topo_.vertex_mesh[v]] = 1;
      std::vector<std::pair<Vec3, std::uint32_t>> at;
      for (std::uint32_t m = 0; m < meshes_.size(); ++m) {
        if (!mesh_moves[m]) continue;
        for (std::uint32_t v = topo_.mesh_vertex_begin[m]; v < topo_.mesh_vertex_begin[m + 1]; ++v)
          at.push_back({mover_of[v] != kNone ? next[mover_of[v]] : topo_.points[v], v});
      }
      std::sort(at.begin(), at.end());
      std::vector<std::uint8_t> stay(movers.size(), 0);
      bool any = false;
      for (std::size_t i = 0; i + 1 < at.size(); ++i) {
        if (at[i].first != at[i + 1].first ||
            topo_.vertex_mesh[at[i].second] != topo_.vertex_mesh[at[i + 1].second])
          continue;
        for (std::uint32_t v : {at[i].second, at[i + 1].second}) {
          if (mover_of[v] != kNone) {
            stay[mover_of[v]] = 1;
            any = true;
          }
        }
      }
      if (!any) return;
      std::size_t kept = 0;
      for (std::size_t i = 0; i < movers.size(); ++i) {
        if (stay[i]) continue;
        movers[kept] = movers[i];
        next[kept] = next[i];
        ++kept;
      }
      movers.resize(kept);
      next.resize(kept);
    }
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
          result.displacement.max_over_mean_edge = mean_edge_[m] > 0 ? d / mean_edge_[m] : 0.0;
        }
      }
    }
    result.displacement.moved_vertices = count;
    result.displacement.mean = count > 0 ? sum / static_cast<double>(count) : 0.0;
  }

  std::vector<Mesh>& meshes_;
  const FixOptions& options_;
  std::function<Vec3(const Vec3&)> round_;
  SceneTopology topo_;
  DetectSettings settings_;
  RegionSettings region_settings_;
  std::vector<std::uint8_t> free_;
  std::vector<std::uint8_t> moved_;
  std::vector<double> mean_edge_;
  std::vector<double> vertex_edge_;
  std::vector<Vec3> start_points_;
  std::vector<Vec3> best_points_;
  std::vector<std::size_t> component_size_;  // welded vertices per component
  std::unique_ptr<TriangleBvh> obstacle_bvh_;
  const SceneHierarchy* hierarchy_ = nullptr;  // at the current positions, during a step
  std::unique_ptr<TrialMove> trial_;
  std::size_t trial_budget_ = 0;  // triangles measured moves may still touch in this step
  std::size_t relax_budget_ = 0;  // the part of it relaxations may still spend
  bool wide_tried_ = false;       // a wide patch was built in this step
  int stage_ = 1;  // 1, 2 or 3: the stage running (escalate)
  std::unique_ptr<Moves> crossing_scratch_;  // measured_crossing_move's, all zero between calls
  std::vector<std::uint8_t> member_, seen_;  // part_moves' scratch, per welded vertex, all zero
  std::vector<std::uint8_t> measured_;       // per welded vertex: taken by a measured move this step
  std::vector<std::uint32_t> measured_list_;
  std::vector<Vec3> normal_;                 // between calls
  std::map<std::uint32_t, std::unique_ptr<MeshTree>> obstacle_trees_;
  std::vector<std::uint8_t> buried_;  // per triangle: find_buried_obstacle_faces
  std::size_t obstacle_crossing_pairs_ = 0;
  std::vector<std::int8_t> orientation_;  // per triangle: face_orientations
  std::vector<std::uint8_t> oriented_;     // per component: orientable (face_orientations)
  // Per layered pair (lower component first): its order, decided where it is first seen.
  std::map<std::pair<std::uint32_t, std::uint32_t>, LayerOrder> layer_orders_;
};


// The solver sums moves, averages and breaks ties in index order, so its floating-point result
// depends on the order of vertices and faces in the file. It therefore runs on a canonical
// renumbering of every mesh: vertices sorted by position (exact duplicates, which weld into one
// vertex and move together, by input index), each triangle rotated to start at its smallest
// canonical corner (orientation kept) and triangles sorted by corners. The same geometry in any
// vertex or face order then gives the same positions, bit for bit (tests/test_determinism.cpp).
struct CanonicalMesh {
  std::vector<std::uint32_t> vertex_order;  // canonical index -> input index
  Mesh mesh;
};

CanonicalMesh canonical(const Mesh& input) {
  CanonicalMesh out;
  const std::size_t nv = input.positions.size();
  out.vertex_order.resize(nv);
  for (std::uint32_t i = 0; i < nv; ++i) out.vertex_order[i] = i;
  std::sort(out.vertex_order.begin(), out.vertex_order.end(), [&](std::uint32_t a, std::uint32_t b) {
    const Vec3& pa = input.positions[a];
    const Vec3& pb = input.positions[b];
    return pa != pb ? pa < pb : a < b;
  });
  std::vector<std::uint32_t> rank(nv);
  for (std::uint32_t k = 0; k < nv; ++k) rank[out.vertex_order[k]] = k;

  const std::size_t nt = input.triangles.size();
  std::vector<Triangle> rotated(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    Triangle tri{};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = input.triangles[t][k];
      tri[k] = v < nv ? rank[v] : v;  // out-of-range indices are the reader's to refuse
    }
    const int first = static_cast<int>(std::min_element(tri.begin(), tri.end()) - tri.begin());
    std::rotate(tri.begin(), tri.begin() + first, tri.end());
    rotated[t] = tri;
  }
  std::vector<std::uint32_t> tri_order(nt);
  for (std::uint32_t t = 0; t < nt; ++t) tri_order[t] = t;
  std::sort(tri_order.begin(), tri_order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return rotated[a] != rotated[b] ? rotated[a] < rotated[b] : a < b;
  });

  out.mesh.path = input.path;
  out.mesh.name = input.name;
  out.mesh.role = input.role;
  out.mesh.source_faces = input.source_faces;
  out.mesh.group_names = input.group_names;
  out.mesh.positions.reserve(nv);
  for (std::uint32_t i : out.vertex_order) out.mesh.positions.push_back(input.positions[i]);
  out.mesh.triangles.reserve(nt);
  for (std::uint32_t t : tri_order) {
    out.mesh.triangles.push_back(rotated[t]);
    if (t < input.polygon.size()) out.mesh.polygon.push_back(input.polygon[t]);
    if (t < input.triangle_group.size()) out.mesh.triangle_group.push_back(input.triangle_group[t]);
  }
  return out;
}

}  // namespace

const char* to_string(FixMethod method) { return method == FixMethod::kRegion ? "region" : "paper"; }

FixResult fix_meshes(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins,
                     const std::function<Vec3(const Vec3&)>& round, const FixProgress& progress) {
  std::vector<CanonicalMesh> renumbered;
  renumbered.reserve(meshes.size());
  for (const Mesh& mesh : meshes) renumbered.push_back(canonical(mesh));
  std::vector<Mesh> work;
  work.reserve(meshes.size());
  PinMask work_pins(pins.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    work.push_back(std::move(renumbered[m].mesh));
    if (m < pins.size() && !pins[m].empty()) {
      const auto& order = renumbered[m].vertex_order;
      work_pins[m].assign(order.size(), 0);
      for (std::size_t k = 0; k < order.size(); ++k)
        if (order[k] < pins[m].size()) work_pins[m][k] = pins[m][order[k]];
    }
  }

  FixResult result = Solver(work, options, work_pins, round).run(progress);

  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const auto& order = renumbered[m].vertex_order;
    for (std::size_t k = 0; k < order.size(); ++k) meshes[m].positions[order[k]] = work[m].positions[k];
  }
  // What is left, in the caller's numbering (the report and --contours name input indices).
  if (!result.clean) {
    DetectOptions detect;
    detect.threads = options.threads;
    detect.skip_obstacle_pairs = true;
    result.remaining = find_intersections(meshes, detect);
  }
  return result;
}

}  // namespace untangle
