// Median-split BVH over triangle boxes.
#include "detect/triangle_bvh.h"

#include <algorithm>

namespace untangle {

Box3 triangle_box(const SceneTopology& topo, std::uint32_t t) {
  Box3 b;
  const Vec3& p = topo.points[topo.tris[t][0]];
  b.lo = p;
  b.hi = p;
  for (int k = 1; k < 3; ++k) {
    const Vec3& q = topo.points[topo.tris[t][k]];
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = std::min(b.lo[a], q[a]);
      b.hi[a] = std::max(b.hi[a], q[a]);
    }
  }
  return b;
}

namespace {

// Spreads the lower 21 bits of x to every third bit (for 63-bit Morton codes).
std::uint64_t spread(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffull;
  x = (x | x << 16) & 0x1f0000ff0000ffull;
  x = (x | x << 8) & 0x100f00f00f00f00full;
  x = (x | x << 4) & 0x10c30c30c30c30c3ull;
  x = (x | x << 2) & 0x1249249249249249ull;
  return x;
}

}  // namespace

TriangleBvh::TriangleBvh(const SceneTopology& topo, const std::vector<bool>& include) {
  std::vector<std::uint32_t> tris;
  std::vector<Box3> boxes;
  Box3 all;
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
    if (!include[topo.tri_mesh[t]]) continue;
    const Box3 box = triangle_box(topo, t);
    if (tris.empty()) all = box;
    for (int a = 0; a < 3; ++a) {
      all.lo[a] = std::min(all.lo[a], box.lo[a]);
      all.hi[a] = std::max(all.hi[a], box.hi[a]);
    }
    tris.push_back(t);
    boxes.push_back(box);
  }
  if (tris.empty()) return;
  // Order the triangles along a Morton curve of their box centres (ties by id): neighbours in the
  // order are neighbours in space, so halving ranges builds a sound hierarchy with a single sort.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    std::uint64_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double extent = all.hi[a] - all.lo[a];
      const double centre = 0.5 * (boxes[i].lo[a] + boxes[i].hi[a]);
      const double unit = extent > 0.0 ? (centre - all.lo[a]) / extent : 0.0;
      const auto cell = static_cast<std::uint64_t>(std::min(std::max(unit, 0.0), 1.0) * 2097151.0);
      code |= spread(cell) << a;
    }
    keys[i] = {code, static_cast<std::uint32_t>(i)};  // i follows the triangle id order
  }
  std::sort(keys.begin(), keys.end());
  triangles_.resize(tris.size());
  leaf_boxes_.resize(tris.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    triangles_[i] = tris[keys[i].second];
    leaf_boxes_[i] = boxes[keys[i].second];
  }
  nodes_.reserve(tris.size() / 2 + 1);
  build(0, static_cast<std::uint32_t>(tris.size()));
}

std::uint32_t TriangleBvh::build(std::uint32_t first, std::uint32_t count) {
  const std::uint32_t index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  if (count <= 4) {
    Box3 box = leaf_boxes_[first];
    for (std::uint32_t i = first + 1; i < first + count; ++i)
      for (int a = 0; a < 3; ++a) {
        box.lo[a] = std::min(box.lo[a], leaf_boxes_[i].lo[a]);
        box.hi[a] = std::max(box.hi[a], leaf_boxes_[i].hi[a]);
      }
    nodes_[index].box = box;
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  const std::uint32_t half = count / 2;
  const std::uint32_t left = build(first, half);
  const std::uint32_t right = build(first + half, count - half);
  Box3 box = nodes_[left].box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = std::min(box.lo[a], nodes_[right].box.lo[a]);
    box.hi[a] = std::max(box.hi[a], nodes_[right].box.hi[a]);
  }
  nodes_[index].box = box;
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

void TriangleBvh::query(const Box3& box, std::vector<std::uint32_t>& out) const {
  if (nodes_.empty()) return;
  std::uint32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!node.box.overlaps(box)) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
        if (leaf_boxes_[i].overlaps(box)) out.push_back(triangles_[i]);
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
}

}  // namespace untangle
