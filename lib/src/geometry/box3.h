// Axis-aligned boxes: the broad phase of detection and of trial moves, and the culling grid.
#pragma once

#include <algorithm>
#include <array>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

struct Box3 {
  std::array<double, 3> lo{}, hi{};
  // Closed boxes: touching counts. All six comparisons without early exits: in a descent the
  // outcome is not predictable, and a mispredicted branch costs more than the comparisons.
  bool overlaps(const Box3& o) const {
    bool apart = false;
    for (int k = 0; k < 3; ++k) apart |= (hi[k] < o.lo[k]) | (o.hi[k] < lo[k]);
    return !apart;
  }
};

// The smallest box holding the corners of `tri`, indices into `points`.
inline Box3 triangle_box(const std::vector<Vec3>& points, const Triangle& tri) {
  Box3 b;
  const Vec3& p = points[tri[0]];
  b.lo = p;
  b.hi = p;
  for (int k = 1; k < 3; ++k) {
    const Vec3& q = points[tri[k]];
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], q[a]);
      b.hi[a] = std::max(b.hi[a], q[a]);
    }
  }
  return b;
}

// The squared distance from p to the nearest point of box b (0 inside it), in doubles.
inline double squared_distance_to(const Box3& b, const Vec3& p) {
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double d = std::max(std::max(b.lo[k] - p[k], p[k] - b.hi[k]), 0.0);
    sum += d * d;
  }
  return sum;
}

inline Box3 merged(const Box3& a, const Box3& b) {
  Box3 out;
  for (int k = 0; k < 3; ++k) {
    out.lo[k] = a.lo[k] < b.lo[k] ? a.lo[k] : b.lo[k];
    out.hi[k] = a.hi[k] > b.hi[k] ? a.hi[k] : b.hi[k];
  }
  return out;
}

}  // namespace untangle
