// Measured moves: a candidate move whose effect on the crossing count is counted exactly before it
// is made, within a budget per step, and made only when it removes crossings.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "detect/detect_crossings.h"
#include "resolve/moves.h"
#include "topology/scene_topology.h"

namespace untangle {

// The largest set of vertices whose moves are measured before they are made.
constexpr std::size_t kMeasuredVertices = 2500;

struct MoveCount {
  std::size_t before = 0;     // crossings with an edge or face of a touched triangle, now
  std::size_t after = 0;      // the same, with the candidate's vertices moved
  std::size_t triangles = 0;  // touched triangles: what the count cost
};

// The measuring state of one step. Crossings elsewhere do not change when a candidate's vertices
// move, so after - before of its count is the change of the scene's crossing count the move would
// make, decided by the same exact predicates as detection. Moves made during a step are committed,
// and later candidates are measured against the positions they leave. The broad phase is the scene
// hierarchy (its boxes hold the positions at the step's start) for triangles neither the candidate
// nor a committed move touches, a sweep over current boxes among the others.
//
// Measuring a move costs about what re-detecting the triangles it touches does, the budget's unit
// (some two per vertex, three with the ring around): a step measures at most a few detections'
// worth, in contour order.
class MeasuredMoves {
 public:
  explicit MeasuredMoves(const SceneTopology& topology);

  // Starts a step on the topology's current positions: `set` their crossings, `hierarchy` at them,
  // `triangles` of the scene (the budgets' base).
  void start_step(const CrossingSet& set, const SceneHierarchy& hierarchy, std::size_t triangles);
  // vertices[i] would move to at[i]. With `stop_above_before`, counting stops once `after` is sure
  // to exceed `before`, and `after` is then only some number above it. Spends no budget.
  MoveCount count(const DetectSettings& settings, const CrossingSet& set,
                  const std::vector<std::uint32_t>& vertices, const std::vector<Vec3>& at,
                  bool stop_above_before = false);
  // Crossings removed (negative: added) by moving part[i] to at[i]: count, stopping early.
  long long gain(const DetectSettings& settings, const CrossingSet& set,
                 const std::vector<std::uint32_t>& part, const std::vector<Vec3>& at);
  // The move is made in this step: later counts see it.
  void commit(const std::vector<std::uint32_t>& vertices, const std::vector<Vec3>& at);
  // Makes a measured move: a region move in `moves`, its vertices taken, committed.
  void make(const Choice& chosen, std::vector<std::uint8_t>& in_moving_set, Moves& moves);
  // Whether a measured move of this step took v (a vertex moves once per step).
  bool taken(std::uint32_t v) const { return taken_[v] != 0; }

  std::size_t trial_budget = 0;  // triangles measured moves may still touch in this step
  std::size_t relax_budget = 0;  // the part of it relaxations may still spend
  bool wide_tried = false;       // a wide patch was built in this step (one per step)

 private:
  // Distinct crossings with an edge or face of a `touched` triangle at points_, stopping once more
  // than `limit` are found.
  std::size_t crossings_of(const DetectSettings& settings,
                           const std::vector<std::uint32_t>& touched, std::size_t limit);

  const SceneTopology& topology_;
  const SceneHierarchy* hierarchy_ = nullptr;
  std::vector<Vec3> points_;             // positions at the step's start, with committed moves
  std::vector<std::uint8_t> affected_;   // per triangle: touched by the candidate, during a count
  std::vector<std::uint8_t> committed_;  // per triangle: touched by a committed move
  std::vector<std::uint32_t> committed_list_;
  std::vector<std::uint32_t> faces_;  // per triangle, crossings through it at the step's start
  std::vector<std::uint8_t> taken_;   // per welded vertex
  std::vector<std::uint32_t> taken_list_;
};

}  // namespace untangle
