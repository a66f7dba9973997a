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
  int side(const Vec3& d) const { return along({d[0] - a_[0], d[1] - a_[1], d[2] - a_[2]}); }
  // The sign of det[b-a, c-a, w] for a vector w given exactly (not a rounded difference; the bound
  // holds all the more): side(d) is along(d - a).
  int along(const Vec3& w) const {
    const double wx = w[0], wy = w[1], wz = w[2];
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

// Exact sign of w . ((b - a) x (c - a)) for a direction w of small integers (exact, and exact in
// every product with a coordinate): the turn of a, b, c projected along w onto a plane normal to
// it, +1 counter-clockwise seen from where w points. PlaneFilter's bound, then exact arithmetic
// (CGAL::Mpzf). Along a coordinate axis it is orient_2d's turn (negated along y).
int orient_along(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& w);
// Exact sign of |w|^2 (c - b) . (b - a) - ((c - b) . w) ((b - a) . w), |w|^2 times the dot product
// of b - a and c - b projected along w: +1 when, projected, c lies ahead of b as seen from a.
int ahead_along(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& w);

// Exact sign of the orientation of a, b, c projected along axis `drop` onto the other two axes
// (i, j) in increasing order: +1 when (a, b, c) turns counter-clockwise in (i, j), as
// CGAL::orientation of the projected points; 0 when collinear there. Three points on a line
// parallel to an axis are collinear without arithmetic; then Shewchuk's orient2d filter (error
// bound A: (3 + 16 eps) eps times the sum of the magnitudes of the two products) decides inline,
// without building points, and orient_2d_exact the rest: exact expansion arithmetic
// (orient_2d_expansion), or CGAL's filtered predicate for magnitudes outside its range.
// Magnitudes near the underflow range, where the filter's bound does not hold, go there too.
int orient_2d_exact(const Vec3& a, const Vec3& b, const Vec3& c, int drop);

// The exact sign of (ax - cx)(by - cy) - (ay - cy)(bx - cx) (CGAL::orientation of the points
// (ax, ay), (bx, by), (cx, cy)) by floating-point expansion arithmetic (Shewchuk 1997: two-sum,
// two-product by fma): the differences as two-component expansions, their products as sixteen
// exact terms summed into a nonoverlapping expansion; when the differences are exact (grid
// points), two products and their errors. Returns 2 (undecided) when a coordinate or difference
// component is nonzero and outside [1e-140, 1e140], where a product's error could underflow or a
// sum overflow; orient_2d_exact then asks CGAL. Collinear grid points, where the filter of
// orient_2d cannot decide, need no CGAL arithmetic.
int orient_2d_expansion(double ax, double ay, double bx, double by, double cx, double cy);
inline int orient_2d(const Vec3& a, const Vec3& b, const Vec3& c, int drop) {
  const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
  if ((a[i] == b[i] && a[i] == c[i]) || (a[j] == b[j] && a[j] == c[j])) return 0;
  const double left = (a[i] - c[i]) * (b[j] - c[j]);
  const double right = (a[j] - c[j]) * (b[i] - c[i]);
  const double det = left - right;
  const double sum = std::abs(left) + std::abs(right);
  const double bound = 3.3306690738754716e-16 * sum;
  if (sum > 1e-280 && det > bound) return 1;
  if (sum > 1e-280 && -det > bound) return -1;
  return orient_2d_exact(a, b, c, drop);
}

// The exact side of points with respect to a plane normal to an axis: a, b, c have the same
// coordinate `axis` (bit for bit). Then det[b-a, c-a, d-a] = (d-a)[axis] * (the axis component of
// (b-a) x (c-a)), so side(d) is CGAL::orientation(a, b, c, d) from one comparison, with the
// triangle's turn in the plane decided once (orient_2d; detection makes it once per triangle, not
// per pair). Flat sheets make nearly every plane one of these; CGAL's filter would fall back to
// interval arithmetic on the exact zeros of the minors.
class AxisPlane {
 public:
  AxisPlane(const Vec3& a, const Vec3& b, const Vec3& c, int axis)
      : AxisPlane(a[axis], axis, turn_of(a, b, c, axis)) {}
  // The plane at coordinate `level` of `axis`, its corners' turn known (turn_of).
  AxisPlane(double level, int axis, int turn) : level_(level), axis_(axis), turn_(turn) {}
  int side(const Vec3& d) const {
    if (d[axis_] == level_) return 0;
    return d[axis_] > level_ ? turn_ : -turn_;
  }
  // The sign of the axis component of (b-a) x (c-a), from orient_2d along the axis (or its value
  // `turn`, made already).
  static int turn_for(int turn, int axis) { return axis == 1 ? -turn : turn; }
  static int turn_of(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
    return turn_for(orient_2d(a, b, c, axis), axis);
  }

 private:
  double level_;
  int axis_;
  int turn_;
};

// The perturbed sign alone (exact arithmetic throughout): exposed for tests.
int orient_symbolic(const Vec3& pa, const Vec3& pb, const Vec3& pc, const Vec3& pd,
                    std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d);

}  // namespace untangle
