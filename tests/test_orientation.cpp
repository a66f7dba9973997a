// The symbolic perturbation: agrees with CGAL off degeneracies, is antisymmetric, never zero.
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "detect/orientation.h"

namespace untangle {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;

int cgal_orientation(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return static_cast<int>(CGAL::orientation(K::Point_3(a[0], a[1], a[2]), K::Point_3(b[0], b[1], b[2]),
                                            K::Point_3(c[0], c[1], c[2]), K::Point_3(d[0], d[1], d[2])));
}

TEST(Orientation, AgreesWithCgalWhenNotDegenerate) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    std::vector<Vec3> p(4);
    for (auto& v : p) v = {u(rng), u(rng), u(rng)};
    const int expected = cgal_orientation(p[0], p[1], p[2], p[3]);
    ASSERT_NE(expected, 0);
    EXPECT_EQ(orient_sos(p, 0, 1, 2, 3), expected);
    EXPECT_EQ(orient_symbolic(p[0], p[1], p[2], p[3], 0, 1, 2, 3), expected);
  }
}

// Degenerate configurations on a 3x3x3 grid: the perturbed sign is never zero, flips under every
// transposition of arguments, and depends only on the ids, not on the argument order.
TEST(Orientation, PerturbedSignIsConsistentOnGridPoints) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> g(0, 2);
  int degenerate = 0;
  for (int i = 0; i < 3000; ++i) {
    std::vector<Vec3> p(6);
    for (auto& v : p) v = {double(g(rng)), double(g(rng)), double(g(rng))};
    std::array<std::uint32_t, 4> ids{0, 1, 2, 3};
    std::shuffle(ids.begin(), ids.end(), rng);
    if (cgal_orientation(p[0], p[1], p[2], p[3]) == 0) ++degenerate;
    const int s = orient_sos(p, ids[0], ids[1], ids[2], ids[3]);
    ASSERT_TRUE(s == 1 || s == -1);
    EXPECT_EQ(orient_sos(p, ids[1], ids[0], ids[2], ids[3]), -s);
    EXPECT_EQ(orient_sos(p, ids[0], ids[2], ids[1], ids[3]), -s);
    EXPECT_EQ(orient_sos(p, ids[0], ids[1], ids[3], ids[2]), -s);
    EXPECT_EQ(orient_sos(p, ids[1], ids[2], ids[3], ids[0]), -s);  // a 4-cycle is odd
    EXPECT_EQ(orient_sos(p, ids[1], ids[2], ids[0], ids[3]), s);   // a 3-cycle is even
  }
  EXPECT_GT(degenerate, 300);  // the grid really produces degenerate cases
}

// Coincident points: a point and its exact copy are told apart by their ids.
TEST(Orientation, CoincidentPointsAreSeparated) {
  const std::vector<Vec3> p{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}};
  const int s = orient_sos(p, 0, 1, 2, 3);
  EXPECT_TRUE(s == 1 || s == -1);
  EXPECT_EQ(orient_sos(p, 3, 1, 2, 0), -s);
}

// The floating-point filter answers only when it is sure: its nonzero signs equal CGAL's exact
// ones, on random points and on points rounded onto a plane (nearly coplanar, often exactly).
TEST(Orientation, FilterAgreesWithCgalWhenItAnswers) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int answered = 0, undecided = 0;
  for (int i = 0; i < 20000; ++i) {
    std::array<Vec3, 4> p;
    for (auto& v : p) v = {u(rng), u(rng), u(rng)};
    if (i % 2 == 1) {  // d near the plane (a, b, c): an affine combination, rounded
      const double s = u(rng), t = u(rng);
      for (int k = 0; k < 3; ++k) p[3][k] = p[0][k] + s * (p[1][k] - p[0][k]) + t * (p[2][k] - p[0][k]);
    }
    if (i % 7 == 0) {  // integer coordinates: exact zeros
      for (auto& v : p)
        for (double& x : v) x = std::round(4.0 * x);
    }
    const int sure = orient_filtered(p[0], p[1], p[2], p[3]);
    const int expected = cgal_orientation(p[0], p[1], p[2], p[3]);
    if (sure != 0) {
      ++answered;
      ASSERT_EQ(sure, expected) << "case " << i;
    } else {
      ++undecided;
    }
  }
  EXPECT_GT(answered, 10000);
  EXPECT_GT(undecided, 1000);
}

// Planes normal to an axis: AxisPlane's side equals CGAL's exact orientation for each axis, with
// the plane's corners on random, grid-snapped (collinear corners, points on the plane) and tiny or
// huge coordinates, and every order of the corners.
TEST(Orientation, AxisPlaneAgreesWithCgal) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> g(0, 2);
  int zeros = 0, flat_triangles = 0;
  for (int i = 0; i < 30000; ++i) {
    const int axis = i % 3;
    const double scale = i % 5 == 0 ? 1e-200 : i % 5 == 1 ? 1e200 : 1.0;
    std::array<Vec3, 4> p;
    for (auto& v : p) {
      for (double& x : v) x = (i % 4 == 0 ? double(g(rng)) : u(rng)) * scale;
    }
    for (int k = 1; k < 3; ++k) p[k][axis] = p[0][axis];
    if (i % 6 == 0) p[3][axis] = p[0][axis];
    std::array<int, 3> order{0, 1, 2};
    do {
      const Vec3 &a = p[order[0]], &b = p[order[1]], &c = p[order[2]];
      const int expected = cgal_orientation(a, b, c, p[3]);
      ASSERT_EQ(AxisPlane(a, b, c, axis).side(p[3]), expected) << "case " << i;
      zeros += expected == 0;
      flat_triangles += orient_2d(a, b, c, axis) == 0;
    } while (std::next_permutation(order.begin(), order.end()));
  }
  EXPECT_GT(zeros, 10000);
  EXPECT_GT(flat_triangles, 1000);
}

}  // namespace
}  // namespace untangle

namespace untangle {
namespace {

int cgal_orientation_2d(double ax, double ay, double bx, double by, double cx, double cy) {
  return static_cast<int>(CGAL::orientation(K::Point_2(ax, ay), K::Point_2(bx, by), K::Point_2(cx, cy)));
}

// The exact 2D orientation by expansion arithmetic equals CGAL's exact orientation on random,
// grid-snapped (collinear, coincident), exactly collinear points with inexact differences,
// nearly collinear, tiny and huge coordinates, in every order of the points; outside its range it
// answers 2 and orient_2d (which then asks CGAL) still agrees.
TEST(Orientation, ExpansionOrient2dAgreesWithCgal) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> g(-2, 2);
  std::uniform_int_distribution<int> e(-60, 60);
  int zeros = 0, inexact_zeros = 0, decided = 0, undecided = 0;
  const double scales[] = {1.0, 1e-130, 1e130, 1e-200, 1e200, 3.0e-320};
  for (int i = 0; i < 60000; ++i) {
    const int kind = i % 6;
    const double scale = scales[(i / 6) % 6];
    std::array<std::array<double, 2>, 3> p;
    if (kind == 0) {  // random
      for (auto& q : p) q = {u(rng) * scale, u(rng) * scale};
    } else if (kind == 1) {  // grid-snapped: collinear and coincident points, exact differences
      const double h = 0.0125 * scale;
      for (auto& q : p) q = {g(rng) * h + 0.3 * scale, g(rng) * h - 0.7 * scale};
    } else if (kind == 2) {  // on the line y = 2^k x: exactly collinear, differences inexact
      const double slope = std::ldexp(1.0, e(rng) / 10);
      for (auto& q : p) {
        const double x = std::ldexp(u(rng), e(rng)) * scale;
        q = {x, x * slope};
      }
    } else if (kind == 3) {  // nearly collinear: the third point rounded onto the line of two
      p[0] = {u(rng) * scale, u(rng) * scale};
      p[1] = {u(rng) * scale, u(rng) * scale};
      const double t = u(rng) * 3.0;
      p[2] = {p[0][0] + t * (p[1][0] - p[0][0]), p[0][1] + t * (p[1][1] - p[0][1])};
    } else if (kind == 4) {  // mixed magnitudes along a diagonal, with offsets
      for (auto& q : p) {
        const double x = std::ldexp(u(rng), e(rng)) * scale;
        q = {x, x};
      }
      p[i % 3][1] += std::ldexp(u(rng), e(rng) - 60) * scale;
    } else {  // a grid of a flat sheet: i / 80 steps from an offset origin, with diagonals
      const double h = 1.2 * scale / 80.0;
      for (auto& q : p) {
        const int k = g(rng) * 7, l = k + (i % 2 ? 0 : g(rng));
        q = {-0.61 * scale + k * h, 0.37 * scale + l * h};
      }
    }
    std::array<int, 3> order{0, 1, 2};
    do {
      const auto &a = p[order[0]], &b = p[order[1]], &c = p[order[2]];
      const int expected = cgal_orientation_2d(a[0], a[1], b[0], b[1], c[0], c[1]);
      const int got = orient_2d_expansion(a[0], a[1], b[0], b[1], c[0], c[1]);
      if (got == 2) {
        ++undecided;
      } else {
        ++decided;
        ASSERT_EQ(got, expected) << "case " << i << " kind " << kind;
        if (expected == 0) {
          ++zeros;
          double x, y;
          x = a[0] - c[0];
          y = a[0] - x - c[0];
          inexact_zeros += y != 0.0 || b[1] - c[1] - (b[1] - c[1]) != 0.0 || kind == 2;
        }
      }
      // orient_2d along axis 2 uses (x, y) = coordinates 0 and 1.
      ASSERT_EQ(orient_2d(Vec3{a[0], a[1], 0.0}, Vec3{b[0], b[1], 0.0}, Vec3{c[0], c[1], 0.0}, 2),
                expected)
          << "case " << i << " kind " << kind;
    } while (std::next_permutation(order.begin(), order.end()));
  }
  EXPECT_GT(zeros, 20000);
  EXPECT_GT(inexact_zeros, 5000);
  EXPECT_GT(decided, 100000);
  EXPECT_GT(undecided, 100000);  // the tiny and huge scales
}

// The oblique predicates of the flat-patch test against exact references: orient_along(a, b, c,
// w) is det[b-a, c-a, w], which is CGAL::orientation(a, b, c, a + w) when a + w is exact (points
// on a grid of 1/8); ahead_along against the same sum in 64-bit integers on that grid, scaled.
// Half of the cases are degenerate by construction (c on the line through a and b seen along w).
TEST(Orientation, ObliquePredicatesAreExact) {
  std::mt19937 rng(31);
  std::uniform_int_distribution<int> g(-40, 40), small(-2, 2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int zeros = 0;
  for (int i = 0; i < 4000; ++i) {
    Vec3 w{double(small(rng)), double(small(rng)), double(small(rng))};
    if (w[0] == 0 && w[1] == 0 && w[2] == 0) w[2] = 1;
    std::array<std::array<long long, 3>, 3> q{};
    for (auto& p : q)
      for (auto& c : p) c = g(rng);
    if (i % 2 == 0)  // c = a + t (b - a) + s w: collinear with a, b seen along w
      for (int k = 0; k < 3; ++k) q[2][k] = q[0][k] + 2 * (q[1][k] - q[0][k]) + static_cast<long long>(w[k]) * 3;
    Vec3 a, b, c;
    for (int k = 0; k < 3; ++k) {
      a[k] = q[0][k] / 8.0;
      b[k] = q[1][k] / 8.0;
      c[k] = q[2][k] / 8.0;
    }
    const Vec3 aw{a[0] + w[0], a[1] + w[1], a[2] + w[2]};
    const int turn = orient_along(a, b, c, w);
    EXPECT_EQ(turn, cgal_orientation(a, b, c, aw)) << i;
    if (turn == 0) ++zeros;
    // ahead_along: |w|^2 (c - b).(b - a) - ((c - b).w)((b - a).w), exactly in integers.
    long long ww = 0, dot = 0, uw = 0, vw = 0;
    for (int k = 0; k < 3; ++k) {
      const long long wk = static_cast<long long>(w[k]), uk = q[1][k] - q[0][k], vk = q[2][k] - q[1][k];
      ww += wk * wk;
      dot += uk * vk;
      uw += uk * wk;
      vw += vk * wk;
    }
    const long long ahead = ww * dot - uw * vw;
    EXPECT_EQ(ahead_along(a, b, c, w), ahead > 0 ? 1 : ahead < 0 ? -1 : 0) << i;
  }
  EXPECT_GT(zeros, 1000);  // the degenerate half is decided exactly, not by the filter
  // Random doubles (no grid): orient_along agrees with CGAL wherever a + w is exact.
  for (int i = 0; i < 2000; ++i) {
    const Vec3 w{double(small(rng)), double(small(rng)), 1.0};
    const Vec3 a{std::ldexp(std::round(std::ldexp(u(rng), 20)), -20), std::ldexp(std::round(std::ldexp(u(rng), 20)), -20),
                 std::ldexp(std::round(std::ldexp(u(rng), 20)), -20)};
    const Vec3 b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
    const Vec3 aw{a[0] + w[0], a[1] + w[1], a[2] + w[2]};
    EXPECT_EQ(orient_along(a, b, c, w), cgal_orientation(a, b, c, aw)) << i;
  }
}

}  // namespace
}  // namespace untangle
