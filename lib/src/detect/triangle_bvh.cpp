// Median-split BVH over triangle boxes.
#include "detect/triangle_bvh.h"

#include <algorithm>
#include <cmath>

#include "detect/orientation.h"
#include "geometry/vec3.h"

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

// Whether the closed segments ab and cd, projected along `drop`, have a point in common (exact;
// collinear segments count as meeting: the caller has found their boxes overlapping).
bool segments_meet(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int drop) {
  const int o1 = orient_2d(a, b, c, drop), o2 = orient_2d(a, b, d, drop);
  if (o1 * o2 > 0) return false;
  const int o3 = orient_2d(c, d, a, drop), o4 = orient_2d(c, d, b, drop);
  return o3 * o4 <= 0;
}

// Whether the projected polyline a -> b -> c goes on beyond b without doubling back on ab: a
// strict turn, or straight on (a and c strictly on either side of b along a coordinate).
bool goes_on(const Vec3& a, const Vec3& b, const Vec3& c, int drop) {
  if (orient_2d(a, b, c, drop) != 0) return true;
  const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
  for (const int k : {i, j})
    if (a[k] != b[k]) return (a[k] < b[k] && c[k] > b[k]) || (a[k] > b[k] && c[k] < b[k]);
  return false;  // a == b in projection
}

// Scratch of the flat-patch test, indexed by global ids, zero/kNone between calls.
struct PatchScratch {
  std::vector<std::int8_t> net;        // per edge: forward minus backward uses in the patch
  std::vector<std::uint8_t> seen;      // per edge: listed in `edges`
  std::vector<std::uint32_t> next;     // per vertex: the loop's next vertex, or kNone
  std::vector<std::uint32_t> edges;    // the patch's edges
  std::vector<std::uint32_t> loop;     // the boundary loop's vertices in order
  std::vector<std::uint32_t> order;    // loop edges by their lowest projected coordinate
};

// Whether the projection along `drop` of the closed loop s.loop is a simple polygon: consecutive
// edges go on beyond their common corner, and no two others meet (a sweep along the first
// projected axis over the edges' coordinate ranges).
bool simple_polygon(const std::vector<Vec3>& P, PatchScratch& s, int drop) {
  const std::size_t n = s.loop.size();
  auto at = [&](std::size_t m) -> const Vec3& { return P[s.loop[m % n]]; };
  for (std::size_t m = 0; m < n; ++m)
    if (!goes_on(at(m), at(m + 1), at(m + 2), drop)) return false;
  const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
  auto lo = [&](std::size_t m, int k) { return std::min(at(m)[k], at(m + 1)[k]); };
  auto hi = [&](std::size_t m, int k) { return std::max(at(m)[k], at(m + 1)[k]); };
  s.order.resize(n);
  for (std::size_t m = 0; m < n; ++m) s.order[m] = static_cast<std::uint32_t>(m);
  std::sort(s.order.begin(), s.order.end(), [&](std::uint32_t a, std::uint32_t b) {
    const double la = lo(a, i), lb = lo(b, i);
    return la != lb ? la < lb : a < b;
  });
  for (std::size_t x = 0; x < n; ++x) {
    const std::size_t a = s.order[x];
    const double end = hi(a, i);
    for (std::size_t y = x + 1; y < n && lo(s.order[y], i) <= end; ++y) {
      const std::size_t b = s.order[y];
      if ((a + 1) % n == b || (b + 1) % n == a) continue;  // consecutive: checked above
      if (hi(a, j) < lo(b, j) || hi(b, j) < lo(a, j)) continue;
      if (segments_meet(at(a), at(a + 1), at(b), at(b + 1), drop)) return false;
    }
  }
  return true;
}

// The flat-patch test of mark_flat_patches for the triangles `tris`, all of them turning one
// strict way along each axis flagged in `axes` (bit k: axis k): their edges' signed sum is one
// loop, and that loop projected along one of those axes is a simple polygon.
bool flat_patch(const SceneTopology& topo, const std::uint32_t* tris, std::size_t count, unsigned axes,
                PatchScratch& s) {
  s.edges.clear();
  for (std::size_t x = 0; x < count; ++x) {
    const std::uint32_t t = tris[x];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t e = topo.tri_edges[t][k];
      const bool forward = topo.edges[e][0] == topo.tris[t][k];
      s.net[e] = static_cast<std::int8_t>(s.net[e] + (forward ? 1 : -1));
      if (!s.seen[e]) {
        s.seen[e] = 1;
        s.edges.push_back(e);
      }
    }
  }
  bool ok = true;
  std::size_t boundary = 0;
  std::uint32_t start = kNone;
  for (const std::uint32_t e : s.edges) {
    const int n = s.net[e];
    if (n == 0 || !ok) continue;
    if (n > 1 || n < -1) {
      ok = false;
      continue;
    }
    const std::uint32_t from = topo.edges[e][n > 0 ? 0 : 1], to = topo.edges[e][n > 0 ? 1 : 0];
    if (s.next[from] != kNone) ok = false;  // two loop edges leave it
    s.next[from] = to;
    if (start == kNone) start = from;
    ++boundary;
  }
  // One loop through every boundary edge: from `start`, back there after exactly `boundary` steps.
  s.loop.clear();
  if (ok && boundary >= 3) {
    std::uint32_t v = start;
    do {
      s.loop.push_back(v);
      v = s.next[v];
    } while (v != kNone && v != start && s.loop.size() < boundary);
    ok = v == start && s.loop.size() == boundary;
  } else {
    ok = false;
  }
  for (const std::uint32_t e : s.edges) {
    s.next[topo.edges[e][0]] = s.next[topo.edges[e][1]] = kNone;
    s.net[e] = 0;
    s.seen[e] = 0;
  }
  if (!ok) return false;
  for (int drop = 0; drop < 3; ++drop)
    if ((axes >> drop & 1u) && simple_polygon(topo.points, s, drop)) return true;
  return false;
}

}  // namespace

void TriangleBvh::mark_flat_patches(const SceneTopology& topo) {
  const std::size_t nodes = nodes_.size();
  flat_.assign(nodes, kNone);
  if (nodes == 0) return;
  // Per node: its range of triangles_ and the directions along which all of its triangles turn
  // one strict way (bit 2 * axis for counter-clockwise, 2 * axis + 1 for clockwise). Children
  // come after their parent: one backward pass.
  std::vector<std::uint8_t> turns(nodes);
  std::vector<std::uint32_t> begin(nodes), end(nodes);
  for (std::size_t n = nodes; n-- > 0;) {
    const Node& node = nodes_[n];
    if (node.count > 0) {
      std::uint8_t mask = 0x3f;
      for (std::uint32_t x = node.first; x < node.first + node.count; ++x) {
        const auto& tri = topo.tris[triangles_[x]];
        const Vec3 &a = topo.points[tri[0]], &b = topo.points[tri[1]], &c = topo.points[tri[2]];
        // Along an axis nearly in the triangle's plane (rounded normal component under 1/1000 of
        // the largest) the turn is not asked: the exact predicate would be slow there, and an axis
        // left out only makes the test stricter.
        const Vec3 n = cross(sub(b, a), sub(c, a));
        const double largest = std::max({std::abs(n[0]), std::abs(n[1]), std::abs(n[2])});
        std::uint8_t own = 0;
        for (int axis = 0; axis < 3; ++axis) {
          if (!(std::abs(n[axis]) >= 1e-3 * largest) || (mask >> (2 * axis) & 3u) == 0) continue;
          const int turn = orient_2d(a, b, c, axis);
          if (turn != 0) own |= static_cast<std::uint8_t>(1u << (2 * axis + (turn > 0 ? 0 : 1)));
        }
        mask &= own;
      }
      turns[n] = mask;
      begin[n] = node.first;
      end[n] = node.first + node.count;
    } else {
      turns[n] = turns[node.left] & turns[node.right];
      begin[n] = begin[node.left];
      end[n] = end[node.right];
    }
  }
  PatchScratch scratch;
  scratch.net.assign(topo.edges.size(), 0);
  scratch.seen.assign(topo.edges.size(), 0);
  scratch.next.assign(topo.points.size(), kNone);
  // From the root down: a node that passes marks its subtree; one that fails passes the question
  // to its children.
  std::vector<std::uint32_t> stack{0u}, below;
  while (!stack.empty()) {
    const std::uint32_t n = stack.back();
    stack.pop_back();
    unsigned axes = 0;
    for (int axis = 0; axis < 3; ++axis)
      if (turns[n] >> (2 * axis) & 3u) axes |= 1u << axis;
    const bool flat = axes != 0 && end[n] - begin[n] >= 2 &&
                      flat_patch(topo, triangles_.data() + begin[n], end[n] - begin[n], axes, scratch);
    if (flat) {
      below.assign(1, n);
      while (!below.empty()) {
        const std::uint32_t m = below.back();
        below.pop_back();
        flat_[m] = n;
        if (nodes_[m].count == 0) below.insert(below.end(), {nodes_[m].left, nodes_[m].right});
      }
    } else if (nodes_[n].count == 0) {
      stack.push_back(nodes_[n].right);
      stack.push_back(nodes_[n].left);
    }
  }
}

std::size_t TriangleBvh::flat_patch_triangles() const {
  std::size_t count = 0;
  for (std::size_t n = 0; n < flat_.size(); ++n)
    if (flat_[n] != kNone && nodes_[n].count > 0) count += nodes_[n].count;
  return count;
}

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
  flat_.clear();  // marked for the positions it was built at
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
