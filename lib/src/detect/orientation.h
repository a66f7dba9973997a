// The one orientation predicate of detection: exact, with one consistent symbolic perturbation.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "untangle/mesh.h"

namespace untangle {

// Sign (+1 or -1, never 0) of the orientation of the points with global ids a, b, c, d, in the
// convention of CGAL::orientation: +1 when d lies on the positive side of the plane (a, b, c).
// Decided by CGAL's filtered exact predicate; an exact zero is resolved by Simulation of
// Simplicity (Edelsbrunner & Mücke 1990): coordinate j of the point with id i is perturbed by
// eps^(2^(3i - j)), so the result depends only on the coordinates and on the order of the ids.
// Every predicate made from it therefore describes one and the same perturbed, generic scene.
int orient_sos(const std::vector<Vec3>& points, std::uint32_t a, std::uint32_t b,
               std::uint32_t c, std::uint32_t d);

// Shewchuk's floating-point filter for orient3d ("Adaptive precision floating-point arithmetic",
// 1997, error bound A): the sign of det[b-a, c-a, d-a] (CGAL::orientation(a, b, c, d)) when the
// rounded determinant exceeds its error bound, else 0 (undecided: ask the exact predicate). The
// bound (7 + 56 eps) eps = 7.77e-16 of the permanent is taken as 8e-16, and tiny permanents (where
// underflow could break it) are left undecided, so a nonzero answer is always the exact sign.
// A plane is prepared once for several query points: its minors are shared.
class PlaneFilter {
 public:
  PlaneFilter(const Vec3& a, const Vec3& b, const Vec3& c) : a_(a) {
    const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
    const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
    n_ = {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
    m_ = {std::abs(uy * vz) + std::abs(uz * vy), std::abs(uz * vx) + std::abs(ux * vz),
          std::abs(ux * vy) + std::abs(uy * vx)};
  }
  int side(const Vec3& d) const {
    const double wx = d[0] - a_[0], wy = d[1] - a_[1], wz = d[2] - a_[2];
    const double det = wx * n_[0] + wy * n_[1] + wz * n_[2];
    const double permanent = std::abs(wx) * m_[0] + std::abs(wy) * m_[1] + std::abs(wz) * m_[2];
    const double bound = 8e-16 * permanent;
    if (!(permanent > 1e-150)) return 0;
    if (det > bound) return 1;
    if (-det > bound) return -1;
    return 0;
  }

 private:
  Vec3 a_, n_, m_;
};

inline int orient_filtered(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return PlaneFilter(a, b, c).side(d);
}

// The perturbed sign alone (exact arithmetic throughout): exposed for tests.
int orient_symbolic(const Vec3& pa, const Vec3& pb, const Vec3& pc, const Vec3& pd,
                    std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d);

}  // namespace untangle
