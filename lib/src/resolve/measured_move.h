// Measured moves: a candidate move counted exactly (TrialMove) before it is made, within a budget
// per step, and made only when it removes crossings.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detect/detect_crossings.h"
#include "resolve/moves.h"
#include "resolve/trial_move.h"
#include "topology/scene_topology.h"

namespace untangle {

// The largest set of vertices whose moves are measured before they are made.
constexpr std::size_t kMeasuredVertices = 2500;

// The measuring state of one step. Measuring a move costs about what re-detecting the triangles
// it touches does, the budget's unit (some two per vertex, three with the ring around): a step
// measures at most a few detections' worth, in contour order.
class MeasuredMoves {
 public:
  explicit MeasuredMoves(const SceneTopology& topo) : trial_(topo), taken_(topo.points.size(), 0) {}

  // Starts a step on the topology's current positions: `set` their crossings, `hierarchy` at them.
  void start_step(const CrossingSet& set, const SceneHierarchy& hierarchy, std::size_t triangles);
  // Crossings removed (negative: added) if part[i] moved to at[i], counted exactly against the
  // positions this step's measured moves leave. Spends no budget.
  long long gain(const DetectSettings& detect, const CrossingSet& set,
                 const std::vector<std::uint32_t>& part, const std::vector<Vec3>& at);
  // Makes a measured move as a region move and lets later measurements in this step see it.
  void make(const Choice& chosen, std::vector<std::uint8_t>& in_moving_set, Moves& moves);
  // Whether a measured move of this step took v (a vertex moves once per step).
  bool taken(std::uint32_t v) const { return taken_[v] != 0; }

  std::size_t trial_budget = 0;  // triangles measured moves may still touch in this step
  std::size_t relax_budget = 0;  // the part of it relaxations may still spend
  bool wide_tried = false;       // a wide patch was built in this step (one per step)

 private:
  TrialMove trial_;
  const SceneHierarchy* hierarchy_ = nullptr;
  std::vector<std::uint8_t> taken_;  // per welded vertex
  std::vector<std::uint32_t> taken_list_;
};

}  // namespace untangle
