// WindingNumber: a median-split hierarchy over the triangles, exact solid angles near the query
// point and one dipole per far node.
#include "resolve/winding_number.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

#include "detect/run_parallel.h"
#include "geometry/vec3.h"

namespace untangle {
namespace {

constexpr std::uint32_t kLeafSize = 8;

// The signed solid angle of triangle (a, b, c) seen from p (Van Oosterom and Strackee 1983):
// positive when p lies on the side its winding's normal points away from.
// `in_plane` is set when p lies in the triangle's plane up to rounding (|det| at most 1e-10 of the
// product of the lengths): the angle may then be that of either side.
double solid_angle(const std::array<Vec3, 3>& t, const Vec3& p, bool& in_plane) {
  const Vec3 a = sub(t[0], p), b = sub(t[1], p), c = sub(t[2], p);
  const double la = norm(a), lb = norm(b), lc = norm(c);
  const double det = dot(a, cross(b, c));
  if (std::abs(det) <= 1e-10 * la * lb * lc) in_plane = true;
  const double div = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
  return 2.0 * std::atan2(det, div);
}

Vec3 centroid(const std::array<Vec3, 3>& t) {
  return scale(add(add(t[0], t[1]), t[2]), 1.0 / 3.0);
}

// Nodes of the hierarchy over n triangles: ranges halved (the left one the smaller) down to
// kLeafSize. Only two sizes occur at each level, so a short memo keeps it linear.
std::uint32_t node_count(std::uint32_t n) {
  static thread_local std::vector<std::pair<std::uint32_t, std::uint32_t>> memo;
  if (n <= kLeafSize) return 1;
  for (const auto& [size, count] : memo)
    if (size == n) return count;
  const std::uint32_t count = 1 + node_count(n / 2) + node_count(n - n / 2);
  if (memo.size() > 256) memo.clear();
  memo.push_back({n, count});
  return count;
}

}  // namespace

WindingNumber::WindingNumber(const std::vector<Vec3>& points,
                             const std::vector<std::array<std::uint32_t, 3>>& tris, int threads) {
  std::vector<Item> items;
  items.reserve(tris.size());
  for (const auto& t : tris) {
    Item item;
    item.tri = {points[t[0]], points[t[1]], points[t[2]]};
    item.area_vector = scale(cross(sub(item.tri[1], item.tri[0]), sub(item.tri[2], item.tri[0])), 0.5);
    item.area = norm(item.area_vector);
    item.centroid = centroid(item.tri);
    item.weighted = scale(item.centroid, item.area);
    items.push_back(item);
    volume_ += volume6(points[tris[0][0]], points[t[0]], points[t[1]], points[t[2]]) / 6.0;
  }
  if (items.empty()) return;
  const auto n = static_cast<std::uint32_t>(items.size());
  nodes_.resize(node_count(n));
  // The splits first, top down (the top levels on this thread, the subtrees below them in
  // parallel, each into node slots of its own), then what each node sums, bottom up.
  // The split keys beside their indices, moved together: the selections and the boxes of the
  // splits read them in order, where through the index they missed the cache (the splits went
  // from 5.2% to 4.2% of `fix` on the shipped MakeHuman pair, which builds this hierarchy of the
  // body three times; issue 24).
  std::vector<Keyed> keyed(n);
  for (std::uint32_t i = 0; i < n; ++i) keyed[i] = {items[i].centroid, i};
  std::vector<Pending> pending;
  const int depth = threads == 1 || n < 4096 ? -1 : 2;
  split(items, keyed, 0, n, 0, depth, pending);
  run_parallel(threads, pending.size(), 1, [&](std::size_t begin, std::size_t end) {
    std::vector<Pending> none;
    for (std::size_t k = begin; k < end; ++k)
      split(items, keyed, pending[k].begin, pending[k].end, pending[k].id, -1, none);
  });
  std::vector<std::uint32_t> order(n);
  for (std::uint32_t i = 0; i < n; ++i) order[i] = keyed[i].item;
  // Pre-order ids: children after their parent, so one pass from the last id up sums them.
  std::vector<Vec3> weighted(nodes_.size());
  std::vector<double> area(nodes_.size(), 0.0);
  for (std::size_t id = nodes_.size(); id-- > 0;) {
    Node& node = nodes_[id];
    Vec3 dipole{0, 0, 0}, sum{0, 0, 0};
    double a = 0.0;
    if (node.left == 0) {
      Vec3 lo = items[order[node.begin]].tri[0], hi = lo;
      for (std::uint32_t i = node.begin; i < node.end; ++i) {
        const Item& item = items[order[i]];
        dipole = add(dipole, item.area_vector);
        sum = add(sum, item.weighted);
        a += item.area;
        for (const Vec3& q : item.tri)
          for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], q[k]);
            hi[k] = std::max(hi[k], q[k]);
          }
      }
      node.centre = a > 0.0 ? scale(sum, 1.0 / a) : scale(add(lo, hi), 0.5);
      // The largest squared distance, one root at the end (the root is monotone and correctly
      // rounded: the largest of the corners' distances).
      double farthest = 0.0;
      for (std::uint32_t i = node.begin; i < node.end; ++i)
        for (const Vec3& q : items[order[i]].tri) {
          const Vec3 r = sub(q, node.centre);
          farthest = std::max(farthest, dot(r, r));
        }
      node.radius = std::sqrt(farthest);
    } else {
      const Node& l = nodes_[node.left];
      const Node& r = nodes_[node.right];
      dipole = add(l.dipole, r.dipole);
      sum = add(weighted[node.left], weighted[node.right]);
      a = area[node.left] + area[node.right];
      node.centre = a > 0.0 ? scale(sum, 1.0 / a) : scale(add(l.centre, r.centre), 0.5);
      // A ball around the centre holding both children's balls: at least the farthest corner's
      // distance (a far node is then farther than kFarField times its extent).
      node.radius = std::max(norm(sub(l.centre, node.centre)) + l.radius,
                             norm(sub(r.centre, node.centre)) + r.radius);
    }
    node.dipole = dipole;
    weighted[id] = sum;
    area[id] = a;
  }
  tri_.reserve(items.size());
  for (std::uint32_t i : order) tri_.push_back(items[i].tri);
  input_of_ = std::move(order);
}

bool WindingNumber::built_from(const std::vector<Vec3>& points,
                               const std::vector<std::array<std::uint32_t, 3>>& tris) const {
  if (tris.size() != tri_.size()) return false;
  for (std::size_t i = 0; i < tri_.size(); ++i) {
    const auto& t = tris[input_of_[i]];
    const std::array<Vec3, 3> corners{points[t[0]], points[t[1]], points[t[2]]};
    if (std::memcmp(corners.data(), tri_[i].data(), sizeof corners) != 0) return false;
  }
  return true;
}

void WindingNumber::split(const std::vector<Item>& items, std::vector<Keyed>& order,
                          std::uint32_t begin, std::uint32_t end, std::uint32_t id, int depth,
                          std::vector<Pending>& pending) {
  Node& node = nodes_[id];
  node.begin = begin;
  node.end = end;
  if (end - begin <= kLeafSize) return;
  // Split at the median centroid along the longest axis of the centroids' box; ties by the
  // corners, so the order depends on the geometry alone. The indices move with their keys, not
  // the items.
  Vec3 lo = order[begin].centroid, hi = lo;
  for (std::uint32_t i = begin + 1; i < end; ++i) {
    const Vec3& c = order[i].centroid;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], c[k]);
      hi[k] = std::max(hi[k], c[k]);
    }
  }
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (hi[k] - lo[k] > hi[axis] - lo[axis]) axis = k;
  const std::uint32_t mid = begin + (end - begin) / 2;
  // The same comparisons as over bare indices, so the same selection, moved with its keys.
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [axis, &items](const Keyed& i, const Keyed& j) {
                     const double a = i.centroid[axis], b = j.centroid[axis];
                     if (a != b) return a < b;
                     return items[i.item].tri < items[j.item].tri;
                   });
  node.left = id + 1;
  node.right = id + 1 + node_count(mid - begin);
  if (depth == 0) {
    pending.push_back({begin, mid, node.left});
    pending.push_back({mid, end, node.right});
  } else {
    split(items, order, begin, mid, node.left, depth - 1, pending);
    split(items, order, mid, end, node.right, depth - 1, pending);
  }
}

double WindingNumber::operator()(const Vec3& p) const {
  bool in_plane = false;
  return evaluate(p, in_plane);
}

double WindingNumber::evaluate(const Vec3& p, bool& in_plane) const {
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
      for (std::uint32_t i = node.begin; i < node.end; ++i) sum += solid_angle(tri_[i], p, in_plane);
    } else {
      stack[top++] = node.right;
      stack[top++] = node.left;
    }
  }
  return sum / (4.0 * M_PI);
}

}  // namespace untangle
