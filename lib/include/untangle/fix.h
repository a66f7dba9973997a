// Resolving penetrations: iterative dynamic-repulsive-normal displacements (paper §III, DESIGN §4-5).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "untangle/intersections.h"
#include "untangle/mesh.h"
#include "untangle/mesh_info.h"

namespace untangle {

enum class FixMethod {
  // Default. Every vertex of an illegal region moves across the other surface (to its closest
  // point there, plus the clearance); self contours, flaps, layers and folds get their own moves
  // (docs/DESIGN.md), and contours that enclose no vertex get the DRN below.
  kRegion,
  // The paper's dynamic repulsive normal (DRN, Eq. 1) on crossing edges only:
  // d = n_r + lambda (r1 + r2), e gets +d, f gets -d,
  // split by mass; BI/BI and non-separating tracks get d = r1, toward the other mesh's boundary.
  kPaper,
};
const char* to_string(FixMethod method);

// What a result may change and still count as clean: the guard of `fix` (its status `distorted`,
// exit 6, when a movable mesh's written shape goes beyond one of these).
struct QualityBounds {
  double max_stretch = 1.5;    // QualityStats::max_stretch at most
  std::size_t max_flips = 0;   // QualityStats::flipped_faces at most
  double max_move = 0.05;      // QualityStats::max_displacement_over_diagonal at most
};

// The one home of every default of the repair. The CLI initialises its options from a
// default-constructed FixOptions (app/pipeline.h) and its help prints these values; the man page
// states them too, and a test checks that help and man page agree.
struct FixOptions {
  FixMethod method = FixMethod::kRegion;
  int max_iterations = 200;
  // Gap kept between the surfaces after a move, as a fraction of the mean edge length of the
  // moving mesh (unitless, so mm, cm and m assets behave alike).
  double clearance = 0.05;
  // In-plane weight of Eq. 1 (paper: 0.1).
  double lambda = 0.1;
  // Per-crossing step, as a fraction of the local edge length.
  double step = 0.25;
  // Largest move of one vertex in one iteration, as a multiple of its mean incident edge length.
  double max_step = 2.0;
  // A closed obstacle's inside decides which side of a movable mesh is illegal (DESIGN §4); when
  // false, "the smaller region is illegal" everywhere (the paper's orientation-free rule).
  bool outside_closed_obstacles = true;
  // Stop as stalled when neither the crossing count nor the contour length improved for this many
  // iterations (method region: after a second stage from the input and a third from the best
  // state: see fix_meshes).
  int stall_iterations = 12;
  // How many stages a stalled region run may use (1 to 3; see stall_iterations), taken in the
  // order 1, 2, 3, or 2, 1, 3 for a single mesh alone in its scene. The continuation's steps but
  // the last use 1: a step that stalls is undone and taken in halves instead.
  int stages = 3;
  // After a clean repair, the moved vertices and the rings around them relax toward the input's
  // shape (their displacements smoothed), every step kept clean by exact detection.
  bool relax = true;
  // The relaxation's sweeps at most (each moves halfway to the solved shape); fewer are faster
  // and relax the shape less.
  int relax_sweeps = 40;
  // An unresolved run writes its best state among those no worse than the input: no more
  // crossings of each kind (movable against obstacle, mesh against itself, between movable
  // meshes) and no more inside vertices than the input, and no vertex moved further than this
  // many diagonals of its mesh's input bounding box. The input itself always qualifies.
  double max_written_move = 0.25;
  // A run that ends unresolved (not cancelled) is retried from the input up to this many times,
  // each with the clearance doubled (a larger gap makes each step's penetration shallower where
  // the moves overshoot one another); the first clean attempt is kept, else the one with the
  // fewest crossings plus inside vertices (the first on a tie). Counted in attempts, not seconds,
  // so that the result does not depend on the machine. Where garments worn together were laid
  // before the retries (`layering`), two at most.
  int retries = 4;
  // On by default (where it runs it adds seconds: 3 to 5 on the MakeHuman garments on bodies scaled
  // 1.02 and 1.05; see docs/PERFORMANCE.md): when the kept attempt is unresolved, or clean but
  // beyond the stretch or flip bound of `bounds` (not the move bound alone: a garment sunk deep has
  // to move far, and the continuation does not make that shorter), and movable vertices lie inside
  // a closed obstacle (a deep penetration), the repair runs once more from the input as a
  // continuation (DESIGN §5): the obstacles shrunk inward along their normals until the movable
  // meshes are outside them, then grown back to their true shape in steps, repaired and relaxed
  // (toward the input's shape) after each; it gives up after four repairs in a row end unresolved.
  // Where its result, or the attempt kept, is still not within the bounds and there is one
  // movable mesh, a second one runs with the obstacles scaled down about their centre instead (a
  // limb moved out of its sleeve by more than its thickness is not reached along normals;
  // FixResult::scaled_continuation).
  // Its result is kept when it is clean and better: within the bounds where the other is not, or
  // unresolved against it, or, both beyond the bounds, better in its largest edge ratio or in its
  // faces beyond them (turned over, or with an edge beyond the stretch bound) and no worse in the
  // other, or, better in one and worse in the other, with fewer faces turned over. Region method
  // only (the paper method is the paper's DRN alone).
  bool continuation = true;
  // Garments worn together (DESIGN §5, "Layering"): when the kept attempt is unresolved, or clean
  // but beyond `bounds`, and the scene has an obstacle and two or more layers (edge-connected
  // pieces of the movable meshes: a top and trousers in one file are two; a single movable mesh
  // only when two of its pieces cross in the kept attempt), the repair runs once more from the
  // input: each movable mesh alone on the obstacles; then, from the layer nearest the obstacles
  // (median distance of its vertices) outward, each laid over the ones inside it, which stand as
  // obstacles flattened onto the obstacles' surface and grow back to their places in the
  // continuation's steps, the layer repaired and relaxed after each toward the shape it had
  // alone; where that ends unresolved or beyond `bounds`, once more in the order where the layers
  // overlap (LayerOrderRule::kOverlap), the better kept. Kept as the continuation is (clean and
  // better). With two or more movable meshes whose first attempt ends unresolved it runs before
  // the retries, which then run only where it is not clean within `bounds`. Region method only;
  // `simulate`'s corrections leave it out.
  bool layering = true;
  // Pieces moved whole (DESIGN §5, "Pieces moved whole"): when the kept attempt is unresolved and
  // every piece it leaves crossing another piece or an obstacle (or with a vertex inside one) is
  // small (at most 2,048 triangles), crosses only small pieces and obstacle components (lies
  // only inside small obstacles: never a garment on a body), and is free to move (no pinned
  // vertex, none shared with an obstacle), each such piece is moved whole, smallest first, by the
  // shortest translation found that clears it (lengths of 1/16 to 1/2 of its bounding-box
  // diagonal, 26 directions of its principal axes), and the repair runs once more from there: a
  // ring through a tube's wall, a torus through a sheet, two links of a chain, which no local move
  // frees. Kept as the continuation is (clean and better); moved beyond the move bound, it
  // reports `distorted`. Region method only, and not with max_iterations 0; `simulate`'s
  // corrections leave it out.
  bool piece_moves = true;
  // What `distorted` means to the continuation's and the layering's trigger and choice (the CLI
  // passes its --max-stretch, --max-flips and --max-move).
  QualityBounds bounds;
  int threads = 0;
};

// One row of the iteration history (the report's `history`).
struct IterationRecord {
  int iteration = 0;
  std::size_t crossings = 0;
  double contour_length = 0.0;
  double elapsed_ms = 0.0;  // since the start of fix_meshes
  int stage = 1;  // 2 in the second stage, which starts again from the input; 3 in the third,
                  // which starts from the best state of the first two; 4 in the continuation's
                  // repairs, 5 in the layering's
};

struct DisplacementStats {
  double max = 0.0;                 // largest vertex displacement, scene units
  double mean = 0.0;                // mean over moved vertices
  double max_over_mean_edge = 0.0;  // max divided by the mean edge length of its mesh
  std::size_t moved_vertices = 0;   // input vertices whose position changed
};

// How much the repair changed one movable mesh's shape, against the input positions (welded
// vertices and their edges and triangles; all 0 for an obstacle or an unmoved mesh).
struct QualityStats {
  // |length / input length - 1| over the edges of nonzero input length: mean, 95th percentile
  // (nearest rank), max.
  double edge_change_mean = 0.0, edge_change_p95 = 0.0, edge_change_max = 0.0;
  // The largest of length / input length and its inverse over those edges (1 = unchanged; an
  // edge 1.5 times longer or shorter than it was has 1.5).
  double max_stretch = 1.0;
  std::size_t flipped_faces = 0;  // triangles whose normal turned by more than 90 degrees
  double max_displacement = 0.0;  // scene units
  double max_displacement_over_mean_edge = 0.0;  // in the mesh's mean input edge lengths
  double max_displacement_over_diagonal = 0.0;   // in its input bounding box's diagonals
};

// Per mesh, the shape of `output` against `input` (the same meshes in the same order, the same
// vertex counts; welded as `input` is): what the repair changed. Obstacles get zeros.
std::vector<QualityStats> measure_quality(const std::vector<Mesh>& input,
                                          const std::vector<Mesh>& output);
bool within_bounds(const QualityStats& quality, const QualityBounds& bounds);

// The verdict on a written result: unresolved while a crossing or a vertex inside remains, else
// distorted when a movable mesh's quality is beyond the bounds, else clean.
enum class FixStatus { kClean, kUnresolved, kDistorted };
const char* to_string(FixStatus status);
FixStatus judge_result(const IntersectionCounts& written, const std::vector<QualityStats>& quality,
                       const QualityBounds& bounds);

// One retry of an unresolved run (FixOptions::retries), in the order they ran.
struct RetryRecord {
  double clearance = 0.0;  // the clearance of this attempt (fraction of the mean edge length)
  bool clean = false;
  std::size_t crossings = 0, inside_vertices = 0;  // left by the attempt
  int iterations = 0;
  bool kept = false;  // its positions are the result
};

// One repair of the continuation: the obstacles at `shrink` of their full inward move (1 at the
// first step, 0 at the last), the counts before and after it.
struct ContinuationStep {
  double shrink = 0.0;
  std::size_t crossings_before = 0, inside_before = 0;
  std::size_t crossings_after = 0, inside_after = 0;
  int iterations = 0;
  bool clean = false;
};

// How a scaled continuation's factor was chosen: none (along normals), the least depth of the
// movable vertices inside the obstacles, or the fewest crossings against them and vertices inside.
enum class ScaleChoice { kNone, kDepth, kCount };

// The continuation (FixOptions::continuation), when it ran.
struct ContinuationRecord {
  bool ran = false;
  double factor = 0.0;        // the scaled continuation's scale at full shrink; 0 along normals
  ScaleChoice chosen_by = ScaleChoice::kNone;  // how `factor` was chosen
  int steps = 0;              // repairs run: the obstacles shrunk, then grown back, the last at
                              // their true shape
  double deepest = 0.0;       // deepest movable vertex inside an obstacle at the start, scene units
  double largest_shrink = 0.0;  // largest inward move of an obstacle vertex, scene units
  std::size_t shrunk_vertices = 0;  // obstacle vertices moved inward
  bool clean = false;         // its last step ended with no crossing and no inside vertex
  std::size_t crossings = 0, inside_vertices = 0;  // left by it (by its last repair if it gave up)
  double max_stretch = 1.0;   // the largest over the movable meshes, against the input
  bool kept = false;          // its positions are the result
  bool gave_up = false;       // ended after four repairs in a row that ended unresolved
  std::vector<ContinuationStep> runs;  // the steps in order
};

// One piece moved whole: mesh (input index), its lowest input vertex (0-based) and the
// translation, scene units.
struct PieceMove {
  std::uint32_t mesh = 0;
  std::uint32_t vertex = 0;
  Vec3 shift{};
};

// Pieces moved whole (FixOptions::piece_moves), when the search ran.
struct PieceMoveRecord {
  bool ran = false;
  std::size_t tangled = 0;    // pieces left crossing another or an obstacle, or inside one
  std::size_t moved = 0;      // of those, moved whole (a clear translation was found)
  double largest_move = 0.0;  // the longest translation, scene units
  bool clean = false;         // the repair after the moves ended with no crossing, nothing inside
  bool kept = false;          // its positions are the result
  std::vector<PieceMove> pieces;  // the pieces moved, by mesh and lowest vertex
};

// One layer laid over those inside it (FixOptions::layering): an edge-connected piece of a
// movable mesh (the top and the trousers of one garment file are two layers).
struct LayerRecord {
  std::uint32_t mesh = 0;       // input index
  std::uint32_t component = 0;  // the piece of that mesh, counted from 0 by its lowest vertex
  double distance = 0.0;        // median distance of its vertices to the obstacles, laid alone
  // Its steps (empty for the innermost, and for one that crossed none of the garments inside it
  // once laid alone), as the continuation's: the garments inside it at `shrink` of the way down
  // to the obstacles' surface.
  std::vector<ContinuationStep> runs;
  bool clean = false;  // free of crossings with everything inside it and with itself
};

// How the layering orders the layers, innermost first.
enum class LayerOrderRule {
  kMedianDistance,  // by the median distance of their vertices to the obstacles
  kOverlap,         // where two overlap, the one that would move less laid over the other outside
};
const char* to_string(LayerOrderRule rule);

// One order the layering tried: its layers and the whole scene once every one was laid.
struct LayeringOrderRecord {
  LayerOrderRule rule = LayerOrderRule::kMedianDistance;
  std::vector<LayerRecord> layers;  // innermost first
  bool clean = false;
  std::size_t crossings = 0, inside_vertices = 0;
  double max_stretch = 1.0;
  bool kept = false;  // the layering's result is this order's
};

// The layering (FixOptions::layering), when it ran.
struct LayeringRecord {
  bool ran = false;
  std::vector<LayerRecord> layers;  // innermost first, of the order kept
  bool clean = false;               // the whole scene, once every garment is laid
  std::size_t crossings = 0, inside_vertices = 0;
  double max_stretch = 1.0;
  bool kept = false;  // its positions are the result
  // The orders tried: by median distance, and where that ends unresolved or beyond the bounds,
  // by overlap too when it differs.
  std::vector<LayeringOrderRecord> orders;
};

struct FixResult {
  // No crossing and no movable vertex inside an obstacle on the final positions.
  bool clean = false;
  bool stalled = false;
  int iterations = 0;
  IntersectionCounts before;
  // The state left in the meshes, as the repair's own last detection counted it (the CLI decides
  // success by detecting the written files again: rounding on the way out can change it).
  IntersectionCounts after;
  std::vector<IterationRecord> history;
  DisplacementStats displacement;
  std::vector<QualityStats> quality;  // per mesh, in input order
  std::size_t illegal_regions_by_inside = 0;  // regions decided by an obstacle's inside
  std::size_t illegal_regions_by_area = 0;    // regions decided by "small is illegal"
  // Triangle pairs of the closed obstacles that cross (an obstacle through itself, as the cow's
  // tail through its rump, or two closed obstacle parts through each other), each pair once. They
  // are left as they are; moves never aim at the faces there (only positions of movable meshes
  // change). Open obstacles are not looked at here (`check` lists every crossing).
  std::size_t obstacle_crossing_pairs = 0;
  // Time per stage, summed over iterations (milliseconds, monotonic clock). resolve_ms =
  // regions_ms + displace_ms: region analysis (flood fills, legal sides), then computing and
  // applying the moves.
  double detect_ms = 0.0, contours_ms = 0.0, resolve_ms = 0.0;
  double regions_ms = 0.0, displace_ms = 0.0;
  // The shape relaxation after a clean repair (FixOptions::relax): sweeps run, welded vertices it
  // moved, milliseconds.
  int relax_sweeps = 0;
  std::size_t relaxed_vertices = 0;
  double relax_ms = 0.0;
  // The retries of an unresolved first attempt; empty when it was clean (or cancelled). When one
  // is kept, every other field but `before` and the times (summed over attempts) is that
  // attempt's.
  std::vector<RetryRecord> retries;
  double clearance = 0.0;  // the clearance of the attempt kept
  ContinuationRecord continuation;
  // The continuation with the obstacles scaled about their centre, where the one along their
  // normals was not within the bounds: by the factor of the least depth inside; where the result
  // is still not within the bounds and the factor of the fewest crossings and vertices inside
  // differs, a second one by that factor.
  ContinuationRecord scaled_continuation;
  ContinuationRecord second_scaled_continuation;
  LayeringRecord layering;
  PieceMoveRecord piece_moves;
  // The final state, detected as `check` detects it (numbered by its own positions, where the
  // repair numbered by the input's: an exact degeneracy can be decided the other way), was not
  // clean and was worse than the input (more crossings of a kind, more inside vertices, or a
  // vertex moved further than max_written_move): the input's positions were returned instead.
  bool reverted = false;
  // describe_mesh of each mesh as given, in input order, from the repair's own topology of the
  // input (the same figures): a caller that reports them need not build that again.
  std::vector<MeshInfo> inputs;
  // When that final detection found the returned meshes clean: the detection itself,
  // find_intersections of the meshes as returned with DetectOptions::skip_obstacle_pairs (with no
  // crossing there is no contour, so DetectOptions::separation changes nothing in it). Empty
  // otherwise. A caller that writes the positions and reads back the same meshes (roles,
  // triangles and positions, bit for bit) has its detection of them here and need not run it
  // again (the CLI's check of the written files, issue 24).
  std::optional<Intersections> clean_verdict;
};

// Per mesh, per input vertex: 1 = pinned (never moves). Empty = nothing pinned.
using PinMask = std::vector<std::vector<std::uint8_t>>;

// Called after each iteration; return false to cancel (the result is then `unresolved`).
using FixProgress = std::function<bool(const IterationRecord&)>;

// Moves vertices of the movable meshes (positions only, in place) until no crossing is left
// between or within meshes (obstacle-obstacle crossings are reported, never fixed), the iteration
// cap, or a stall. Welded vertices move together. `round` (optional) maps positions to what the
// output format will store (e.g. float32); success is checked on rounded positions. Never prints.
FixResult fix_meshes(std::vector<Mesh>& meshes, const FixOptions& options, const PinMask& pins = {},
                     const std::function<Vec3(const Vec3&)>& round = {},
                     const FixProgress& progress = {});

}  // namespace untangle
