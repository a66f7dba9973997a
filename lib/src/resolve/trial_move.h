// Measuring a candidate move before making it: how many crossings the triangles it touches take
// part in now, and how many they would take part in after it.
#pragma once

#include <cstdint>
#include <vector>

#include "detect/detect_crossings.h"
#include "topology/scene_topology.h"

namespace untangle {

struct TrialCount {
  std::size_t before = 0;     // crossings with an edge or face of a touched triangle, now
  std::size_t after = 0;      // the same, with the candidate's vertices moved
  std::size_t triangles = 0;  // touched triangles: what the count cost
};

// Crossings elsewhere do not change when `vertices` move, so after - before is the change of the
// scene's crossing count a move would make, decided by the same exact predicates as detection.
// Moves chosen during one step are committed, and later candidates are measured against the
// positions they leave. The broad phase is the scene hierarchy (its boxes must hold the positions
// at sync) for triangles neither the candidate nor a committed move touches, a sweep over current
// boxes among the others.
class TrialMove {
 public:
  explicit TrialMove(const SceneTopology& topology);
  // Starts a step: the topology's current positions, `set` their crossings.
  void sync(const CrossingSet& set);
  // vertices[i] would move to at[i]. With `stop_above_before`, counting stops once `after` is
  // sure to exceed `before`, and `after` is then only some number above it.
  TrialCount count(const DetectSettings& settings, const SceneHierarchy& hierarchy,
                   const CrossingSet& set, const std::vector<std::uint32_t>& vertices,
                   const std::vector<Vec3>& at, bool stop_above_before = false);
  // The move is made in this step: later counts see it.
  void commit(const std::vector<std::uint32_t>& vertices, const std::vector<Vec3>& at);

 private:
  // Distinct crossings with an edge or face of a `touched` triangle at points_, stopping once
  // more than `limit` are found.
  std::size_t crossings_of(const DetectSettings& settings, const SceneHierarchy& hierarchy,
                           const std::vector<std::uint32_t>& touched, std::size_t limit);

  const SceneTopology& topology_;
  std::vector<Vec3> points_;             // positions at sync, with committed moves and a candidate
  std::vector<std::uint8_t> affected_;   // per triangle: touched by the candidate, during a count
  std::vector<std::uint8_t> committed_;  // per triangle: touched by a committed move
  std::vector<std::uint32_t> committed_list_;
  std::vector<std::uint32_t> faces_;     // per triangle, crossings through it at sync
};

}  // namespace untangle
