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

TriangleBvh::TriangleBvh(const SceneTopology& topo, const std::vector<bool>& include) {
  std::vector<Item> items;
  for (std::uint32_t t = 0; t < topo.tris.size(); ++t) {
    if (!include[topo.tri_mesh[t]]) continue;
    Item item;
    item.box = triangle_box(topo, t);
    item.tri = t;
    for (int a = 0; a < 3; ++a) item.centre[a] = item.box.lo[a] + item.box.hi[a];
    items.push_back(item);
  }
  if (items.empty()) return;
  nodes_.reserve(items.size() / 2 + 1);
  build(0, static_cast<std::uint32_t>(items.size()), items);
  triangles_.resize(items.size());
  leaf_boxes_.resize(items.size());
  for (std::size_t i = 0; i < items.size(); ++i) {
    triangles_[i] = items[i].tri;
    leaf_boxes_[i] = items[i].box;
  }
}

std::uint32_t TriangleBvh::build(std::uint32_t first, std::uint32_t count, std::vector<Item>& items) {
  const std::uint32_t index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  Box3 box = items[first].box;
  for (std::uint32_t i = first + 1; i < first + count; ++i)
    for (int a = 0; a < 3; ++a) {
      box.lo[a] = std::min(box.lo[a], items[i].box.lo[a]);
      box.hi[a] = std::max(box.hi[a], items[i].box.hi[a]);
    }
  nodes_[index].box = box;
  if (count <= 4) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  int axis = 0;
  for (int a = 1; a < 3; ++a)
    if (box.hi[a] - box.lo[a] > box.hi[axis] - box.lo[axis]) axis = a;
  // Split at the median centre along the longest axis; ties broken by triangle id (deterministic).
  const std::uint32_t half = count / 2;
  std::nth_element(items.begin() + first, items.begin() + first + half, items.begin() + first + count,
                   [axis](const Item& x, const Item& y) {
                     return x.centre[axis] != y.centre[axis] ? x.centre[axis] < y.centre[axis]
                                                             : x.tri < y.tri;
                   });
  const std::uint32_t left = build(first, half, items);
  const std::uint32_t right = build(first + half, count - half, items);
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
