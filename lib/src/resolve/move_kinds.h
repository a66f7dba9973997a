// The move kinds of the repair and what they read. Each kind takes the step's context and returns
// the moves it proposes by adding them to `moves`; only the loop (repair_loop.cpp) applies them.
// Entry points are grouped under the file that defines them.
//
// Notation: `set` the step's crossings, `traced` its contours, `analysis` the region labels;
// `in_moving_set[v]` marks welded vertices that a region-like move of this step already took
// (later kinds leave their contours alone); components are the edge-connected pieces of meshes.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "resolve/measured_move.h"
#include "resolve/moves.h"
#include "resolve/region_analysis.h"
#include "resolve/scene_measures.h"
#include "resolve/surface_queries.h"
#include "topology/scene_topology.h"
#include "untangle/fix.h"

namespace untangle {

// What every move kind reads during one step.
struct RepairContext {
  const SceneTopology& topo;  // positions of this step
  const SceneMeasures& measures;
  const FixOptions& options;
  const DetectSettings& detect;
  const Rounding& round;
  int stage;  // 1, 2 or 3 (repair_loop.cpp)
  // Stages 2 and 3: track pieces are candidate sides, and only measured moves act where both
  // sides of a contour move.
  bool pieces() const { return stage >= 2; }
};

// Per-vertex scratch, all zero between calls: the cost of a call follows the set, not the mesh.
struct Scratch {
  explicit Scratch(std::size_t n) : member(n, 0), seen(n, 0), normal(n, Vec3{0, 0, 0}), drn(n) {}
  std::vector<std::uint8_t> member, seen;  // part_moves
  std::vector<Vec3> normal;                // part_moves
  Moves drn;                               // measured_drn_move
};

// What the move kinds of a step share and change.
struct StepTools {
  SurfaceTrees& trees;
  MeasuredMoves& measured;
  Scratch& scratch;
};

// ---- region_move.cpp: an illegal region moved across the other surface ----

// The connected parts of `vertices` (of `mesh`) and, for each, the candidate moves across `tree`:
// to its closest point plus the clearance, mirrored through it, along the part's normal to where
// that ray leaves the surface (both ways), and in stages 2-3 reflected across the closest face's
// plane. `orientation` is the other surface's (closed_orientations; 0 for a local patch).
std::vector<PartMoves> part_moves(const RepairContext& ctx, Scratch& scratch, std::uint32_t mesh,
                                  int orientation, const std::vector<std::uint32_t>& vertices,
                                  const MeshTree& tree);
// Moves every connected part of an illegal set across `tree` by its least-strain candidate.
void move_regions(const RepairContext& ctx, Scratch& scratch, std::uint32_t mesh, int orientation,
                  const std::vector<std::uint32_t>& vertices, const MeshTree& tree, Moves& moves);

// ---- inside_move.cpp: movable vertices inside an obstacle that no contour reaches ----

// `inside` per welded vertex: the obstacle mesh it lies inside (find_inside_vertices) or kNone.
// Free inside vertices not joined through inside vertices to a crossing, and not yet in a moving
// set, are moved across the nearest component of that obstacle by move_regions.
void inside_move(const RepairContext& ctx, Scratch& scratch, SurfaceTrees& trees,
                 const CrossingSet& set, const std::vector<std::uint32_t>& inside,
                 std::vector<std::uint8_t>& in_moving_set, Moves& moves);

// ---- measured_move.cpp ----

// Every connected part of every candidate with every move of part_moves, counted exactly: the one
// that removes most crossings, the least strain breaking ties (empty part: nothing measured).
Choice measured_choice(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                       const std::vector<Candidate>& candidates);

// ---- self_contour_move.cpp: a component through itself ----

void self_contour_move(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                       const TracedContour& traced, const RegionAnalysis& analysis,
                       std::vector<std::uint8_t>& in_moving_set, Moves& moves);

// ---- flap_move.cpp: what a contour that separates nothing cuts off ----

void flap_move(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
               const TracedContour& t, FreshTrees& trees, std::vector<std::uint8_t>& in_moving_set,
               Moves& moves);

// ---- layer_move.cpp: layers, coincident layers and folds ----

// Per pair of different components that cross (lower index first): how many of their crossings
// join nearly parallel faces, and how many crossings they have.
using ParallelCounts =
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::array<std::size_t, 2>>;
using ComponentPairs = std::set<std::pair<std::uint32_t, std::uint32_t>>;

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
// Per layered pair (lower component first), kept for the run.
using LayerOrders = std::map<std::pair<std::uint32_t, std::uint32_t>, LayerOrder>;

ParallelCounts parallel_crossings(const SceneTopology& topo, const CrossingSet& set,
                                  const std::vector<TracedContour>& traced);
// The pairs that are layers (decided once per pair into `orders`, where first seen).
ComponentPairs layered_pairs(const RepairContext& ctx, SurfaceTrees& trees,
                             const ParallelCounts& parallel, LayerOrders& orders);
// Layered pairs laid in their order; other pairs that cross in parallel with no illegal region
// (an exact copy, sheets in one plane) laid apart by index.
void separate_coincident_layers(const RepairContext& ctx, SurfaceTrees& trees,
                                const CrossingSet& set, const std::vector<TracedContour>& traced,
                                const ParallelCounts& parallel, const ComponentPairs& layered,
                                const LayerOrders& orders, const RegionAnalysis& analysis,
                                std::vector<std::uint8_t>& in_moving_set, Moves& moves);
// A fold of one component lying over itself near a closed obstacle, its two sheets laid one
// outside the other; measured (none when the scene has no closed obstacle).
Choice fold_layer_choice(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                         const TracedContour& traced, const Moves& moves);

// ---- drn_move.cpp: the paper's dynamic repulsive normal per crossing ----

// Adds the DRN step of every crossing of the contour (paper Eq. 1, action and reaction).
void drn_moves(const RepairContext& ctx, const CrossingSet& set, const TracedContour& t,
               const RegionAnalysis& analysis, Moves& moves);
// Vertex v's DRN step: the mean of its DRN moves, at most max_step times its mean edge length.
Vec3 drn_step(const RepairContext& ctx, const Moves& moves, std::uint32_t v);
// The contour's DRN step measured and made when it removes crossings; else its neighbourhood
// relaxed (relax_choice) when that does.
void measured_drn_move(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                       const TracedContour& t, const RegionAnalysis& analysis,
                       std::vector<std::uint8_t>& in_moving_set, Moves& moves);

// ---- relax_move.cpp ----

// The neighbourhood of `seeds` (ascending) relaxed by 0 to a few rings, measured: the size that
// removes most crossings.
Choice relax_choice(const RepairContext& ctx, StepTools& tools, const CrossingSet& set,
                    const std::vector<std::uint32_t>& seeds, const Moves& moves);

// ---- apply_moves.cpp ----

// The positions the step's moves lead to: DRN steps capped, a guard against flipped
// triangles, rounded as the file stores them, and no two vertices of a mesh on one position.
struct SettledMoves {
  std::vector<std::uint32_t> movers;  // ascending
  std::vector<Vec3> next;             // their new positions
};
SettledMoves settle_moves(const RepairContext& ctx, const Moves& moves);

}  // namespace untangle
