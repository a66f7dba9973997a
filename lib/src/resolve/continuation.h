// Continuation for deep penetration (DESIGN §5, "Continuation"): where the garment lies deep
// inside a closed obstacle, "the small side is illegal" and the closest exit both point the wrong
// way. The obstacles are shrunk inward along their normals until the movable meshes are outside
// them, then grown back to their true shape in steps; each step is a shallow penetration that the
// repair resolves, and the relaxation pulls toward the input's shape after each.
#pragma once

#include <vector>

#include "resolve/moves.h"
#include "untangle/fix.h"
#include "untangle/mesh.h"

namespace untangle {

class ObstacleWinding;

struct ContinuationPlan {
  // Per mesh, per input vertex: the inward move of an obstacle vertex at full shrink (all copies
  // of a welded vertex alike); empty for movable meshes.
  std::vector<std::vector<Vec3>> inward;
  double deepest = 0.0;         // deepest movable vertex inside an obstacle, scene units
  double largest_shrink = 0.0;  // largest inward move, scene units
  std::size_t shrunk_vertices = 0;
  double movable_edge = 0.0;  // the smallest mean edge of a movable mesh with a vertex inside
  int steps = 0;  // repairs to run, the last at the true shape; 0: nothing is inside, no plan
  // Repairs ending unresolved one after the other that end the run unresolved (the obstacles
  // back at their true shape); 0: never.
  int give_up_after = 0;
  double factor = 0.0;  // a scaled plan's: the obstacles' scale at full shrink (0: along normals)
};

// The plan for meshes at their input positions (canonical order, as run_repair takes them).
// Each movable vertex inside a closed obstacle at depth d asks the obstacle's surface around its
// closest point to move inward by d plus half the movable mesh's mean edge, over a radius of a
// few times that, tapering to nothing; an obstacle vertex moves by the largest ask, at most 0.4 of
// the obstacle's thickness behind it (a ray inward), so that thin parts are not turned inside
// out. Steps: the largest move in steps of kStepEdges mean edges of the movable meshes, between
// 2 and kMaxSteps. It gives up after kGiveUpAfter unresolved repairs in a row.
ContinuationPlan plan_continuation(const std::vector<Mesh>& meshes, const FixOptions& options,
                                   const PinMask& pins);

// The plans of the scaled continuation: every obstacle scaled about the centre of the obstacles'
// bounding box, by a factor below 1 (1 - k/64 for k = 1 to 10, then refined by halved steps down
// to 1/512 around the best). A garment made for a slimmer body, or a body grown from the one the
// garment was made on, sits outside the body scaled down where the shrink along normals cannot
// get it out: a limb moved sideways out of its sleeve by more than its thickness. The inward move
// of a vertex is its way to the scaled position, so that the steps are the body growing back.
// `by_depth` takes the factor at which the movable vertices inside the obstacles lie least deep
// in sum (in their meshes' mean edges; equal sums, none inside: the fewest crossings against the
// obstacles and inside vertices), `by_count` the one with the fewest crossings and inside
// vertices. No plan (steps 0) without an obstacle or a movable mesh. `earlier`, when given: the
// repair's winding numbers of the same obstacles, whose hierarchies the depths share.
struct ScaledPlans {
  ContinuationPlan by_depth, by_count;
};
ScaledPlans plan_scaled_continuation(const std::vector<Mesh>& meshes, const FixOptions& options,
                                     const ObstacleWinding* earlier = nullptr);

// The steps of a plan whose largest inward move is `largest_shrink`: that move in steps of
// kStepEdges mean edges `movable_edge` of the movable meshes, between kMinSteps and kMaxSteps.
int continuation_steps(double largest_shrink, double movable_edge);

// Runs the plan on `meshes` (input positions in, result out; the obstacles end at their input
// positions bit for bit). The result is the last step's, with `quality` and `displacement`
// measured against the input and `history` the steps' iterations in order (with `stage`: 4 for
// the continuation, 5 for the layering's). `runs` receives one record per step; `gave_up`, when
// given, whether the plan's give_up_after ended it.
FixResult run_continuation(std::vector<Mesh>& meshes, const ContinuationPlan& plan,
                           const FixOptions& options, const PinMask& pins, const Rounding& round,
                           const FixProgress& progress, std::vector<ContinuationStep>& runs,
                           int stage = 4, bool* gave_up = nullptr);

// Displacement statistics of the movable meshes of `meshes` against `from` (the same meshes at
// other positions), relative to the mean edge lengths of `from`.
DisplacementStats displacement_against(const std::vector<Mesh>& from,
                                       const std::vector<Mesh>& meshes);

}  // namespace untangle
