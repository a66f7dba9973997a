// A bounding-volume hierarchy over the triangles of some meshes, the broad phase of detection.
// Leaves of 2 to 4 triangles in Morton order of their box centres, ranges halved. Built once per
// mesh (obstacles never move; movable meshes are refitted between iterations of fix).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "geometry/box3.h"
#include "topology/scene_topology.h"

namespace untangle {

// The box of triangle t at the topology's current positions.
inline Box3 triangle_box(const SceneTopology& topology, std::uint32_t t) {
  return triangle_box(topology.points, topology.tris[t]);
}

class TriangleBvh {
 public:
  TriangleBvh() = default;  // empty
  // Over the triangles whose mesh is flagged in `include`.
  TriangleBvh(const SceneTopology& topology, const std::vector<bool>& include);
  // Over the listed triangles (ascending ids).
  TriangleBvh(const SceneTopology& topology, const std::vector<std::uint32_t>& triangles);
  // Over triangles that are not a topology's, given by their boxes: entry i is boxes[i], and the
  // queries report i (a closest-point tree over copies of some triangles).
  explicit TriangleBvh(std::vector<Box3> boxes);

  // Recomputes every box from the current positions, keeping the tree (vertices moved a little:
  // iterations of fix). Queries stay exact; only their speed depends on how far things moved.
  void refit(const SceneTopology& topology);

  // Groups the triangles into flat patches that provably meet one another only in the vertices
  // and edges they share, so that each_pair_self and the self parts of each_pair_in skip the pairs
  // inside one patch. A patch grows over shared edges from a seed, taking triangles that turn the
  // same strict way projected along one of 13 small-integer directions (exact: a normal cone
  // inside that direction's half-space), and is kept when its boundary (the signed sum of its
  // triangles' edges: one or several loops, pinched or nested) projects without two segments
  // meeting except at shared corners, and the covering number it implies is 1 on the patch's side
  // of every boundary segment (exact winding counts, touching counts as meeting). Then every point
  // of the plane is covered at most once, the patch projects one to one, and two of its triangles
  // meet in space only in a shared vertex or edge: no edge can pass through a face under any
  // perturbation (DESIGN.md, "Flat patches"). Only the speed of the self pairs depends on it,
  // never which crossings are found.
  void mark_flat_patches(const SceneTopology& topology);
  // Triangles in some patch, and the number of patches.
  std::size_t flat_patch_triangles() const;
  std::size_t flat_patch_count() const { return patches_; }

  // Appends every indexed triangle whose box overlaps `box` (in no particular order).
  void query(const Box3& box, std::vector<std::uint32_t>& out) const;
  // A nearest-triangle search: calls f(t) for the indexed triangles whose boxes may lie within the
  // bound f returns (the squared distance of the nearest found so far; +infinity before the first
  // call), the nearer child first, skipping what lies beyond the bound. The bound is widened by a
  // relative 1e-12 so that rounding of the box distances never skips a triangle that could be
  // nearer: f decides which is nearest, exactly if it likes.
  template <class F>
  void nearest(const Vec3& p, const F& f) const {
    if (nodes_.empty()) return;
    double bound = std::numeric_limits<double>::infinity();
    auto beyond = [&bound](double d2) { return d2 > bound + bound * 1e-12; };
    struct Entry {
      std::uint32_t node;
      double d2;
    };
    // Each level pops one entry and pushes two: the stack holds at most the depth plus one (under
    // 64: 30 levels of Morton bits, then halving among equal codes).
    Entry stack[96];
    int top = 0;
    stack[top++] = {0u, squared_distance_to(nodes_[0].box, p)};
    while (top > 0) {
      const Entry e = stack[--top];
      if (beyond(e.d2)) continue;
      const Node& n = nodes_[e.node];
      if (n.count > 0) {
        for (std::uint32_t x = n.first; x < n.first + n.count; ++x)
          if (!beyond(squared_distance_to(leaf_boxes_[x], p))) bound = f(triangles_[x]);
        continue;
      }
      const double dl = squared_distance_to(nodes_[n.left].box, p);
      const double dr = squared_distance_to(nodes_[n.right].box, p);
      if (dl <= dr) {
        stack[top++] = {n.right, dr};
        stack[top++] = {n.left, dl};
      } else {
        stack[top++] = {n.left, dl};
        stack[top++] = {n.right, dr};
      }
    }
  }

  bool empty() const { return triangles_.empty(); }
  std::size_t size() const { return triangles_.size(); }  // indexed triangles

  // Calls f(t, u) for every triangle t of this hierarchy and u of `other` whose boxes overlap, by
  // a simultaneous descent of both trees (deterministic order).
  template <class F>
  void each_pair_with(const TriangleBvh& other, const F& f) const {
    if (!nodes_.empty() && !other.nodes_.empty()) each_pair_in(other, {0u, 0u}, false, f);
  }

  // Calls f(t, u) once for every unordered pair of distinct triangles whose boxes overlap.
  template <class F>
  void each_pair_self(const F& f) const {
    if (!nodes_.empty()) each_pair_in(*this, {0u, 0u}, true, f);
  }

  // A simultaneous descent split into independent parts, for parallel loops: node pairs (i of
  // this tree, j of `other`) whose descents (each_pair_in) together report every pair of
  // each_pair_with(other), or with `self` (other is this tree) of each_pair_self, exactly once;
  // (i, i) stands for the pairs inside node i. At least `want` parts where the trees allow it, in
  // an order that depends only on the trees.
  struct Part {
    std::uint32_t i = 0, j = 0;
  };
  std::vector<Part> split(const TriangleBvh& other, bool self, std::size_t want) const;

  // The pairs of one part of split(other, self, ...), as each_pair_with or each_pair_self would
  // report them.
  template <class F>
  void each_pair_in(const TriangleBvh& other, Part part, bool self, const F& f) const {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> stack;
    stack.reserve(128);  // about the sum of the two depths
    const bool flat = self && !flat_.empty();
    // Two triangles of one flat patch: no crossing between them, nothing to report.
    auto apart = [&](std::uint32_t x, std::uint32_t y) {
      return flat && entry_patch_[x] != kNone && entry_patch_[x] == entry_patch_[y];
    };
    // Both halves inside one flat patch: nothing to report.
    if (flat && flat_[part.i] != kNone && flat_[part.i] == flat_[part.j]) return;
    stack.push_back({part.i, part.j});
    while (!stack.empty()) {
      const auto [i, j] = stack.back();
      stack.pop_back();
      if (self && i == j) {
        if (flat && flat_[i] != kNone) continue;
        const Node& a = nodes_[i];
        if (a.count > 0) {
          for (std::uint32_t x = a.first; x < a.first + a.count; ++x)
            for (std::uint32_t y = x + 1; y < a.first + a.count; ++y)
              if (!apart(x, y) && leaf_boxes_[x].overlaps(leaf_boxes_[y])) f(triangles_[x], triangles_[y]);
        } else {
          stack.push_back({a.left, a.right});
          stack.push_back({a.right, a.right});
          stack.push_back({a.left, a.left});
        }
        continue;
      }
      if (flat) {
        if (flat_[i] != kNone && flat_[i] == flat_[j]) continue;
        const Node& a = nodes_[i];
        const Node& b = nodes_[j];
        if (a.count > 0 && b.count > 0) {
          if (!a.box.overlaps(b.box)) continue;
          for (std::uint32_t x = a.first; x < a.first + a.count; ++x)
            for (std::uint32_t y = b.first; y < b.first + b.count; ++y)
              if (!apart(x, y) && leaf_boxes_[x].overlaps(leaf_boxes_[y])) f(triangles_[x], triangles_[y]);
          continue;
        }
      }
      descend(other, i, j, stack, f);
    }
  }

 private:
  struct Node {
    Box3 box;
    std::uint32_t first = 0, count = 0;  // leaf: range in triangles_
    std::uint32_t left = 0, right = 0;   // inner: children
  };
  // One step of a simultaneous descent of node i (this tree) and node j (other): report the
  // overlapping leaf pairs, or push the children of the larger node.
  template <class F>
  void descend(const TriangleBvh& other, std::uint32_t i, std::uint32_t j,
               std::vector<std::pair<std::uint32_t, std::uint32_t>>& stack, const F& f) const {
    const Node& a = nodes_[i];
    const Node& b = other.nodes_[j];
    if (!a.box.overlaps(b.box)) return;
    if (a.count > 0 && b.count > 0) {
      for (std::uint32_t x = a.first; x < a.first + a.count; ++x)
        for (std::uint32_t y = b.first; y < b.first + b.count; ++y)
          if (leaf_boxes_[x].overlaps(other.leaf_boxes_[y])) f(triangles_[x], other.triangles_[y]);
    } else if (b.count > 0 || (a.count == 0 && volume(a.box) >= volume(b.box))) {
      stack.push_back({a.right, j});
      stack.push_back({a.left, j});
    } else {
      stack.push_back({i, b.right});
      stack.push_back({i, b.left});
    }
  }
  static double volume(const Box3& b) {
    return (b.hi[0] - b.lo[0]) + (b.hi[1] - b.lo[1]) + (b.hi[2] - b.lo[2]);  // half perimeter
  }
  void build_over(const SceneTopology& topology, const std::vector<std::uint32_t>& triangles);
  // The same over the triangles' boxes (boxes[i] that of ids[i]); with `split_by_code`, ranges
  // are split where their Morton codes' highest differing bit turns (tighter boxes for nearest
  // queries; detection keeps its halved ranges and so its order of pairs).
  void build_over_boxes(std::vector<Box3> boxes, const std::vector<std::uint32_t>& ids,
                        bool split_by_code);

  // Nodes over triangles_[first, first + count); ranges are halved, or cut at the entry of `cuts`
  // (ascending) nearest their middle when they hold one, or with `code` (the entries' Morton codes,
  // ascending) where the highest bit of their codes turns.
  std::uint32_t build(std::uint32_t first, std::uint32_t count,
                      const std::vector<std::uint32_t>* cuts,
                      const std::vector<std::uint32_t>* code = nullptr);

  std::vector<Node> nodes_;
  std::vector<std::uint32_t> triangles_;
  std::vector<Box3> leaf_boxes_;  // per entry of triangles_
  // Once mark_flat_patches ran: per node, the patch holding all of its triangles, or kNone; per
  // entry of triangles_, its patch or kNone.
  std::vector<std::uint32_t> flat_;
  std::vector<std::uint32_t> entry_patch_;
  std::size_t patches_ = 0;
};

}  // namespace untangle
