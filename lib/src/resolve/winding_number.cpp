// WindingNumber: a median-split hierarchy over the triangles, exact solid angles near the query
// point and one dipole per far node.
#include "resolve/winding_number.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "geometry/vec3.h"

namespace untangle {
namespace {

constexpr std::uint32_t kLeafSize = 8;

// The signed solid angle of triangle (a, b, c) seen from p (Van Oosterom and Strackee 1983):
// positive when p lies on the side its winding's normal points away from.
double solid_angle(const std::array<Vec3, 3>& t, const Vec3& p) {
  const Vec3 a = sub(t[0], p), b = sub(t[1], p), c = sub(t[2], p);
  const double la = norm(a), lb = norm(b), lc = norm(c);
  const double det = dot(a, cross(b, c));
  const double div = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
  return 2.0 * std::atan2(det, div);
}

Vec3 centroid(const std::array<Vec3, 3>& t) {
  return scale(add(add(t[0], t[1]), t[2]), 1.0 / 3.0);
}

}  // namespace

WindingNumber::WindingNumber(const std::vector<Vec3>& points,
                             const std::vector<std::array<std::uint32_t, 3>>& tris) {
  tri_.reserve(tris.size());
  for (const auto& t : tris) {
    tri_.push_back({points[t[0]], points[t[1]], points[t[2]]});
    volume_ += dot(points[t[0]], cross(points[t[1]], points[t[2]])) / 6.0;
  }
  if (tri_.empty()) return;
  nodes_.reserve(2 * tri_.size() / kLeafSize + 2);
  build(0, static_cast<std::uint32_t>(tri_.size()));
}

std::uint32_t WindingNumber::build(std::uint32_t begin, std::uint32_t end) {
  const std::uint32_t id = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back({});
  Node node;
  node.begin = begin;
  node.end = end;
  double area = 0.0;
  Vec3 weighted{0, 0, 0}, lo = tri_[begin][0], hi = lo;
  for (std::uint32_t i = begin; i < end; ++i) {
    const auto& t = tri_[i];
    const Vec3 n = scale(cross(sub(t[1], t[0]), sub(t[2], t[0])), 0.5);
    const double a = norm(n);
    node.dipole = add(node.dipole, n);
    weighted = add(weighted, scale(centroid(t), a));
    area += a;
    for (const Vec3& q : t) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], q[k]);
        hi[k] = std::max(hi[k], q[k]);
      }
    }
  }
  node.centre = area > 0.0 ? scale(weighted, 1.0 / area) : scale(add(lo, hi), 0.5);
  for (std::uint32_t i = begin; i < end; ++i)
    for (const Vec3& q : tri_[i]) node.radius = std::max(node.radius, norm(sub(q, node.centre)));
  if (end - begin > kLeafSize) {
    // Split at the median centroid along the box's longest axis; ties by the other coordinates
    // and the corners, so the order depends on the geometry alone.
    int axis = 0;
    for (int k = 1; k < 3; ++k)
      if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
    const std::uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(tri_.begin() + begin, tri_.begin() + mid, tri_.begin() + end,
                     [axis](const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
                       const Vec3 ca = centroid(a), cb = centroid(b);
                       if (ca[axis] != cb[axis]) return ca[axis] < cb[axis];
                       return a < b;
                     });
    node.left = build(begin, mid);
    node.right = build(mid, end);
  }
  nodes_[id] = node;
  return id;
}

double WindingNumber::operator()(const Vec3& p) const {
  if (nodes_.empty()) return 0.0;
  double sum = 0.0;
  std::uint32_t stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    const Vec3 r = sub(node.centre, p);
    const double d = norm(r);
    if (d > kFarField * node.radius) {
      sum += dot(node.dipole, r) / (d * d * d);
    } else if (node.left == 0) {
      for (std::uint32_t i = node.begin; i < node.end; ++i) sum += solid_angle(tri_[i], p);
    } else {
      stack[top++] = node.right;
      stack[top++] = node.left;
    }
  }
  return sum / (4.0 * M_PI);
}

}  // namespace untangle
