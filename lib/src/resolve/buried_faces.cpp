// buried_faces: faces of the closed obstacles whose outer side lies inside an obstacle.
#include "resolve/buried_faces.h"

#include <algorithm>
#include <array>
#include <iterator>

#include "detect/detect_crossings.h"
#include "detect/run_parallel.h"
#include "detect/triangle_bvh.h"
#include "geometry/vec3.h"
#include "resolve/triangle_tree.h"

namespace untangle {
namespace {

constexpr std::size_t kRegionSamples = 7;
constexpr std::size_t kParts = 64;  // parts of the descent, for parallel loops

int shared_corners(const std::array<std::uint32_t, 3>& a, const std::array<std::uint32_t, 3>& b) {
  int shared = 0;
  for (std::uint32_t v : a) shared += (v == b[0] || v == b[1] || v == b[2]) ? 1 : 0;
  return shared;
}

// Whether triangles a and b (sharing at most one corner) cross under detection's predicates: an
// edge of one through the other, skipping edges that share a corner with it. Two triangles that
// share one corner cross along a segment from it (a loop vertex) exactly when the edge opposite
// the shared corner in one passes through the other.
bool pair_crosses(const std::vector<Vec3>& points, const std::array<std::uint32_t, 3>& a,
                  const std::array<std::uint32_t, 3>& b) {
  auto has = [](const std::array<std::uint32_t, 3>& t, std::uint32_t v) {
    return t[0] == v || t[1] == v || t[2] == v;
  };
  auto edges_through = [&](const std::array<std::uint32_t, 3>& e,
                           const std::array<std::uint32_t, 3>& t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t p = e[k], q = e[(k + 1) % 3];
      if (has(t, p) || has(t, q)) continue;
      if (edge_crosses_triangle(points, p, q, t[0], t[1], t[2])) return true;
    }
    return false;
  };
  return edges_through(a, b) || edges_through(b, a);
}

// The orientation of the surface that holds triangle t.
int orientation_of(const std::vector<ClosedSurface>& surfaces, std::uint32_t t) {
  for (const ClosedSurface& s : surfaces)
    if (std::binary_search(s.triangles.begin(), s.triangles.end(), t)) return s.orientation;
  return 1;
}

class Winding {
 public:
  explicit Winding(const SceneTopology& topology, const std::vector<ClosedSurface>& surfaces) {
    for (const ClosedSurface& surface : surfaces) {
      for (std::uint32_t t : surface.triangles) {
        const auto& tri = topology.tris[t];
        auto p = [&](int k) {
          const Vec3& v = topology.points[tri[k]];
          return TreeKernel::Point_3(v[0], v[1], v[2]);
        };
        list_.emplace_back(p(0), p(1), p(2));
        sign_.push_back(surface.orientation);
      }
    }
    tree_.insert(list_.begin(), list_.end());
  }

  // The winding number of the surfaces about q: the median over three fixed directions of the
  // signed count of faces a ray from q crosses (+1 leaving through a face's outer side). A ray
  // through an edge or a vertex counts its faces twice or not at all; the other two rays outvote
  // it.
  int at(const Vec3& q) const {
    static constexpr std::array<std::array<double, 3>, 3> kDirections = {{
        {0.5361, 0.6723, 0.5105},
        {-0.7071, 0.3119, 0.6346},
        {0.2234, -0.8829, 0.4129},
    }};
    std::array<int, 3> counts{};
    for (std::size_t r = 0; r < kDirections.size(); ++r) {
      const auto& d = kDirections[r];
      hits_.clear();
      tree_.all_intersected_primitives(TreeKernel::Ray_3(TreeKernel::Point_3(q[0], q[1], q[2]),
                                                         TreeKernel::Vector_3(d[0], d[1], d[2])),
                                       std::back_inserter(hits_));
      int count = 0;
      for (const auto& hit : hits_) {
        const TreeKernel::Vector_3 n = hit->supporting_plane().orthogonal_vector();
        const double s = (n.x() * d[0] + n.y() * d[1] + n.z() * d[2]) *
                         sign_[static_cast<std::size_t>(hit - list_.begin())];
        count += s > 0.0 ? 1 : s < 0.0 ? -1 : 0;
      }
      counts[r] = count;
    }
    std::sort(counts.begin(), counts.end());
    return counts[1];
  }

 private:
  TreeTriangleList list_;
  std::vector<int> sign_;  // per entry of list_: its surface's orientation
  TriangleTree tree_;
  mutable std::vector<TreePrimitive::Id> hits_;
};

// Whether the outer side of triangle t lies inside a surface: the winding number a
// thousandth of its shortest edge outside its centroid is not 0.
bool outer_side_inside(const SceneTopology& topology, std::uint32_t t, int orientation,
                       const Winding& winding) {
  const auto& tri = topology.tris[t];
  const Vec3& a = topology.points[tri[0]];
  const Vec3& b = topology.points[tri[1]];
  const Vec3& c = topology.points[tri[2]];
  const Vec3 n = cross(sub(b, a), sub(c, a));
  const double length = norm(n);
  if (length == 0.0) return false;
  const double shortest = std::min({norm(sub(b, a)), norm(sub(c, b)), norm(sub(a, c))});
  const double offset = 1e-3 * shortest * orientation / length;
  Vec3 q;
  for (int k = 0; k < 3; ++k) q[k] = (a[k] + b[k] + c[k]) / 3.0 + offset * n[k];
  return winding.at(q) != 0;
}

}  // namespace

std::vector<std::vector<std::uint8_t>> buried_faces(const SceneTopology& topology,
                                                    const std::vector<ClosedSurface>& surfaces,
                                                    int threads, std::size_t* crossing_pairs) {
  if (crossing_pairs != nullptr) *crossing_pairs = 0;
  std::vector<std::vector<std::uint8_t>> buried;
  std::vector<std::uint32_t> all;  // every triangle of every surface, ascending
  for (const ClosedSurface& surface : surfaces) {
    buried.emplace_back(surface.triangles.size(), 0);
    all.insert(all.end(), surface.triangles.begin(), surface.triangles.end());
  }
  std::sort(all.begin(), all.end());
  const std::size_t n = all.size();
  if (n == 0) return buried;
  auto local = [&](std::uint32_t t) {
    const auto it = std::lower_bound(all.begin(), all.end(), t);
    return it != all.end() && *it == t ? static_cast<std::size_t>(it - all.begin()) : n;
  };

  // The triangles of crossing pairs: where the intersection curves run. Each part of the descent
  // lists its own; the flags do not depend on the order they are joined in.
  // The pairs inside one flat patch meet only where they share a vertex or an edge (exact, the
  // same test as detection's self pairs): skipped, with the same crossing pairs found. A ground
  // plate or a spike's flank is one patch instead of thousands of coplanar pairs for the
  // perturbation to decide one by one.
  TriangleBvh bvh(topology, all);
  bvh.mark_flat_patches(topology);
  const std::vector<TriangleBvh::Part> parts = bvh.split(bvh, true, kParts);
  // Each triangle's plane for the pruning test, found once (a triangle is in a dozen pairs).
  const auto& tris = topology.detect_tris();  // shared positions are one point (DESIGN §2)
  std::vector<TriPlane> planes(topology.tris.size());
  run_parallel(threads, n, 1024, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) planes[all[i]] = triangle_plane(topology.points, tris[all[i]]);
  });
  std::vector<std::vector<std::uint32_t>> found(parts.size());
  run_parallel(threads, parts.size(), 1, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      bvh.each_pair_in(bvh, parts[k], true, [&](std::uint32_t t, std::uint32_t u) {
        const auto& a = tris[t];
        const auto& b = tris[u];
        if (shared_corners(a, b) >= 2 ||
            triangles_surely_apart(topology.points, a, b, planes[t], planes[u]))
          return;
        if (!pair_crosses(topology.points, a, b)) return;
        found[k].push_back(t);
        found[k].push_back(u);
      });
    }
  });
  std::vector<std::uint8_t> cut(n, 0);
  bool any = false;
  for (const auto& list : found) {
    for (std::uint32_t t : list) cut[local(t)] = 1, any = true;
    if (crossing_pairs != nullptr) *crossing_pairs += list.size() / 2;
  }
  // One closed surface that crosses nothing is embedded: nothing of it is inside it. Two or more
  // may still lie one inside another (an eye in a head) without crossing.
  if (!any && surfaces.size() < 2) return buried;

  const Winding winding(topology, surfaces);
  std::vector<std::uint8_t> flags(n, 0);  // by entry of `all`
  // Regions of the other triangles, flooded across shared edges, in ascending order of their
  // lowest triangle.
  std::vector<std::uint8_t> reached(n, 0);
  std::vector<std::size_t> members;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (cut[seed]) {
      // An intersection curve runs through it: part of it is buried, and a closest point on that
      // part is inside. The exposed faces around it still hold the surface.
      flags[seed] = 1;
      continue;
    }
    if (reached[seed]) continue;
    members.assign(1, seed);
    reached[seed] = 1;
    for (std::size_t i = 0; i < members.size(); ++i) {
      for (std::uint32_t e : topology.tri_edges[all[members[i]]]) {
        for (std::uint32_t k = topology.edge_face_begin[e]; k < topology.edge_face_begin[e + 1];
             ++k) {
          const std::size_t j = local(topology.edge_faces[k]);
          if (j == n || cut[j] || reached[j]) continue;
          reached[j] = 1;
          members.push_back(j);
        }
      }
    }
    std::sort(members.begin(), members.end());
    const std::size_t samples = std::min(kRegionSamples, members.size());
    std::size_t inside = 0;
    for (std::size_t s = 0; s < samples; ++s) {
      const std::uint32_t pick = all[members[s * members.size() / samples]];
      if (outer_side_inside(topology, pick, orientation_of(surfaces, pick), winding)) ++inside;
    }
    if (2 * inside > samples)
      for (std::size_t j : members) flags[j] = 1;
  }
  for (std::size_t s = 0; s < surfaces.size(); ++s)
    for (std::size_t k = 0; k < surfaces[s].triangles.size(); ++k)
      buried[s][k] = flags[local(surfaces[s].triangles[k])];
  return buried;
}

}  // namespace untangle
