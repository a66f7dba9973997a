// As-rigid-as-possible targets for the relaxation (shape_solve.h): a sparse Cholesky
// factorization of the graph Laplacian over the part (ordered once per part, one scalar matrix for
// the three coordinates), a rotation fitted per 1-ring per iteration in closed form.
#include "resolve/shape_solve.h"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "detect/run_parallel.h"
#include "geometry/ldlt_columns.h"

namespace untangle {
namespace {

// Keeps a 1-ring that has no fixed vertex anywhere around it from making the matrix singular:
// a weight this small toward where the iteration starts changes nothing else.
constexpr double kAnchor = 1e-9;
// The weight of a held contact against the unit weight of each edge. The term pulls the vertex
// toward the point of its plane under where its ring alone would put it, the same in x, y and z,
// so that one scalar matrix serves the three coordinates: on the MakeHuman garments the 3x3 block
// n n^T (weight 1e3) of a held vertex coupled the coordinates of every vertex near the body, and
// factoring the coupled matrix was 45% of female_casualsuit01's fix (280,636 entries in the
// factor of 6,531 unknowns). Pulled toward its own projection instead, a held vertex stayed where
// it was along the plane (weight 10: the continuation on the body x 1.05 stalled). Weights 10, 100
// and 1000 gave the six garments largest edge ratios within 0.07 of each other; 100 the lowest
// on five (DESIGN §5).
constexpr double kContact = 100.0;
// Iterations after which the held contacts may still grow; each growth is a new factorization.
// Later iterations keep them, and what ends past its plane is put onto it. Unbounded, the
// MakeHuman garments took 2 to 3 times the factorizations for the same shapes (female_casualsuit01
// 260 against 114, largest edge ratio 1.36 against 1.34).
constexpr int kHeldUpdates = 2;
constexpr std::size_t kGrain = 256;  // cells or part vertices per parallel block

}  // namespace

ShapeSolve::ShapeSolve(const SceneTopology& topo, const std::vector<Vec3>& rest,
                       const std::vector<std::uint32_t>& part, int threads)
    : topo_(topo), rest_(rest), part_(part), threads_(threads), local_(topo.points.size(), kNone) {
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
  // The polar factor from the eigenvectors of C^T C (closed form for 3x3, several times cheaper
  // than an SVD): C v_k = s_k u_k for the two largest s_k, and the third axes of both frames are
  // their cross products, so the rotation is proper (the SVD's reflection fix). A 1-ring that has
  // collapsed to a line or a point falls back to the SVD.
  Eigen::Matrix3d rotation;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(covariance.transpose() * covariance);
  const Eigen::Vector3d lambda = eigen.eigenvalues();  // ascending
  if (eigen.info() == Eigen::Success && lambda[2] > 0.0 && lambda[1] > 1e-20 * lambda[2]) {
    Eigen::Vector3d v1 = eigen.eigenvectors().col(2).normalized();
    Eigen::Vector3d v2 = eigen.eigenvectors().col(1);
    v2 = (v2 - v1.dot(v2) * v1).normalized();
    const Eigen::Vector3d u1 = (covariance * v1).normalized();
    Eigen::Vector3d u2 = covariance * v2;
    u2 = (u2 - u1.dot(u2) * u1).normalized();
    rotation = v1 * u1.transpose() + v2 * u2.transpose() + v1.cross(v2) * u1.cross(u2).transpose();
  } else {
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d u = svd.matrixU();
    rotation = svd.matrixV() * u.transpose();
    if (rotation.determinant() < 0.0) {  // a reflection: turn the axis of least spread over
      u.col(2) = -u.col(2);
      rotation = svd.matrixV() * u.transpose();
    }
  }
  std::array<double, 9> out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = rotation(r, c);
  return out;
}

void ShapeSolve::factor(const std::vector<std::uint8_t>& fixed, const std::vector<std::uint8_t>& held) {
  // One row per part vertex, the same matrix for x, y and z (solved as three columns): a fixed
  // vertex is an identity row (scaled by its degree) whose couplings are explicit zeros, so the
  // pattern never changes and is ordered once per part; a held vertex adds its contact weight to
  // the diagonal.
  std::vector<Eigen::Triplet<double>> entries;
  for (std::uint32_t i = 0; i < part_.size(); ++i) {
    const std::uint32_t v = part_[i];
    const double degree = topo_.vertex_edge_begin[v + 1] - topo_.vertex_edge_begin[v];
    const bool free = !fixed[i];
    double value = degree * (free ? 1.0 + kAnchor : 1.0);
    if (free && held[i]) value += kContact * degree;
    entries.emplace_back(i, i, value);
    for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
      const std::uint32_t l = local_[topo_.vertex_neighbors[j]];
      if (l == kNone) continue;
      entries.emplace_back(i, l, free && !fixed[l] ? -1.0 : 0.0);
    }
  }
  const Eigen::Index n = static_cast<Eigen::Index>(part_.size());
  Eigen::SparseMatrix<double> matrix(n, n);
  matrix.setFromTriplets(entries.begin(), entries.end());
  if (!analyzed_) {
    solver_.analyzePattern(matrix);
    analyzed_ = true;
  }
  solver_.factorize(matrix);
  factored_unknowns_ += static_cast<std::size_t>(3 * n);  // x, y and z
  factored_fixed_ = fixed;
  factored_held_ = held;
  factored_ = true;
}

void ShapeSolve::targets(const std::vector<Vec3>& points, const std::vector<std::uint8_t>& fixed,
                         const std::vector<Contact>& contacts, int iterations,
                         std::vector<Vec3>& out, const std::vector<Vec3>* warm) {
  std::vector<std::uint8_t> held(part_.size(), 0);
  auto below = [&](std::uint32_t i, const std::vector<Vec3>& x) {
    return !contacts.empty() && contacts[i].active &&
           dot(sub(x[part_[i]], contacts[i].point), contacts[i].normal) < 0.0;
  };
  std::vector<Vec3> x = points;  // the iterate, over every welded vertex (only part changes)
  if (warm)
    for (std::uint32_t i = 0; i < part_.size(); ++i)
      if (!fixed[i]) x[part_[i]] = (*warm)[i];
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
  // Only the cells with a free part vertex in their 1-ring change after the first iteration: the
  // others keep their rotation (the same inputs give the same bits).
  std::vector<std::uint32_t> turning;
  for (std::uint32_t c = 0; c < cells.size(); ++c) {
    const std::uint32_t v = cells[c];
    auto free_at = [&](std::uint32_t w) { return local_[w] != kNone && !fixed[local_[w]]; };
    bool moves = free_at(v);
    for (std::uint32_t j = topo_.vertex_edge_begin[v]; !moves && j < topo_.vertex_edge_begin[v + 1]; ++j)
      moves = free_at(topo_.vertex_neighbors[j]);
    if (moves) turning.push_back(c);
  }
  std::vector<std::array<double, 9>> rotation(cells.size());
  for (int iteration = 0; iteration < iterations; ++iteration) {
    if (!factored_ || fixed != factored_fixed_ || held != factored_held_)
      factor(fixed, held);
    const Eigen::Index rows = solver_.rows();
    if (rows == 0 || solver_.info() != Eigen::Success) break;
    if (iteration == 0) {
      run_parallel(threads_, cells.size(), kGrain, [&](std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c) rotation[c] = fit_rotation(cells[c], x);
      });
    } else {
      run_parallel(threads_, turning.size(), kGrain, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) rotation[turning[k]] = fit_rotation(cells[turning[k]], x);
      });
    }
    std::vector<std::array<double, 3>> rhs(static_cast<std::size_t>(rows), {0.0, 0.0, 0.0});
    // Each part vertex writes its own row.
    run_parallel(threads_, part_.size(), kGrain, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const std::uint32_t v = part_[i];
        const double degree = topo_.vertex_edge_begin[v + 1] - topo_.vertex_edge_begin[v];
        if (fixed[i]) {
          for (int c = 0; c < 3; ++c) rhs[i][c] = degree * x[v][c];
          continue;
        }
        for (int c = 0; c < 3; ++c) rhs[i][c] += kAnchor * degree * x[v][c];
        const auto& rv = rotation[cell_of[v]];
        Vec3 wants{0.0, 0.0, 0.0};
        for (std::uint32_t j = topo_.vertex_edge_begin[v]; j < topo_.vertex_edge_begin[v + 1]; ++j) {
          const std::uint32_t w = topo_.vertex_neighbors[j];
          const auto& rw = rotation[cell_of[w]];
          const Vec3 r = sub(rest_[v], rest_[w]);
          for (int c = 0; c < 3; ++c) {
            double turned = 0.0;
            for (int d = 0; d < 3; ++d) turned += 0.5 * (rv[3 * c + d] + rw[3 * c + d]) * r[d];
            rhs[i][c] += turned;
            wants[c] += turned + x[w][c];
          }
          const std::uint32_t l = local_[w];
          if (l == kNone || fixed[l])
            for (int c = 0; c < 3; ++c) rhs[i][c] += x[w][c];
        }
        if (held[i]) {
          // Toward the plane, at the point under where the ring alone would put the vertex (its
          // row solved with the last iterate's neighbours): on the plane along its normal, free
          // along it.
          const Vec3& n = contacts[i].normal;
          const Vec3 free_at = scale(wants, 1.0 / degree);
          const Vec3 onto = sub(free_at, scale(n, dot(sub(free_at, contacts[i].point), n)));
          for (int c = 0; c < 3; ++c) rhs[i][c] += kContact * degree * onto[c];
        }
      }
    });
    ldlt_solve_columns(solver_, rhs);  // the same bits as Eigen's solve, the factor read once
    for (std::uint32_t i = 0; i < part_.size(); ++i)
      if (!fixed[i])
        for (int c = 0; c < 3; ++c) x[part_[i]][c] = rhs[i][c];
    if (iteration < kHeldUpdates)
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
