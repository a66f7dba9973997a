// Morton codes of points in a box (10 bits an axis, 30 in all) and a stable sort by them: the
// orders the hierarchies are built from (detection's TriangleBvh, the winding numbers).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "geometry/box3.h"

namespace untangle {

// Spreads the lower 10 bits of x to every third bit.
inline std::uint32_t morton_spread(std::uint32_t x) {
  x &= 0x3ff;
  x = (x | x << 16) & 0x030000ff;
  x = (x | x << 8) & 0x0300f00f;
  x = (x | x << 4) & 0x030c30c3;
  x = (x | x << 2) & 0x09249249;
  return x;
}

// The code of point c in box `all`: its cell of a 1024^3 grid over the box, axes interleaved.
inline std::uint32_t morton_code(const Vec3& c, const Box3& all) {
  std::uint32_t code = 0;
  for (int a = 0; a < 3; ++a) {
    const double extent = all.hi[a] - all.lo[a];
    const double unit = extent > 0.0 ? (c[a] - all.lo[a]) / extent : 0.0;
    const auto cell = static_cast<std::uint32_t>(std::min(std::max(unit, 0.0), 1.0) * 1023.0);
    code |= morton_spread(cell) << a;
  }
  return code;
}

// Stable LSD radix sort of `order` by `code` (three passes of 10 bits): equal codes keep their
// order, so the result is the order of (code, position) and deterministic.
inline void sort_by_code(const std::vector<std::uint32_t>& code,
                         std::vector<std::uint32_t>& order) {
  std::vector<std::uint32_t> scratch(order.size());
  for (int shift = 0; shift < 30; shift += 10) {
    std::uint32_t count[1025] = {};
    for (std::uint32_t i : order) ++count[((code[i] >> shift) & 1023u) + 1];
    for (int k = 0; k < 1024; ++k) count[k + 1] += count[k];
    for (std::uint32_t i : order) scratch[count[(code[i] >> shift) & 1023u]++] = i;
    order.swap(scratch);
  }
}

// Where a range of entries sorted by code splits into the two halves of the octree cell it fills:
// the first entry of [first, first + count) with the highest bit set in which the range's first
// and last codes differ (an offset into the range), or count / 2 where every code is the same.
inline std::uint32_t code_split(const std::vector<std::uint32_t>& sorted, std::uint32_t first,
                                std::uint32_t count) {
  const std::uint32_t a = sorted[first], b = sorted[first + count - 1];
  if (a == b) return count / 2;
  int bit = 31;
  while (((a ^ b) >> bit & 1u) == 0) --bit;
  const std::uint32_t upper = b >> bit << bit;  // b's prefix down to that bit, zeros below
  const auto begin = sorted.begin() + first;
  return static_cast<std::uint32_t>(std::lower_bound(begin, begin + count, upper) - begin);
}

}  // namespace untangle
