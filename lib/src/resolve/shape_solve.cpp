// As-rigid-as-possible targets for the relaxation (shape_solve.h): one sparse Cholesky
// factorization of the graph Laplacian over the unknowns, a rotation fitted per 1-ring per
// iteration.
#include "resolve/shape_solve.h"

#include <Eigen/Dense>
#include <Eigen/SVD>

namespace untangle {
namespace {

// Keeps a 1-ring that has no fixed vertex anywhere around it from making the matrix singular:
// a weight this small toward where the iteration starts changes nothing else.
constexpr double kAnchor = 1e-9;
// The stiffness of a held contact, against the unit weight of each edge.
constexpr double kContact = 1e3;

}  // namespace

ShapeSolve::ShapeSolve(const SceneTopology& topo, const std::vector<Vec3>& rest,
                       const std::vector<std::uint32_t>& part)
    : topo_(topo), rest_(rest), part_(part), local_(topo.points.size(), kNone) {
  for (std::uint32_t i = 0; i < part.size(); ++i) local_[part[i]] = i;
}

std::array<double, 9> ShapeSolve::fit_rotation(std::uint32_t v, const std::vector<Vec3>& x) const {
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
    const std::uint32_t w = topo_.vertex_neighbors[j];
    const Vec3 r = sub(rest_[v], rest_[w]);
    const Vec3 e = sub(x[v], x[w]);
    covariance += Eigen::Vector3d(r[0], r[1], r[2]) * Eigen::Vector3d(e[0], e[1], e[2]).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  Eigen::Matrix3d rotation = svd.matrixV() * u.transpose();
  if (rotation.determinant() < 0.0) {  // a reflection: turn the axis of least spread over
    u.col(2) = -u.col(2);
    rotation = svd.matrixV() * u.transpose();
  }
  std::array<double, 9> out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = rotation(r, c);
  return out;
}

void ShapeSolve::factor(const std::vector<std::uint8_t>& fixed,
                        const std::vector<Contact>& contacts,
                        const std::vector<std::uint8_t>& held) {
  unknown_.assign(part_.size(), kNone);
  std::uint32_t count = 0;
  for (std::uint32_t i = 0; i < part_.size(); ++i)
    if (!fixed[i]) unknown_[i] = count++;
  // Three rows per unknown (x, y, z): the Laplacian on each coordinate, and on a held contact
  // kContact n n^T, which couples them.
  std::vector<Eigen::Triplet<double>> entries;
  for (std::uint32_t i = 0; i < part_.size(); ++i) {
    const std::uint32_t k = unknown_[i];
    if (k == kNone) continue;
    const std::uint32_t v = part_[i];
    const double degree = topo_.vertex_edge_begin[v + 1] - topo_.vertex_edge_begin[v];
    for (int c = 0; c < 3; ++c) entries.emplace_back(3 * k + c, 3 * k + c, degree * (1.0 + kAnchor));
    if (held[i]) {
      const Vec3& n = contacts[i].normal;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) entries.emplace_back(3 * k + r, 3 * k + c, kContact * degree * n[r] * n[c]);
    }
    for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
      const std::uint32_t l = local_[topo_.vertex_neighbors[j]];
      if (l != kNone && unknown_[l] != kNone)
        for (int c = 0; c < 3; ++c) entries.emplace_back(3 * k + c, 3 * unknown_[l] + c, -1.0);
    }
  }
  Eigen::SparseMatrix<double> matrix(3 * count, 3 * count);
  matrix.setFromTriplets(entries.begin(), entries.end());
  solver_.compute(matrix);
  factored_fixed_ = fixed;
  factored_held_ = held;
  factored_ = true;
}

void ShapeSolve::targets(const std::vector<Vec3>& points, const std::vector<std::uint8_t>& fixed,
                         const std::vector<Contact>& contacts, int iterations,
                         std::vector<Vec3>& out) {
  std::vector<std::uint8_t> held(part_.size(), 0);
  auto below = [&](std::uint32_t i, const std::vector<Vec3>& x) {
    return !contacts.empty() && contacts[i].active &&
           dot(sub(x[part_[i]], contacts[i].point), contacts[i].normal) < 0.0;
  };
  std::vector<Vec3> x = points;  // the iterate, over every welded vertex (only part changes)
  for (std::uint32_t i = 0; i < part_.size(); ++i) held[i] = below(i, x);
  out.resize(part_.size());
  // Rotations of the part's vertices and of their neighbours (every cell an unknown's edges lie in).
  std::vector<std::uint32_t> cells;
  std::vector<std::uint32_t> cell_of(topo_.points.size(), kNone);
  for (std::uint32_t v : part_) {
    if (cell_of[v] == kNone) cell_of[v] = static_cast<std::uint32_t>(cells.size()), cells.push_back(v);
    for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
      const std::uint32_t w = topo_.vertex_neighbors[j];
      if (cell_of[w] == kNone) cell_of[w] = static_cast<std::uint32_t>(cells.size()), cells.push_back(w);
    }
  }
  std::vector<std::array<double, 9>> rotation(cells.size());
  for (int iteration = 0; iteration < iterations; ++iteration) {
    if (!factored_ || fixed != factored_fixed_ || held != factored_held_) factor(fixed, contacts, held);
    const Eigen::Index rows = solver_.rows();
    if (rows == 0 || solver_.info() != Eigen::Success) break;
    for (std::size_t c = 0; c < cells.size(); ++c) rotation[c] = fit_rotation(cells[c], x);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(rows);
    for (std::uint32_t i = 0; i < part_.size(); ++i) {
      const std::uint32_t k = unknown_[i];
      if (k == kNone) continue;
      const std::uint32_t v = part_[i];
      const double degree = topo_.vertex_edge_begin[v + 1] - topo_.vertex_edge_begin[v];
      for (int c = 0; c < 3; ++c) rhs[3 * k + c] += kAnchor * degree * x[v][c];
      if (held[i]) {
        const Vec3& n = contacts[i].normal;
        const double level = dot(n, contacts[i].point);
        for (int c = 0; c < 3; ++c) rhs[3 * k + c] += kContact * degree * level * n[c];
      }
      const auto& rv = rotation[cell_of[v]];
      for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
        const std::uint32_t w = topo_.vertex_neighbors[j];
        const auto& rw = rotation[cell_of[w]];
        const Vec3 r = sub(rest_[v], rest_[w]);
        for (int c = 0; c < 3; ++c) {
          double turned = 0.0;
          for (int d = 0; d < 3; ++d) turned += 0.5 * (rv[3 * c + d] + rw[3 * c + d]) * r[d];
          rhs[3 * k + c] += turned;
        }
        const std::uint32_t l = local_[w];
        if (l == kNone || unknown_[l] == kNone)
          for (int c = 0; c < 3; ++c) rhs[3 * k + c] += x[w][c];
      }
    }
    const Eigen::VectorXd solved = solver_.solve(rhs);
    for (std::uint32_t i = 0; i < part_.size(); ++i)
      if (unknown_[i] != kNone)
        for (int c = 0; c < 3; ++c) x[part_[i]][c] = solved[3 * unknown_[i] + c];
    for (std::uint32_t i = 0; i < part_.size(); ++i) held[i] = held[i] || below(i, x);
  }
  // What is still a little past its plane (the term is stiff, not hard) goes onto it.
  for (std::size_t i = 0; i < part_.size(); ++i) {
    out[i] = x[part_[i]];
    if (below(static_cast<std::uint32_t>(i), x))
      out[i] = sub(out[i], scale(contacts[i].normal,
                                 dot(sub(out[i], contacts[i].point), contacts[i].normal)));
  }
}

}  // namespace untangle
