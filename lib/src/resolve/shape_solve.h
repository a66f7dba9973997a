// Local–global shape targets for the relaxation (DESIGN §5, "Relaxation"): as-rigid-as-possible
// (Sorkine and Alexa 2007) over the relaxing vertices, with the input as the rest shape.
#pragma once

#include <Eigen/Sparse>
#include <cstdint>
#include <vector>

#include "geometry/vec3.h"
#include "topology/scene_topology.h"

namespace untangle {

// The energy sum_i sum_{j ~ i} |(x_i - x_j) - R_i (r_i - r_j)|^2 over the cells of the relaxing
// vertices, r the rest (input) positions and R_i the rotation that fits cell i best. Its minimum
// with every other vertex where it is keeps each 1-ring's shape (edge lengths and bending) and lets
// the ring turn: a push spreads into a bump the size the held vertices ask for, where averaging
// displacements (one ring per sweep) leaves compressed edges next to the held ones. Uniform
// weights: unit-free and never negative on the irregular triangles of real garments.
class ShapeSolve {
 public:
  // `part`: the relaxing welded vertices, ascending; `rest`: the input's welded positions;
  // `threads` as everywhere (0: all cores; the same result for every count).
  ShapeSolve(const SceneTopology& topo, const std::vector<Vec3>& rest,
             const std::vector<std::uint32_t>& part, int threads = 1);

  // A one-sided contact of part[i]: it stays on the side of the plane through `point` that
  // `normal` (unit) points to.
  struct Contact {
    bool active = false;
    Vec3 point{0.0, 0.0, 0.0};
    Vec3 normal{0.0, 0.0, 0.0};
  };

  // Targets for part (out[i] for part[i]) after `iterations` local–global iterations started at
  // `points`, or at `warm` (per part index) for the free part vertices when given: the last
  // targets, from which a few iterations reach what ten reach from `points`. part[i] with fixed[i]
  // set, and every vertex outside part, stays where it is. A vertex whose iterate goes past its
  // contact plane (`contacts`, per part index, or empty) is held: a term of the solve pulls it
  // toward the point of the plane under where its ring alone would put it (its row solved with
  // the last iterate's neighbours), and what ends past the plane is put onto it. That point
  // follows the neighbours one iteration late, so a patch held all over slides about a ring per
  // iteration: a 7 x 7 patch held everywhere, its border shifted by 2 edges, had its least moved
  // vertex at 0, 72% and 99.5% of the shift after 10, 30 and 100 iterations; the warm starts
  // carry that progress from solve to solve.
  // The matrix's pattern is ordered once; its numbers are factored again when the fixed vertices or
  // the contacts held change.
  void targets(const std::vector<Vec3>& points, const std::vector<std::uint8_t>& fixed,
               const std::vector<Contact>& contacts, int iterations, std::vector<Vec3>& out,
               const std::vector<Vec3>* warm = nullptr);

  // The unknowns factored so far, summed over the factorizations: the solve's work, counted so
  // that a bound on it does not depend on the machine.
  std::size_t factored_unknowns() const { return factored_unknowns_; }

 private:
  void factor(const std::vector<std::uint8_t>& fixed, const std::vector<std::uint8_t>& held);
  // The best rotation of vertex v's 1-ring from its rest to `x` (row-major 3x3).
  std::array<double, 9> fit_rotation(std::uint32_t v, const std::vector<Vec3>& x) const;

  const SceneTopology& topo_;
  const std::vector<Vec3>& rest_;
  const std::vector<std::uint32_t>& part_;
  int threads_;
  std::vector<std::uint32_t> local_;     // welded vertex -> index in part_, or kNone
  std::vector<std::uint8_t> factored_fixed_;
  std::vector<std::uint8_t> factored_held_;
  bool factored_ = false;
  std::size_t factored_unknowns_ = 0;
  bool analyzed_ = false;  // the pattern (the part's graph) is ordered
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
};

}  // namespace untangle
