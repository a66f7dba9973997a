// ldlt_solve_columns gives, bit for bit, what Eigen's SimplicialLDLT::solve gives each column
// alone: on grid Laplacians like the cloth's and the relaxation's matrices (with rows fixed to
// identities, as pinned particles and held vertices make them), for dense right sides, for right
// sides with zeros (Eigen skips a column's update there) and for negative zeros.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <vector>

#include "geometry/ldlt_columns.h"

namespace untangle {
namespace {

// An n x n grid's Laplacian plus `anchor` on the diagonal, rows of every `fixed_every`-th vertex
// made identities scaled by their degree.
Eigen::SparseMatrix<double> grid_matrix(int side, double anchor, int fixed_every) {
  const int n = side * side;
  std::vector<Eigen::Triplet<double>> entries;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const int i = y * side + x;
      std::vector<int> neighbours;
      if (x > 0) neighbours.push_back(i - 1);
      if (x + 1 < side) neighbours.push_back(i + 1);
      if (y > 0) neighbours.push_back(i - side);
      if (y + 1 < side) neighbours.push_back(i + side);
      const double degree = static_cast<double>(neighbours.size());
      const bool fixed = fixed_every > 0 && i % fixed_every == 0;
      entries.emplace_back(i, i, fixed ? degree : degree * (1.0 + anchor));
      for (int j : neighbours) {
        const bool other_fixed = fixed_every > 0 && j % fixed_every == 0;
        entries.emplace_back(i, j, fixed || other_fixed ? 0.0 : -1.0);
      }
    }
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

void expect_same_as_eigen(const Ldlt& solver, const std::vector<std::array<double, 3>>& b) {
  const Eigen::Index n = solver.rows();
  std::vector<std::array<double, 3>> ours = b;
  ldlt_solve_columns(solver, ours);
  std::size_t differ = 0;
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd column(n);
    for (Eigen::Index i = 0; i < n; ++i) column(i) = b[static_cast<std::size_t>(i)][c];
    const Eigen::VectorXd theirs = solver.solve(column);
    for (Eigen::Index i = 0; i < n; ++i)
      if (std::memcmp(&theirs(i), &ours[static_cast<std::size_t>(i)][c], sizeof(double)) != 0)
        ++differ;
  }
  EXPECT_EQ(differ, 0u) << "of " << 3 * n << " values";
}

TEST(LdltColumns, SameBitsAsEigenColumnByColumn) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> value(-1.0, 1.0);
  for (const auto& [side, anchor, fixed_every] :
       std::vector<std::tuple<int, double, int>>{{5, 0.01, 0}, {31, 1e-3, 7}, {81, 0.5, 13}}) {
    Ldlt solver(grid_matrix(side, anchor, fixed_every));
    ASSERT_EQ(solver.info(), Eigen::Success);
    const std::size_t n = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
    std::vector<std::array<double, 3>> dense(n), sparse(n, {0.0, 0.0, 0.0});
    for (auto& row : dense)
      for (double& v : row) v = value(rng);
    // Zeros where Eigen skips a column's update, a negative zero, and one column all zero.
    for (std::size_t i = 0; i < n; i += 3) sparse[i] = {value(rng), 0.0, value(rng)};
    sparse[n / 2] = {-0.0, value(rng), 0.0};
    expect_same_as_eigen(solver, dense);
    expect_same_as_eigen(solver, sparse);
  }
}

}  // namespace
}  // namespace untangle
