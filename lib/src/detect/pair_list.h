// The candidate pairs of a set of triangles that move a little at a time (a Verlet list): found
// once by a descent of the hierarchies with the triangles' boxes grown by more than twice a
// reach, then reused by every update while no corner of theirs has moved farther than the reach
// from its reference; the triangles at a corner that has are listed again alone. The relaxation
// moves the same few thousand triangles pass after pass and sweep after sweep by a fraction of an
// edge; each of its updates descended the hierarchies again and built trees over the moved
// triangles and over the rest of their mesh.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "detect/detect_crossings.h"

namespace untangle {

class PairList {
 public:
  // Over `triangles` (global ids, ascending); `reach` in scene units, positive.
  PairList(std::vector<std::uint32_t> triangles, double reach);

  // Whether the list has been made and every corner of the listed triangles lies within the reach
  // of its reference (where it was when the list was made or its triangles last listed again),
  // coordinate by coordinate.
  bool holds(const SceneTopology& topology) const;

  // Makes the list at the current positions, or brings it up to date: the listed triangles at a
  // corner that went beyond the reach are listed again, that corner's position now its reference.
  // Then every pair of a listed triangle t and a triangle u of a tree of `hierarchy` or of
  // settings.skipped_bvh (both at the current positions) that the update of update_crossings
  // would test (the mesh filters of `settings`, at most one shared corner) and whose boxes may
  // overlap while the list holds is in it, each unordered pair once.
  void prepare(const SceneTopology& topology, const DetectSettings& settings,
               const SceneHierarchy& hierarchy);

  double reach() const { return reach_; }
  const std::vector<std::uint32_t>& triangles() const { return triangles_; }
  // The partners of listed triangle i (an index into triangles()) in the pairs, and the index of
  // triangle t among the listed ones (kNone for another).
  struct Range {
    const std::uint32_t* first;
    const std::uint32_t* last;
    const std::uint32_t* begin() const { return first; }
    const std::uint32_t* end() const { return last; }
  };
  Range adjacent(std::uint32_t i) const {
    return {adjacent_.data() + adjacent_begin_[i], adjacent_.data() + adjacent_begin_[i + 1]};
  }
  std::uint32_t slot(std::uint32_t t) const { return slot_[t]; }

 private:
  std::vector<std::uint32_t> triangles_;
  double reach_;
  bool made_ = false;
  std::vector<std::uint32_t> corners_;  // the listed triangles' vertices, ascending
  std::vector<Vec3> at_;                // per corner: its reference position
  std::vector<std::array<std::uint32_t, 2>> pairs_;
  std::vector<std::uint8_t> scratch_;
  std::vector<std::uint32_t> slot_;  // per triangle of the scene: its index in triangles_, or kNone
  // The pairs by listed triangle (each under both of its listed triangles), CSR.
  std::vector<std::uint32_t> adjacent_begin_, adjacent_;

  void index();  // adjacent_ from pairs_
  bool beyond(const Vec3& p,
              const Vec3& reference) const;  // farther than the reach, per coordinate

  void make(const SceneTopology& topology, const DetectSettings& settings,
            const std::vector<std::pair<const TriangleBvh*, bool>>& trees);
  bool wanted(const SceneTopology& topology, const DetectSettings& settings, std::uint32_t t,
              std::uint32_t u, bool from_shared) const;
};

// update_crossings (detect_crossings.h) with the pairs of `list` in place of the descents: the
// same crossings, provided list.holds(topology) and every vertex flagged in `moved` is a corner of
// a listed triangle. It walks the pairs of the listed triangles with a moved corner only.
CrossingSet update_crossings(const SceneTopology& topology, const DetectSettings& settings,
                             const PairList& list, const CrossingSet& previous,
                             const std::vector<std::uint8_t>& moved);

}  // namespace untangle
