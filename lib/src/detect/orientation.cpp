// Exact orientation with Simulation of Simplicity for the zero cases.
#include "detect/orientation.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace untangle {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Exact = CGAL::Mpzf;  // exact sums and products of doubles
using Interval = CGAL::Interval_nt_advanced;  // rounding mode set once per call

// One term of the perturbed 4x4 determinant |x y z 1| (rows = points sorted by id): the set S of
// perturbed entries (row, column) it multiplies, and the permutations consistent with S with their
// signs. Its coefficient is sum over those permutations of sign * product of unperturbed entries
// on the rows outside S.
struct Term {
  std::uint32_t exponent = 0;  // sum of 2^(3r + 2 - c) over S (r, c from 0): smaller dominates
  std::array<int, 4> fixed_row_col{-1, -1, -1, -1};  // column taken by S in each row, or -1
  std::vector<std::pair<std::array<int, 4>, int>> permutations;
};

int permutation_sign(const std::array<int, 4>& p) {
  int inversions = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      if (p[i] > p[j]) ++inversions;
  return inversions % 2 == 0 ? 1 : -1;
}

std::vector<Term> make_terms() {
  std::vector<std::array<int, 4>> perms;
  std::array<int, 4> p{0, 1, 2, 3};
  do perms.push_back(p);
  while (std::next_permutation(p.begin(), p.end()));

  std::vector<Term> terms;
  // Each row takes no perturbed entry (-1) or one of the three coordinate columns; columns distinct.
  for (int code = 0; code < 256; ++code) {
    std::array<int, 4> take{};
    int c = code;
    bool ok = true;
    int used = 0;
    for (int r = 0; r < 4; ++r) {
      take[r] = (c & 3) - 1;  // -1, 0, 1, 2
      c >>= 2;
      if (take[r] >= 0) {
        if (used & (1 << take[r])) ok = false;
        used |= 1 << take[r];
      }
    }
    if (!ok) continue;
    Term term;
    term.fixed_row_col = take;
    for (int r = 0; r < 4; ++r)
      if (take[r] >= 0) term.exponent += 1u << (3 * r + 2 - take[r]);
    for (const auto& perm : perms) {
      bool consistent = true;
      for (int r = 0; r < 4; ++r)
        if (take[r] >= 0 && perm[r] != take[r]) consistent = false;
      if (consistent) term.permutations.push_back({perm, permutation_sign(perm)});
    }
    terms.push_back(std::move(term));
  }
  std::sort(terms.begin(), terms.end(),
            [](const Term& a, const Term& b) { return a.exponent < b.exponent; });
  return terms;
}

const std::vector<Term>& terms() {
  static const std::vector<Term> kTerms = make_terms();
  return kTerms;
}

// The coefficient of one term, evaluated in number type NT.
template <class NT>
NT coefficient(const Term& term, const std::array<const Vec3*, 4>& rows) {
  NT sum(0);
  for (const auto& [perm, sign] : term.permutations) {
    NT product(sign);
    for (int r = 0; r < 4; ++r)
      if (term.fixed_row_col[r] < 0 && perm[r] != 3) product *= NT((*rows[r])[perm[r]]);
    sum += product;
  }
  return sum;
}

// Sign of the perturbed determinant of rows (x, y, z, 1) in the given (sorted-by-id) order. Each
// coefficient is first bounded with interval arithmetic (exact on small integers, where most
// degenerate input lives); only an interval straddling zero is recomputed exactly.
int perturbed_det4_sign(const std::array<const Vec3*, 4>& rows, bool skip_unperturbed) {
  const std::vector<Term>& all = terms();
  const CGAL::Protect_FPU_rounding<true> rounding;  // upward rounding for Interval_nt_advanced
  for (std::size_t k = skip_unperturbed ? 1 : 0; k < all.size(); ++k) {
    const Term& term = all[k];
    const Interval bound = coefficient<Interval>(term, rows);
    if (bound.inf() > 0) return 1;
    if (bound.sup() < 0) return -1;
    if (bound.inf() == 0 && bound.sup() == 0) continue;
    const Exact exact = [&] {
      const CGAL::Protect_FPU_rounding<true> nearest(CGAL_FE_TONEAREST);  // Mpzf needs it
      return coefficient<Exact>(term, rows);
    }();
    const CGAL::Sign sign = CGAL::sign(exact);
    if (sign != CGAL::ZERO) return sign == CGAL::POSITIVE ? 1 : -1;
  }
  return 1;  // unreachable: the last terms leave the column of ones, a nonzero minor
}

// Sorts the four points by id and evaluates the perturbed determinant; `known_zero` skips the
// unperturbed term when the caller has already found it to be zero.
int orient_perturbed(const Vec3& pa, const Vec3& pb, const Vec3& pc, const Vec3& pd,
                     std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d,
                     bool known_zero) {
  std::array<std::pair<std::uint32_t, const Vec3*>, 4> items{
      {{a, &pa}, {b, &pb}, {c, &pc}, {d, &pd}}};
  // Sort by id, counting transpositions (insertion sort on four items).
  int parity = 1;
  for (int i = 1; i < 4; ++i)
    for (int j = i; j > 0 && items[j].first < items[j - 1].first; --j) {
      std::swap(items[j], items[j - 1]);
      parity = -parity;
    }
  const std::array<const Vec3*, 4> rows{items[0].second, items[1].second, items[2].second,
                                        items[3].second};
  // CGAL's orientation(a, b, c, d) is the sign of det[b-a, c-a, d-a] = -det4(a, b, c, d).
  return -parity * perturbed_det4_sign(rows, known_zero);
}

}  // namespace

int orient_symbolic(const Vec3& pa, const Vec3& pb, const Vec3& pc, const Vec3& pd,
                    std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  return orient_perturbed(pa, pb, pc, pd, a, b, c, d, false);
}

namespace {

// Shewchuk's error-free transformations ("Adaptive precision floating-point arithmetic", 1997):
// x + y == a + b and x * y's error exactly, in round-to-nearest, barring overflow (and, for the
// product, underflow of its error term).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// Magnitudes for which orient2d_expansion is exact: every product of two components lies between
// 1e-280 and 1e280, so its error term is a double (no underflow) and no sum overflows.
bool in_expansion_range(double x) {
  const double m = std::abs(x);
  return m == 0.0 || (m >= 1e-140 && m <= 1e140);
}

}  // namespace

int orient_2d_expansion(double ax, double ay, double bx, double by, double cx, double cy) {
  // det = (ax - cx)(by - cy) - (ay - cy)(bx - cx), each difference a two-component expansion.
  std::array<double, 8> d{};
  two_sum(ax, -cx, d[0], d[1]);
  two_sum(by, -cy, d[2], d[3]);
  two_sum(ay, -cy, d[4], d[5]);
  two_sum(bx, -cx, d[6], d[7]);
  for (double x : {ax, ay, bx, by, cx, cy})
    if (!in_expansion_range(x)) return 2;
  for (double x : d)
    if (!in_expansion_range(x)) return 2;
  if (d[1] == 0.0 && d[3] == 0.0 && d[5] == 0.0 && d[7] == 0.0) {
    // Exact differences (grid points, Sterbenz): compare the two products. Rounding is monotone,
    // so rounded products that differ order the exact ones; equal ones leave their errors.
    double p, pe, q, qe;
    two_product(d[0], d[2], p, pe);
    two_product(d[4], d[6], q, qe);
    if (p != q) return p > q ? 1 : -1;
    return pe > qe ? 1 : pe < qe ? -1 : 0;
  }
  // The sixteen exact partial products, summed into a nonoverlapping expansion (grow-expansion
  // with zero elimination; components in increasing magnitude): its sign is its largest
  // component's.
  std::array<double, 17> h{};
  int size = 0;
  auto add = [&](double term) {
    double q = term;
    int kept = 0;
    for (int k = 0; k < size; ++k) {
      double sum, error;
      two_sum(q, h[k], sum, error);
      q = sum;
      if (error != 0.0) h[kept++] = error;
    }
    if (q != 0.0) h[kept++] = q;
    size = kept;
  };
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 2; ++y) {
      double p, pe, q, qe;
      two_product(d[x], d[2 + y], p, pe);
      two_product(d[4 + x], d[6 + y], q, qe);
      add(p);
      add(pe);
      add(-q);
      add(-qe);
    }
  if (size == 0) return 0;
  return h[size - 1] > 0.0 ? 1 : -1;
}

int orient_2d_exact(const Vec3& a, const Vec3& b, const Vec3& c, int drop) {
  const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
  const int sign = orient_2d_expansion(a[i], a[j], b[i], b[j], c[i], c[j]);
  if (sign != 2) return sign;
  return static_cast<int>(CGAL::orientation(Kernel::Point_2(a[i], a[j]), Kernel::Point_2(b[i], b[j]),
                                            Kernel::Point_2(c[i], c[j])));
}

int orient_along(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& w) {
  if (const int sure = PlaneFilter(a, b, c).along(w)) return sure;
  const CGAL::Protect_FPU_rounding<true> nearest(CGAL_FE_TONEAREST);  // Mpzf needs it
  Exact u[3], v[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = Exact(b[k]) - Exact(a[k]);
    v[k] = Exact(c[k]) - Exact(a[k]);
  }
  Exact det(0);
  for (int k = 0; k < 3; ++k) {
    const int i = (k + 1) % 3, j = (k + 2) % 3;
    if (w[k] != 0.0) det = det + Exact(w[k]) * (u[i] * v[j] - u[j] * v[i]);
  }
  const CGAL::Sign sign = CGAL::sign(det);
  return sign == CGAL::ZERO ? 0 : sign == CGAL::POSITIVE ? 1 : -1;
}

int ahead_along(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& w) {
  const CGAL::Protect_FPU_rounding<true> nearest(CGAL_FE_TONEAREST);  // Mpzf needs it
  Exact uw(0), vw(0), ww(0);
  Exact dot(0);
  for (int k = 0; k < 3; ++k) {
    const Exact u = Exact(b[k]) - Exact(a[k]), v = Exact(c[k]) - Exact(b[k]), wk(w[k]);
    dot = dot + u * v;
    uw = uw + u * wk;
    vw = vw + v * wk;
    ww = ww + wk * wk;
  }
  const CGAL::Sign sign = CGAL::sign(ww * dot - uw * vw);
  return sign == CGAL::ZERO ? 0 : sign == CGAL::POSITIVE ? 1 : -1;
}

int orient_sos(const std::vector<Vec3>& points, std::uint32_t a, std::uint32_t b,
               std::uint32_t c, std::uint32_t d) {
  const Vec3& pa = points[a];
  const Vec3& pb = points[b];
  const Vec3& pc = points[c];
  const Vec3& pd = points[d];
  if (const int sure = orient_filtered(pa, pb, pc, pd)) return sure;
  const CGAL::Orientation o =
      CGAL::orientation(Kernel::Point_3(pa[0], pa[1], pa[2]), Kernel::Point_3(pb[0], pb[1], pb[2]),
                        Kernel::Point_3(pc[0], pc[1], pc[2]), Kernel::Point_3(pd[0], pd[1], pd[2]));
  if (o == CGAL::POSITIVE) return 1;
  if (o == CGAL::NEGATIVE) return -1;
  return orient_perturbed(pa, pb, pc, pd, a, b, c, d, true);
}

}  // namespace untangle
