// Shape relaxation after a clean repair: the moved vertices and the rings around them relax toward
// the input's shape, and exact detection keeps every accepted step free of crossings and of
// vertices inside an obstacle (DESIGN §5, "Relaxation").
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detect/detect_crossings.h"
#include "resolve/inside_vertices.h"
#include "resolve/moves.h"
#include "resolve/scene_measures.h"
#include "topology/scene_topology.h"
#include "untangle/fix.h"

namespace untangle {

class SurfaceTrees;

struct RelaxShapeResult {
  int sweeps = 0;             // sweeps run
  std::size_t relaxed = 0;    // welded vertices whose position the relaxation changed
  std::size_t held = 0;       // proposals turned back because they would cross, go inside or
                              // lose clearance (summed over sweeps)
};

// What the relaxation reads: the scene, the input's welded positions, the rounding of the output
// format, how near an obstacle a vertex may come (scene units, per mesh), and the detection state
// of the current positions, which must be clean (no crossing, no vertex inside).
struct RelaxShapeInputs {
  const SceneMeasures& measures;
  const std::vector<Vec3>& input;
  const Rounding& round;
  const DetectSettings& detect;
  const ObstacleWinding& winding;
  std::vector<double> clearance;  // per mesh, scene units
  int threads = 0;
  // Where the run started, when `input` (the shape relaxed toward) is another state, as in the
  // continuation's steps (toward the asset's shape, from the step's start): the vertices moved
  // since `moved_from` seed the part. Null: `input` is both.
  const std::vector<Vec3>* moved_from = nullptr;
  int max_sweeps = FixOptions{}.relax_sweeps;  // sweeps at most
  // Where the obstacles' tree is kept for the run (they never move), or null: built here.
  SurfaceTrees* trees = nullptr;
};

// Relaxes topo.points in place: the moved vertices and kRelaxRings rings around them move toward
// the input's shape, each sweep halfway to the as-rigid-as-possible solution (shape_solve.h) with
// every vertex outside them, and every vertex that holds, fixed, and the obstacles near a vertex as
// its contact plane. A proposal that would bring a vertex nearer than `clearance` to an obstacle
// (and nearer than it is) slides along the obstacle instead (lifted back out to the clearance
// where the obstacle curves under the slide), or holds; one that would make a crossing or put a
// vertex inside an obstacle is shortened, then held, and the rest of the sweep solved again
// around it. A sweep that cannot be made clean is undone and what it refused sits the next one
// out; a second in a row ends the relaxation, and so does a strain (squared relative edge-length
// change) that has stopped falling. Every sweep ends as clean as it started. `hierarchy` is refitted to the positions left; `set` stays empty.
// `moved[v]` is set for every vertex the relaxation changed.
RelaxShapeResult relax_shape(const RelaxShapeInputs& in, SceneTopology& topo,
                             SceneHierarchy& hierarchy, std::vector<std::uint32_t>& inside,
                             std::vector<std::uint8_t>& moved);

}  // namespace untangle
