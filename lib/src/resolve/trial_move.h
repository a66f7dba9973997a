// Measuring a candidate move before making it: how many crossings the triangles it touches take
// part in now, and how many they would take part in after it.
#pragma once

#include <cstdint>
#include <vector>

#include "detect/detect_crossings.h"
#include "topology/scene_topology.h"

namespace untangle {

struct TrialCount {
  std::size_t before = 0;  // crossings with an edge or face of a touched triangle, now
  std::size_t after = 0;   // the same, with the candidate's vertices moved
  std::size_t triangles = 0;  // touched triangles: what the count cost
};

// Crossings elsewhere do not change when `vertices` move, so after - before is the change of the
// scene's crossing count a move would make, decided by the same exact predicates as detection.
// The broad phase is the scene hierarchy (its boxes must hold the current positions) for triangles
// the move leaves alone, a direct box test among the moved ones.
class TrialMove {
 public:
  explicit TrialMove(const SceneTopology& topology);
  // `set` holds the crossings at the current positions (the one given to sync); vertices[i] would
  // move to at[i]. With `stop_above_before`, counting stops once `after` is sure to exceed
  // `before`, and `after` is then only some number above it.
  TrialCount count(const DetectSettings& settings, const SceneHierarchy& hierarchy,
                   const CrossingSet& set, const std::vector<std::uint32_t>& vertices,
                   const std::vector<Vec3>& at, bool stop_above_before = false);
  // Call before counting against new positions or a new crossing set.
  void sync(const CrossingSet& set);

 private:
  const SceneTopology& topology_;
  std::vector<Vec3> points_;            // the current positions, with a candidate's applied
  std::vector<std::uint8_t> affected_;  // per triangle, during one count
  std::vector<std::uint32_t> faces_;    // per triangle, crossings through it
};

}  // namespace untangle
