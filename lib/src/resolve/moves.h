// The moves a step proposes, per welded vertex, and the candidate moves that are measured before
// they are made. Every move kind adds to one Moves; only the loop applies it (apply_moves.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "geometry/vec3.h"
#include "resolve/surface_queries.h"

namespace untangle {

// Maps a position to what the output file will store (float32, short decimals); empty = exact.
using Rounding = std::function<Vec3(const Vec3&)>;

// Accumulated moves of one step, per welded vertex: a region move (the whole vertex set goes
// across, as far as it must) wins over the DRN steps of the crossings at the vertex (averaged,
// capped).
struct Moves {
  std::vector<Vec3> region;
  std::vector<std::uint8_t> has_region;
  std::vector<Vec3> drn;
  std::vector<std::uint32_t> drn_count;

  explicit Moves(std::size_t n)
      : region(n, Vec3{0, 0, 0}), has_region(n, 0), drn(n, Vec3{0, 0, 0}), drn_count(n, 0) {}

  void push_drn(std::uint32_t v, const Vec3& d) {
    drn[v] = add(drn[v], d);
    ++drn_count[v];
  }
  void add_region(const std::vector<std::uint32_t>& part, const std::vector<Vec3>& delta) {
    for (std::size_t i = 0; i < part.size(); ++i) {
      region[part[i]] = add(region[part[i]], delta[i]);
      has_region[part[i]] = 1;
    }
  }
};

// A set of vertices that could move across another surface (`tree`), as a region.
struct Candidate {
  std::uint32_t mesh;
  int orientation;  // of the other surface: closed_orientations, 0 for a local patch
  std::vector<std::uint32_t> vertices;
  const MeshTree* tree;
};

// A measured move: the vertices it moves, how, and what it gains.
struct Choice {
  long long gain = std::numeric_limits<long long>::min();  // crossings removed
  double strain = INFINITY;
  std::vector<std::uint32_t> part;
  std::vector<Vec3> delta;
  std::vector<Vec3> at;  // the part's positions after the move

  // Adds vertex v, now at `from`, moved to `target` as the file will store it; a vertex the
  // rounding leaves where it is does not move.
  void propose(std::uint32_t v, const Vec3& from, Vec3 target, const Rounding& round) {
    if (round) target = round(target);
    if (target == from) return;
    part.push_back(v);
    delta.push_back(sub(target, from));
    at.push_back(target);
  }
};

// One connected part of a set to move and its candidate displacements (per vertex of `part`,
// ascending), each with its strain.
struct PartMoves {
  std::vector<std::uint32_t> part;
  std::vector<std::vector<Vec3>> options;
  std::vector<double> strain;
  std::size_t least_strain() const {
    return static_cast<std::size_t>(std::min_element(strain.begin(), strain.end()) -
                                    strain.begin());
  }
};

}  // namespace untangle
