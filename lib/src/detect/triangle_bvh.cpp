// Median-split BVH over triangle boxes.
#include "detect/triangle_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "detect/orientation.h"
#include "geometry/morton.h"
#include "geometry/vec3.h"

namespace untangle {
namespace {

// The directions the flat-patch test projects along: the coordinate axes, then the six face
// diagonals and the four body diagonals. Vectors of small integers, so every predicate along them
// stays exact (orient_along, ahead_along); with both signs of each, every normal lies within 35
// degrees of one of them, where the axes alone leave 55. e1 and e2 span the plane normal to w,
// the frame of the projection: along an axis the other two axes in increasing order (orient_2d's
// frame); oblique ones turn from e1 to e2 counter-clockwise seen from where w points
// (e1 x e2 . w > 0), so orient_along is the frame's turn.
struct Direction {
  int axis;  // 0 to 2: the coordinate axis; -1: oblique
  Vec3 w, e1, e2;
};
constexpr int kDirections = 13;
const Direction kDirection[kDirections] = {
    {0, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}},   {1, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}},
    {2, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}},   {-1, {1, 1, 0}, {-1, 1, 0}, {0, 0, 1}},
    {-1, {1, -1, 0}, {1, 1, 0}, {0, 0, 1}}, {-1, {1, 0, 1}, {1, 0, -1}, {0, 1, 0}},
    {-1, {1, 0, -1}, {-1, 0, -1}, {0, 1, 0}}, {-1, {0, 1, 1}, {0, -1, 1}, {1, 0, 0}},
    {-1, {0, 1, -1}, {0, 1, 1}, {1, 0, 0}}, {-1, {1, 1, 1}, {1, -1, 0}, {1, 1, -2}},
    {-1, {1, 1, -1}, {-1, 1, 0}, {1, 1, 2}}, {-1, {1, -1, 1}, {-1, -1, 0}, {1, -1, -2}},
    {-1, {1, -1, -1}, {1, 1, 0}, {1, -1, 2}}};

// 1 / |w| of direction k.
double inverse_length(int k) { return 1.0 / std::sqrt(dot(kDirection[k].w, kDirection[k].w)); }

// Whether `next` (vertex -> the loop's next vertex, or kNone) leads from `start` back to it after
// exactly `size` steps; the vertices on the way into `loop`.
bool walk_loop(const std::vector<std::uint32_t>& next, std::uint32_t start, std::size_t size,
               std::vector<std::uint32_t>& loop) {
  loop.clear();
  std::uint32_t v = start;
  do {
    loop.push_back(v);
    v = next[v];
  } while (v != kNone && v != start && loop.size() < size);
  return v == start && loop.size() == size;
}

// The exact turn of a, b, c projected along direction k, in its frame (+1 counter-clockwise, 0
// collinear).
int turn(const Vec3& a, const Vec3& b, const Vec3& c, int k) {
  const Direction& d = kDirection[k];
  return d.axis >= 0 ? orient_2d(a, b, c, d.axis) : orient_along(a, b, c, d.w);
}

// Whether the closed segments ab and cd, projected along direction k, have a point in common
// (exact; collinear segments count as meeting: the caller has found their boxes overlapping).
bool segments_meet(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, int k) {
  const int o1 = turn(a, b, c, k), o2 = turn(a, b, d, k);
  if (o1 * o2 > 0) return false;
  const int o3 = turn(c, d, a, k), o4 = turn(c, d, b, k);
  return o3 * o4 <= 0;
}

// Whether the polyline a -> b -> c projected along direction k goes on beyond b without doubling
// back on ab: a strict turn, or straight on (a and c strictly on either side of b).
bool goes_on(const Vec3& a, const Vec3& b, const Vec3& c, int k) {
  if (turn(a, b, c, k) != 0) return true;
  const int drop = kDirection[k].axis;
  if (drop < 0) return ahead_along(a, b, c, kDirection[k].w) > 0;  // 0 too when a == b there
  const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
  for (const int x : {i, j})
    if (a[x] != b[x]) return (a[x] < b[x] && c[x] > b[x]) || (a[x] > b[x] && c[x] < b[x]);
  return false;  // a == b in projection
}

// Scratch of the flat-patch test, indexed by global ids, zero/kNone between calls.
struct PatchScratch {
  std::vector<std::int8_t> net;        // per edge: forward minus backward uses in the patch
  std::vector<std::uint8_t> seen;      // per edge: listed in `edges`
  std::vector<std::uint32_t> next;     // per vertex: the loop's next vertex, or kNone
  std::vector<std::uint32_t> edges;    // the patch's edges
  std::vector<std::uint32_t> loop;     // the boundary loop's vertices in order
  std::vector<std::array<double, 4>> range;  // per loop corner: projected [lo, hi] of e1, then e2
  std::vector<std::array<double, 4>> edge_box;  // per loop edge: the same, over its two corners
  std::vector<std::pair<double, std::uint32_t>> by_lo;  // loop edges by their lowest e1, then index
};

// Whether the projection along direction k of the closed loop s.loop is a simple polygon:
// consecutive edges go on beyond their common corner, and no two others meet (a sweep along the
// frame's first coordinate over the edges' ranges, the second one's ranges compared).
bool simple_polygon(const std::vector<Vec3>& P, PatchScratch& s, int k) {
  const std::size_t n = s.loop.size();
  auto at = [&](std::size_t m) -> const Vec3& { return P[s.loop[m % n]]; };
  for (std::size_t m = 0; m < n; ++m)
    if (!goes_on(at(m), at(m + 1), at(m + 2), k)) return false;
  // Each corner's two projected coordinates as [lo, hi]: exact along an axis; along an oblique
  // direction the rounded dot products with e1 and e2, widened by a bound of their error (the
  // products with the small integers are exact, the two sums add at most 2.3e-16 of the sum of
  // the magnitudes), so that no overlap of the exact ranges is missed.
  const Direction& d = kDirection[k];
  s.range.resize(n);
  for (std::size_t m = 0; m < n; ++m) {
    const Vec3& p = at(m);
    auto& r = s.range[m];
    if (d.axis >= 0) {
      const int i = d.axis == 0 ? 1 : 0, j = d.axis == 2 ? 1 : 2;
      r = {p[i], p[i], p[j], p[j]};
      continue;
    }
    for (int c = 0; c < 2; ++c) {
      const Vec3& e = c == 0 ? d.e1 : d.e2;
      const double x = dot(p, e);
      const double err =
          1e-15 * (std::abs(p[0] * e[0]) + std::abs(p[1] * e[1]) + std::abs(p[2] * e[2])) + 1e-300;
      r[2 * c] = x - err;
      r[2 * c + 1] = x + err;
    }
  }
  // Each edge's ranges, found once: computed in every comparison of the sort and the sweep, with
  // the modulo of the next corner, they cost a one-thread `check` of the shipped MakeHuman pair
  // about 1% (the flat-patch marking with this test and its sort: 15.3% of the samples before,
  // 14.1% after; issue 24). The sort keys are distinct (ties by index): the one order.
  s.edge_box.resize(n);
  s.by_lo.resize(n);
  for (std::size_t m = 0; m < n; ++m) {
    const auto &p = s.range[m], &q = s.range[m + 1 == n ? 0 : m + 1];
    s.edge_box[m] = {std::min(p[0], q[0]), std::max(p[1], q[1]), std::min(p[2], q[2]),
                     std::max(p[3], q[3])};
    s.by_lo[m] = {s.edge_box[m][0], static_cast<std::uint32_t>(m)};
  }
  std::sort(s.by_lo.begin(), s.by_lo.end());
  for (std::size_t x = 0; x < n; ++x) {
    const std::size_t a = s.by_lo[x].second;
    const auto& box_a = s.edge_box[a];
    for (std::size_t y = x + 1; y < n && s.by_lo[y].first <= box_a[1]; ++y) {
      const std::size_t b = s.by_lo[y].second;
      if ((a + 1) % n == b || (b + 1) % n == a) continue;  // consecutive: checked above
      const auto& box_b = s.edge_box[b];
      if (box_a[3] < box_b[2] || box_b[3] < box_a[2]) continue;
      if (segments_meet(at(a), at(a + 1), at(b), at(b + 1), k)) return false;
    }
  }
  return true;
}

// The flat-patch test of mark_flat_patches for the triangles `tris`, all of them turning one
// strict way along direction k: their edges' signed sum is one loop, and that loop projected along
// k is a simple polygon. Then the number of triangles covering a point of the plane is the
// polygon's winding number there times their common turn, which is never negative: 0 or 1.
bool flat_patch(const SceneTopology& topo, const std::uint32_t* tris, std::size_t count, int k,
                PatchScratch& s) {
  s.edges.clear();
  for (std::size_t x = 0; x < count; ++x) {
    const std::uint32_t t = tris[x];
    for (int c = 0; c < 3; ++c) {
      const std::uint32_t e = topo.tri_edges[t][c];
      const bool forward = topo.edges[e][0] == topo.tris[t][c];
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
  ok = ok && boundary >= 3 && walk_loop(s.next, start, boundary, s.loop);
  for (const std::uint32_t e : s.edges) {
    s.next[topo.edges[e][0]] = s.next[topo.edges[e][1]] = kNone;
    s.net[e] = 0;
    s.seen[e] = 0;
  }
  return ok && simple_polygon(topo.points, s, k);
}

}  // namespace

void TriangleBvh::mark_flat_patches(const SceneTopology& topo) {
  const std::size_t nodes = nodes_.size(), size = triangles_.size();
  flat_.assign(nodes, kNone);
  entry_patch_.assign(size, kNone);
  patches_ = 0;
  if (nodes == 0) return;
  // Local slots for the triangles of this hierarchy (one mesh's ids are contiguous).
  const auto [lowest, highest] = std::minmax_element(triangles_.begin(), triangles_.end());
  const std::uint32_t base = *lowest;
  std::vector<std::uint32_t> entry(*highest - base + 1, kNone);  // slot -> entry in triangles_
  for (std::uint32_t x = 0; x < size; ++x) entry[triangles_[x] - base] = x;
  std::vector<std::uint32_t> stamp(entry.size(), kNone);   // slot -> last growth that asked it
  std::vector<std::uint32_t> corner(topo.points.size(), kNone);  // vertex -> last growth touching it
  auto normal_of = [&](std::uint32_t t) {
    const auto& tri = topo.tris[t];
    const Vec3 &a = topo.points[tri[0]], &b = topo.points[tri[1]], &c = topo.points[tri[2]];
    return cross(sub(b, a), sub(c, a));
  };
  auto turn_of = [&](std::uint32_t t, int k) {
    const auto& tri = topo.tris[t];
    return turn(topo.points[tri[0]], topo.points[tri[1]], topo.points[tri[2]], k);
  };
  std::vector<std::uint32_t> side(topo.edges.size(), kNone);  // edge -> last growth bordering it
  // The growing disk's boundary loop, oriented as its triangles: loop_next[v] for the corners of
  // this growth (corner[v] == growth) on it, kNone inside.
  std::vector<std::uint32_t> loop_next(topo.points.size(), kNone);
  std::uint32_t loop_start = kNone;
  std::size_t loop_size = 0;
  PatchScratch scratch;
  scratch.net.assign(topo.edges.size(), 0);
  scratch.seen.assign(topo.edges.size(), 0);
  scratch.next.assign(topo.points.size(), kNone);
  std::vector<std::uint32_t> members;
  std::uint32_t growth = 0;
  // Seeds in the hierarchy's order. From each unclaimed seed, a breadth-first growth over shared
  // edges takes the unclaimed triangles that turn the seed's way along the direction nearest the
  // seed's normal (exact) and lie within 60 degrees of it (rounded: only the shape of the patches
  // depends on it), keeping the patch a disk: a triangle joins across one taken edge with a new
  // third corner, or across two (filling a notch). Every prefix of the growth is then a disk too.
  // Grown to kFirstPatch triangles, then to twice as many while the whole still passes the exact
  // test (flat_patch): the longest passing prefix is kept, the rest left for later seeds. When the
  // first one fails, its halves, quarters, ... are tried instead.
  constexpr std::size_t kFirstPatch = 128;
  for (std::uint32_t x = 0; x < size; ++x) {
    const std::uint32_t seed = triangles_[x];
    if (entry_patch_[x] != kNone) continue;
    const Vec3 n = normal_of(seed);
    int k = 0;
    double best = -1.0;
    for (int d = 0; d < kDirections; ++d) {
      const double along = std::abs(dot(n, kDirection[d].w)) * inverse_length(d);
      if (along > best) {
        best = along;
        k = d;
      }
    }
    const int sign = turn_of(seed, k);
    if (sign == 0) continue;
    const Vec3& w = kDirection[k].w;
    const double w_length = 1.0 / inverse_length(k);
    ++growth;
    members.assign(1, seed);
    stamp[seed - base] = growth;
    for (const std::uint32_t v : topo.tris[seed]) corner[v] = growth;
    for (const std::uint32_t e : topo.tri_edges[seed]) side[e] = growth;
    for (int c = 0; c < 3; ++c) loop_next[topo.tris[seed][c]] = topo.tris[seed][(c + 1) % 3];
    loop_start = topo.tris[seed][0];
    loop_size = 3;
    std::size_t head = 0;
    auto grow = [&](std::size_t limit) {
      for (; head < members.size() && members.size() < limit; ++head) {
        const std::uint32_t t = members[head];
        for (const std::uint32_t e : topo.tri_edges[t])
          for (std::uint32_t i = topo.edge_face_begin[e]; i < topo.edge_face_begin[e + 1]; ++i) {
            const std::uint32_t u = topo.edge_faces[i];
            if (u < base || u - base >= entry.size()) continue;
            const std::uint32_t slot = u - base;
            if (entry[slot] == kNone || stamp[slot] == growth || entry_patch_[entry[slot]] != kNone) continue;
            // Which of u's edges border the disk (edge c joins corners c and c + 1), and whether
            // they run against the loop (u oriented as the disk) and follow one another on it.
            const auto& q = topo.tris[u];
            unsigned mask = 0;
            for (int c = 0; c < 3; ++c)
              if (side[topo.tri_edges[u][c]] == growth) mask |= 1u << c;
            // One edge: that one; two: the later of them in u's cyclic order.
            static constexpr int kFirst[8] = {0, 0, 1, 1, 2, 0, 2, 0};
            const int taken = (mask & 1u) + (mask >> 1 & 1u) + (mask >> 2 & 1u), first = kFirst[mask];
            const std::uint32_t x = q[first], y = q[(first + 1) % 3], z = q[(first + 2) % 3];
            bool joins = false;
            if (taken == 1) {
              // Across y -> x on the loop (u has x -> y), with a new third corner z.
              joins = corner[z] != growth && loop_next[y] == x;
            } else if (taken == 2) {
              // u's edges z -> x and x -> y border it: the loop runs y -> x -> z; x goes inside.
              joins = loop_next[y] == x && loop_next[x] == z;
            }
            if (!joins) continue;  // asked again later
            stamp[slot] = growth;  // asked: in this patch, or never
            const Vec3 nu = normal_of(u);
            if (!(sign * dot(nu, w) >= 0.5 * std::sqrt(dot(nu, nu)) * w_length) || turn_of(u, k) != sign)
              continue;
            if (taken == 1) {
              loop_next[y] = z;
              loop_next[z] = x;
              corner[z] = growth;
              ++loop_size;
            } else {
              loop_next[y] = z;
              loop_next[x] = kNone;
              if (loop_start == x) loop_start = y;
              --loop_size;
            }
            for (const std::uint32_t f : topo.tri_edges[u]) side[f] = growth;
            members.push_back(u);
          }
      }
    };
    std::size_t kept = 0;
    for (std::size_t limit = kFirstPatch;; limit *= 2) {
      grow(limit);
      // The disk's loop as the growth keeps it (flat_patch would find the same from its edges).
      if (!walk_loop(loop_next, loop_start, loop_size, scratch.loop) ||
          !simple_polygon(topo.points, scratch, k))
        break;
      kept = members.size();
      if (head >= members.size()) break;  // nothing more to take
    }
    if (kept == 0)
      for (std::size_t length = members.size() / 2; length >= 2 && kept == 0; length /= 2)
        if (flat_patch(topo, members.data(), length, k, scratch)) kept = length;
    if (kept >= 2) {  // one triangle alone has no pair to skip
      for (std::size_t m = 0; m < kept; ++m) entry_patch_[entry[members[m] - base]] = patches_;
      ++patches_;
    }
  }
  // The hierarchy again, each patch one subtree: at the first entry of each patch all of its
  // entries (in their order), an entry in no patch where it is; the ranges cut at the patch border
  // nearest their middle while they hold several. Only the speed of queries depends on the shape.
  std::vector<std::uint32_t> start(patches_ + 1, 0), listed(size), order;
  for (std::uint32_t x = 0; x < size; ++x)
    if (entry_patch_[x] != kNone) ++start[entry_patch_[x] + 1];
  for (std::size_t p = 0; p < patches_; ++p) start[p + 1] += start[p];
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t x = 0; x < size; ++x)
      if (entry_patch_[x] != kNone) listed[fill[entry_patch_[x]]++] = x;
  }
  order.reserve(size);
  for (std::uint32_t x = 0; x < size; ++x) {
    const std::uint32_t patch = entry_patch_[x];
    if (patch == kNone) {
      order.push_back(x);
    } else if (listed[start[patch]] == x) {
      order.insert(order.end(), listed.begin() + start[patch], listed.begin() + start[patch + 1]);
    }
  }
  // Rebuilt unless one patch holds everything (the root is that patch) or there is none.
  if (patches_ > 0 && start[1] < size) {
    std::vector<std::uint32_t> triangles(size), patch_of(size), cuts;
    std::vector<Box3> boxes(size);
    for (std::uint32_t x = 0; x < size; ++x) {
      triangles[x] = triangles_[order[x]];
      boxes[x] = leaf_boxes_[order[x]];
      patch_of[x] = entry_patch_[order[x]];
      if (x > 0 && (patch_of[x] == kNone || patch_of[x] != patch_of[x - 1])) cuts.push_back(x);
    }
    triangles_.swap(triangles);
    leaf_boxes_.swap(boxes);
    entry_patch_.swap(patch_of);
    nodes_.clear();
    build(0, static_cast<std::uint32_t>(size), &cuts);
    flat_.assign(nodes_.size(), kNone);
  }
  // A node holds one patch when all of its triangles do. Children come after their parent.
  for (std::size_t n = nodes_.size(); n-- > 0;) {
    const Node& node = nodes_[n];
    if (node.count > 0) {
      std::uint32_t patch = entry_patch_[node.first];
      for (std::uint32_t x = node.first + 1; x < node.first + node.count; ++x)
        if (entry_patch_[x] != patch) patch = kNone;
      flat_[n] = patch;
    } else {
      flat_[n] = flat_[node.left] == flat_[node.right] ? flat_[node.left] : kNone;
    }
  }
}

std::size_t TriangleBvh::flat_patch_triangles() const {
  std::size_t count = 0;
  for (const std::uint32_t patch : entry_patch_)
    if (patch != kNone) ++count;
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
  for (std::size_t i = 0; i < tris.size(); ++i) boxes[i] = triangle_box(topo, tris[i]);
  build_over_boxes(std::move(boxes), tris, false);
}

TriangleBvh::TriangleBvh(std::vector<Box3> boxes) {
  if (boxes.empty()) return;
  std::vector<std::uint32_t> ids(boxes.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<std::uint32_t>(i);
  build_over_boxes(std::move(boxes), ids, true);
}

void TriangleBvh::build_over_boxes(std::vector<Box3> boxes, const std::vector<std::uint32_t>& tris,
                                   bool split_by_code) {
  if (tris.empty()) return;
  Box3 all = boxes[0];
  for (std::size_t i = 1; i < tris.size(); ++i) all = merged(all, boxes[i]);
  // Order the triangles along a Morton curve of their box centres (ties by id): neighbours in the
  // order are neighbours in space, so halving ranges builds a sound hierarchy with a single sort.
  std::vector<std::uint32_t> code(tris.size()), order(tris.size());
  for (std::size_t i = 0; i < tris.size(); ++i) {
    Vec3 centre;
    for (int a = 0; a < 3; ++a) centre[a] = 0.5 * (boxes[i].lo[a] + boxes[i].hi[a]);
    code[i] = morton_code(centre, all);
    order[i] = static_cast<std::uint32_t>(i);  // i follows the triangle id order
  }
  sort_by_code(code, order);
  triangles_.resize(tris.size());
  leaf_boxes_.resize(tris.size());
  for (std::size_t i = 0; i < order.size(); ++i) {
    triangles_[i] = tris[order[i]];
    leaf_boxes_[i] = boxes[order[i]];
  }
  // A binary tree over leaves of 2 to 4 triangles has fewer than tris.size() nodes; split by code,
  // leaves may hold one, and it has fewer than twice as many.
  nodes_.reserve(split_by_code ? 2 * tris.size() : tris.size());
  if (split_by_code) {
    std::vector<std::uint32_t> sorted(order.size());
    for (std::size_t i = 0; i < order.size(); ++i) sorted[i] = code[order[i]];
    build(0, static_cast<std::uint32_t>(tris.size()), nullptr, &sorted);
    return;
  }
  build(0, static_cast<std::uint32_t>(tris.size()), nullptr);
}

void TriangleBvh::refit(const SceneTopology& topo) {
  flat_.clear();  // marked for the positions it was built at
  entry_patch_.clear();
  patches_ = 0;
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

std::uint32_t TriangleBvh::build(std::uint32_t first, std::uint32_t count,
                                 const std::vector<std::uint32_t>* cuts,
                                 const std::vector<std::uint32_t>* code) {
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
  std::uint32_t half = count / 2;
  if (cuts != nullptr) {
    // The cut inside the range nearest its middle, if any.
    const auto at = std::lower_bound(cuts->begin(), cuts->end(), first + half);
    std::uint32_t best = 0;
    if (at != cuts->end() && *at < first + count) best = *at - first;
    if (at != cuts->begin() && *(at - 1) > first) {
      const std::uint32_t below = *(at - 1) - first;
      if (best == 0 || half - below < best - half) best = below;
    }
    if (best != 0) half = best;
  } else if (code != nullptr) {
    half = code_split(*code, first, count);
  }
  const std::uint32_t left = build(first, half, cuts, code);
  const std::uint32_t right = build(first + half, count - half, cuts, code);
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
