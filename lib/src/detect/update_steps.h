// The steps update_crossings (detect_crossings.h) is made of, shared with the update over a list
// of candidate pairs (pair_list.h). Internal to detect/.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "detect/detect_crossings.h"

namespace untangle {

constexpr std::size_t kParts = 64;  // parts per descent of two hierarchies (run in parallel)

inline int shared_vertices(const std::array<std::uint32_t, 3>& a,
                           const std::array<std::uint32_t, 3>& b) {
  int n = 0;
  for (std::uint32_t x : a)
    for (std::uint32_t y : b)
      if (x == y) ++n;
  return n;
}

// The narrow phase of an update for one candidate pair (t the retested triangle, or the lower of
// two retested ones): the pruning test, then t's owned edges through u and u's through t.
void test_pair(const SceneTopology& topology, std::uint32_t t, std::uint32_t u,
               const TriPlane& plane_t, const TriPlane& plane_u, std::vector<RawCrossing>& out);

// The crossings after an update: those of `previous` whose edge and face kept all their vertices,
// and those `found` among the retested pairs, sorted and unique.
CrossingSet merge_update(const SceneTopology& topology, const CrossingSet& previous,
                         const std::vector<std::uint8_t>& moved,
                         const std::vector<std::vector<RawCrossing>>& found);

}  // namespace untangle
