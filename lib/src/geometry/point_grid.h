// PointGrid: points binned in cubic cells of one size, to visit those within that distance of a
// query (the 27 cells around it). A cell is keyed by its integer coordinates, so every point
// within `cell` of the query is visited wherever the cell boundaries fall, each once, in an order
// that depends only on what was added (the continuation's plan and the layering's overlaps).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "geometry/vec3.h"

namespace untangle {

class PointGrid {
 public:
  explicit PointGrid(double cell) : cell_(cell) {}

  void add(const Vec3& p, std::uint32_t id) { cells_[cell_of(p)].push_back(id); }

  // Calls visit(id) for every id added in the 27 cells around `p`: all within `cell` of it, and
  // some farther (the caller measures).
  template <class Visit>
  void for_each_near(const Vec3& p, Visit&& visit) const {
    const Cell c = cell_of(p);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(Cell{c.x + dx, c.y + dy, c.z + dz});
          if (it == cells_.end()) continue;
          for (std::uint32_t id : it->second) visit(id);
        }
  }

 private:
  struct Cell {
    std::int64_t x, y, z;
    bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct CellHash {
    std::size_t operator()(const Cell& c) const {
      // Mixed in unsigned arithmetic, where wrapping is defined.
      return static_cast<std::size_t>((static_cast<std::uint64_t>(c.x) * 73856093u) ^
                                      (static_cast<std::uint64_t>(c.y) * 19349663u) ^
                                      (static_cast<std::uint64_t>(c.z) * 83492791u));
    }
  };
  // Cell coordinates clamped (and a coordinate that is not a number in cell 0), so that the
  // conversion to an integer is defined.
  std::int64_t coordinate(double x) const {
    const double c = std::floor(x / cell_);
    return c == c ? static_cast<std::int64_t>(std::clamp(c, -1e15, 1e15)) : 0;
  }
  Cell cell_of(const Vec3& p) const {
    return Cell{coordinate(p[0]), coordinate(p[1]), coordinate(p[2])};
  }

  double cell_;
  std::unordered_map<Cell, std::vector<std::uint32_t>, CellHash> cells_;
};

}  // namespace untangle
