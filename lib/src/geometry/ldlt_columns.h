// Three right-hand sides solved at once with a factored SimplicialLDLT: bit for bit what Eigen's
// solve gives each column alone (the same operations on every column, in the same order), but the
// factor is read once for the three where Eigen's triangular solves read it once a column. The
// cloth's and the relaxation's solves are x, y and z with one matrix (issues 19 and 24).
#pragma once

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <array>
#include <vector>

namespace untangle {

using Ldlt = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>;

// Replaces each row of `rows` (an n x 3 right side, row-interleaved) with the solution of
// A x = b for that column. Eigen 3.4's steps, column by column (SimplicialCholeskyBase::_solve_impl
// and the sparse triangular solvers): x = P b; L x = x (unit lower, column-major, a column skipped
// where its entry is 0); x = D^-1 x (1 / d times x); L^T x = x (the transpose read row by row);
// x = P^-1 x. A factorization that failed leaves `rows` as it is.
inline void ldlt_solve_columns(const Ldlt& solver, std::vector<std::array<double, 3>>& rows) {
  if (solver.info() != Eigen::Success) return;
  const Eigen::Index n = solver.rows();
  const auto& perm = solver.permutationP();
  std::vector<std::array<double, 3>> x(static_cast<std::size_t>(n));
  if (perm.size() > 0) {
    for (Eigen::Index i = 0; i < n; ++i)
      x[static_cast<std::size_t>(perm.indices()(i))] = rows[static_cast<std::size_t>(i)];
  } else {
    x = rows;
  }
  const Eigen::SparseMatrix<double>& lower = solver.matrixL().nestedExpression();
  if (lower.nonZeros() > 0) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const std::array<double, 3> t = x[static_cast<std::size_t>(i)];
      if (t[0] == 0.0 && t[1] == 0.0 && t[2] == 0.0) continue;
      Eigen::SparseMatrix<double>::InnerIterator it(lower, i);
      while (it && it.index() < i) ++it;
      if (it && it.index() == i) ++it;
      for (; it; ++it) {
        std::array<double, 3>& r = x[static_cast<std::size_t>(it.index())];
        const double v = it.value();
        for (int c = 0; c < 3; ++c)
          if (t[c] != 0.0) r[c] -= t[c] * v;
      }
    }
  }
  const auto& diagonal = solver.vectorD();
  if (diagonal.size() > 0)
    for (Eigen::Index i = 0; i < n; ++i) {
      const double inverse = 1.0 / diagonal(i);
      for (double& value : x[static_cast<std::size_t>(i)]) value = inverse * value;
    }
  if (lower.nonZeros() > 0) {
    for (Eigen::Index i = n - 1; i >= 0; --i) {
      std::array<double, 3> t = x[static_cast<std::size_t>(i)];
      Eigen::SparseMatrix<double>::InnerIterator it(lower, i);
      while (it && it.index() < i) ++it;
      if (it && it.index() == i) ++it;
      for (; it; ++it) {
        const std::array<double, 3>& r = x[static_cast<std::size_t>(it.index())];
        const double v = it.value();
        for (int c = 0; c < 3; ++c) t[c] -= v * r[c];
      }
      x[static_cast<std::size_t>(i)] = t;
    }
  }
  const auto& inverse = solver.permutationPinv();
  if (inverse.size() > 0) {
    for (Eigen::Index i = 0; i < n; ++i)
      rows[static_cast<std::size_t>(inverse.indices()(i))] = x[static_cast<std::size_t>(i)];
  } else {
    rows = std::move(x);
  }
}

}  // namespace untangle
