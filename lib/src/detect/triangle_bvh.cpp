// Median-split BVH over triangle boxes.
#include "detect/triangle_bvh.h"

#include <algorithm>

namespace untangle {
namespace {

// Spreads the lower 10 bits of x to every third bit (30-bit Morton codes).
std::uint32_t spread(std::uint32_t x) {
  x &= 0x3ff;
  x = (x | x << 16) & 0x030000ff;
  x = (x | x << 8) & 0x0300f00f;
  x = (x | x << 4) & 0x030c30c3;
  x = (x | x << 2) & 0x09249249;
  return x;
}

// Stable LSD radix sort of `order` by `code` (three passes of 10 bits): equal codes keep their
// order, so the result is the order of (code, position) and deterministic.
void sort_by_code(const std::vector<std::uint32_t>& code, std::vector<std::uint32_t>& order) {
  std::vector<std::uint32_t> scratch(order.size());
  for (int shift = 0; shift < 30; shift += 10) {
    std::uint32_t count[1025] = {};
    for (std::uint32_t i : order) ++count[((code[i] >> shift) & 1023u) + 1];
    for (int k = 0; k < 1024; ++k) count[k + 1] += count[k];
    for (std::uint32_t i : order) scratch[count[(code[i] >> shift) & 1023u]++] = i;
    order.swap(scratch);
  }
}

}  // namespace

TriangleBvh::TriangleBvh(const SceneTopology& topo, const std::vector<bool>& include) {
  // Triangles are stored mesh by mesh: only the ranges of included meshes are visited.
  const std::size_t meshes = topo.mesh_tri_begin.size() - 1;
  std::size_t included = 0;
  for (std::size_t m = 0; m < meshes; ++m)
    if (include[m]) included += topo.mesh_tri_begin[m + 1] - topo.mesh_tri_begin[m];
  std::vector<std::uint32_t> tris;
  tris.reserve(included);
  for (std::size_t m = 0; m < meshes; ++m) {
    if (!include[m]) continue;
    for (std::uint32_t t = topo.mesh_tri_begin[m]; t < topo.mesh_tri_begin[m + 1]; ++t) tris.push_back(t);
  }
  build_over(topo, tris);
}

TriangleBvh::TriangleBvh(const SceneTopology& topo, const std::vector<std::uint32_t>& triangles) {
  build_over(topo, triangles);
}

void TriangleBvh::build_over(const SceneTopology& topo, const std::vector<std::uint32_t>& tris) {
  if (tris.empty()) return;
  std::vector<Box3> boxes(tris.size());
  Box3 all = boxes[0] = triangle_box(topo, tris[0]);
  for (std::size_t i = 1; i < tris.size(); ++i) {
    boxes[i] = triangle_box(topo, tris[i]);
    all = merged(all, boxes[i]);
  }
  // Order the triangles along a Morton curve of their box centres (ties by id): neighbours in the
  // order are neighbours in space, so halving ranges builds a sound hierarchy with a single sort.
  std::vector<std::uint32_t> code(tris.size()), order(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    std::uint32_t c = 0;
    for (int a = 0; a < 3; ++a) {
      const double extent = all.hi[a] - all.lo[a];
      const double centre = 0.5 * (boxes[i].lo[a] + boxes[i].hi[a]);
      const double unit = extent > 0.0 ? (centre - all.lo[a]) / extent : 0.0;
      const auto cell = static_cast<std::uint32_t>(std::min(std::max(unit, 0.0), 1.0) * 1023.0);
      c |= spread(cell) << a;
    }
    code[i] = c;
    order[i] = static_cast<std::uint32_t>(i);  // i follows the triangle id order
  }
  sort_by_code(code, order);
  triangles_.resize(tris.size());
  leaf_boxes_.resize(tris.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    triangles_[i] = tris[order[i]];
    leaf_boxes_[i] = boxes[order[i]];
  }
  // A binary tree over leaves of 2 to 4 triangles has fewer than tris.size() nodes.
  nodes_.reserve(tris.size());
  build(0, static_cast<std::uint32_t>(tris.size()));
}

void TriangleBvh::refit(const SceneTopology& topo) {
  for (std::size_t i = 0; i < triangles_.size(); ++i) leaf_boxes_[i] = triangle_box(topo, triangles_[i]);
  // Children come after their parent (pre-order build): one backward pass refits every node.
  for (std::size_t n = nodes_.size(); n-- > 0;) {
    Node& node = nodes_[n];
    Box3 box;
    if (node.count > 0) {
      box = leaf_boxes_[node.first];
      for (std::uint32_t i = node.first + 1; i < node.first + node.count; ++i) box = merged(box, leaf_boxes_[i]);
    } else {
      box = merged(nodes_[node.left].box, nodes_[node.right].box);
    }
    node.box = box;
  }
}

std::uint32_t TriangleBvh::build(std::uint32_t first, std::uint32_t count) {
  const std::uint32_t index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.emplace_back();
  if (count <= 4) {
    Box3 box = leaf_boxes_[first];
    for (std::uint32_t i = first + 1; i < first + count; ++i) box = merged(box, leaf_boxes_[i]);
    nodes_[index].box = box;
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  const std::uint32_t half = count / 2;
  const std::uint32_t left = build(first, half);
  const std::uint32_t right = build(first + half, count - half);
  nodes_[index].box = merged(nodes_[left].box, nodes_[right].box);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

std::vector<TriangleBvh::Part> TriangleBvh::split(const TriangleBvh& other, bool self,
                                                   std::size_t want) const {
  std::vector<Part> parts;
  if (nodes_.empty() || other.nodes_.empty()) return parts;
  parts.push_back({0u, 0u});
  // Level by level, the first steps of the descent of each_pair_in: each part is replaced by the
  // parts it would push (a leaf pair, which pushes none, stays), until there are enough.
  std::vector<Part> next;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pushed;
  while (parts.size() < want) {
    bool grew = false;
    next.clear();
    for (const Part& p : parts) {
      const Node& a = nodes_[p.i];
      const Node& b = other.nodes_[p.j];
      pushed.clear();
      if (self && p.i == p.j) {
        if (a.count == 0) pushed = {{a.left, a.left}, {a.right, a.right}, {a.left, a.right}};
      } else if (!a.box.overlaps(b.box)) {
        grew = true;  // nothing below it
        continue;
      } else if (a.count == 0 || b.count == 0) {
        // The children descend() would push, in the order it would visit them.
        descend(other, p.i, p.j, pushed, [](std::uint32_t, std::uint32_t) {});
        std::reverse(pushed.begin(), pushed.end());
      }
      if (pushed.empty()) {
        next.push_back(p);
        continue;
      }
      grew = true;
      for (const auto& [i, j] : pushed) next.push_back({i, j});
    }
    parts.swap(next);
    if (!grew) break;
  }
  return parts;
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
