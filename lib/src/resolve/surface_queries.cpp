// Closest-point trees, near points and oriented normals for the move kinds.
#include "resolve/surface_queries.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "geometry/vec3.h"
#include "resolve/mesh_tree_cgal.h"

namespace untangle {

std::unique_ptr<MeshTree> build_tree(const SceneTopology& topo,
                                     const std::vector<std::uint32_t>& tris) {
  auto out = std::make_unique<MeshTree>();
  // Sized once: grown by doubling, the body's 27,300 triangles were copied and their pages first
  // touched several times over.
  out->cgal->triangles.reserve(tris.size());
  out->ids.reserve(tris.size());
  std::vector<Box3> boxes;
  boxes.reserve(tris.size());
  for (std::uint32_t t : tris) {
    const auto& tri = topo.tris[t];
    auto p = [&](int k) {
      const Vec3& v = topo.points[tri[k]];
      return TreeKernel::Point_3(v[0], v[1], v[2]);
    };
    out->cgal->triangles.emplace_back(p(0), p(1), p(2));
    out->ids.push_back(t);
    boxes.push_back(triangle_box(topo, t));
  }
  out->boxes = TriangleBvh(std::move(boxes));
  return out;
}

MeshTree::MeshTree() : cgal(std::make_unique<MeshTreeCgal>()) {}
MeshTree::~MeshTree() = default;

const TriangleTree& MeshTreeCgal::ray_tree() const {
  std::call_once(rays_built_, [this] {
    rays_ = std::make_unique<TriangleTree>(triangles.begin(), triangles.end());
  });
  return *rays_;
}

namespace {

// The squared distance from p to triangle (a, b, c) in plain doubles (Ericson, Real-Time Collision
// Detection, 5.1.5): only a filter, about twenty times cheaper than CGAL's projection, whose
// predicates decide on which side of an edge the point falls.
double rough_squared_distance(const TreeKernel::Triangle_3& t, const Vec3& p) {
  const Vec3 a{t[0].x(), t[0].y(), t[0].z()};
  const Vec3 b{t[1].x(), t[1].y(), t[1].z()};
  const Vec3 c{t[2].x(), t[2].y(), t[2].z()};
  auto squared = [&p](const Vec3& q) {
    const Vec3 d = sub(p, q);
    return dot(d, d);
  };
  const Vec3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return squared(a);
  const Vec3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return squared(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return squared(add(a, scale(ab, d1 / (d1 - d3))));
  const Vec3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return squared(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return squared(add(a, scale(ac, d2 / (d2 - d6))));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return squared(add(b, scale(sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)))));
  const double denom = va + vb + vc;
  if (!(denom > 0.0)) return 0.0;  // degenerate: never filtered out
  const double v = vb / denom, w = vc / denom;
  return squared(add(a, add(scale(ab, v), scale(ac, w))));
}

// The largest coordinate magnitude of p and t's corners: the scale of the filter's rounding.
double magnitude(const TreeKernel::Triangle_3& t, const Vec3& p) {
  double m = std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
  for (int k = 0; k < 3; ++k)
    m = std::max({m, std::abs(t[k].x()), std::abs(t[k].y()), std::abs(t[k].z())});
  return m;
}

}  // namespace

Closest closest_on(const MeshTree& tree, const Vec3& p) {
  const TreeKernel::Point_3 q(p[0], p[1], p[2]);
  const auto project = TreeKernel().construct_projected_point_3_object();
  const auto compare = TreeKernel().compare_distance_3_object();
  // The nearest projection, decided exactly between the projections (as CGAL's traversal decides
  // them); equally near ones by the lowest id (CGAL kept whichever its traversal met last).
  constexpr std::size_t kNoEntry = ~std::size_t{0};
  std::size_t found = kNoEntry;
  TreeKernel::Point_3 at_point;
  double squared = INFINITY;
  tree.boxes.nearest(p, [&](std::uint32_t k) {
    const TreeKernel::Triangle_3& triangle = tree.cgal->triangles[k];
    // A triangle surely farther than the nearest so far is not projected: the filter's distance
    // within a relative 1e-9 and a billionth of the coordinates' scale (its rounding is a few units
    // in the last place of the coordinates, and so is the projection's).
    if (found != kNoEntry) {
      const double tolerance = 1e-9 * magnitude(triangle, p);
      if (rough_squared_distance(triangle, p) > squared + 1e-9 * squared + tolerance * tolerance)
        return squared;
    }
    const TreeKernel::Point_3 c = project(triangle, q);
    bool take = found == kNoEntry;
    if (!take) {
      const CGAL::Comparison_result r = compare(q, c, at_point);
      take = r == CGAL::SMALLER || (r == CGAL::EQUAL && tree.ids[k] < tree.ids[found]);
    }
    if (take) {
      found = k;
      at_point = c;
      squared = CGAL::squared_distance(q, c);
    }
    return squared;
  });
  if (found == kNoEntry) return {p, 0, INFINITY};
  const Vec3 at{at_point.x(), at_point.y(), at_point.z()};
  // Inside its triangle, away from the corners and edges (by a millionth of a millionth of the
  // edge), the point is the triangle's alone: another triangle as close would have to lie at the
  // same distance across the gap, which only a symmetric scene gives.
  const TreeKernel::Triangle_3& t = tree.cgal->triangles[found];
  bool inside = true;
  double longest2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const Vec3 a{t[k].x(), t[k].y(), t[k].z()};
    const Vec3 b{t[(k + 1) % 3].x(), t[(k + 1) % 3].y(), t[(k + 1) % 3].z()};
    const Vec3 edge = sub(b, a);
    const double length2 = dot(edge, edge);
    longest2 = std::max(longest2, length2);
    inside = inside && norm(cross(edge, sub(at, a))) > 1e-12 * length2;
  }
  if (inside) return {at, tree.ids[found], squared};
  // On a corner or an edge: the triangles holding that point (those that meet a box around it a
  // millionth of the longest edge wide, decided exactly, as CGAL's box query decided it).
  const double reach = 1e-6 * std::sqrt(longest2);
  Box3 box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = at[a] - reach;
    box.hi[a] = at[a] + reach;
  }
  std::vector<std::uint32_t> near;
  tree.boxes.query(box, near);
  near.push_back(static_cast<std::uint32_t>(found));
  Closest best;
  best.squared = INFINITY;
  bool any = false;
  const CGAL::Bbox_3 exact_box(box.lo[0], box.lo[1], box.lo[2], box.hi[0], box.hi[1], box.hi[2]);
  for (std::uint32_t k : near) {
    if (k != found && !CGAL::do_intersect(exact_box, tree.cgal->triangles[k])) continue;
    const std::uint32_t face = tree.ids[k];
    const TreeKernel::Point_3 c = project(tree.cgal->triangles[k], q);
    const double d2 = CGAL::squared_distance(q, c);
    if (!any || d2 < best.squared || (d2 == best.squared && face < best.face)) {
      best = {Vec3{c.x(), c.y(), c.z()}, face, d2};
      any = true;
    }
  }
  return best;
}

bool first_ray_hit(const MeshTree& tree, const Vec3& from, const Vec3& direction, Vec3& out) {
  if (tree.empty()) return false;
  const TreeKernel::Point_3 p(from[0], from[1], from[2]);
  // CGAL's ray is handed a direction as long as the tree's box diagonal: its traversal and the
  // coplanarity test below use from + d, which with a unit direction mixes the scene's length
  // with a fixed one, so that the primitive found (and so the continuation's plan) changed in its
  // last bits when the scene was scaled by 1024 (issue 21). Scaled by the diagonal, a scene scaled
  // by a power of two gives the same hits scaled. The hit point below is homogeneous either way.
  const TriangleTree& rays = tree.cgal->ray_tree();
  const CGAL::Bbox_3 box = rays.bbox();
  const double dx = box.xmax() - box.xmin(), dy = box.ymax() - box.ymin(),
               dz = box.zmax() - box.zmin();
  const double diagonal = std::sqrt(dx * dx + dy * dy + dz * dz);
  const double length = norm(direction);
  const double stretch = diagonal > 0.0 && length > 0.0 ? diagonal / length : 1.0;
  const TreeKernel::Vector_3 d(direction[0] * stretch, direction[1] * stretch,
                               direction[2] * stretch);
  const auto hit = rays.first_intersected_primitive(TreeKernel::Ray_3(p, d));
  if (!hit) return false;
  const TreeKernel::Triangle_3& triangle = **hit;
  if (CGAL::orientation(triangle[0], triangle[1], triangle[2], p) == CGAL::COPLANAR &&
      CGAL::orientation(triangle[0], triangle[1], triangle[2], p + d) == CGAL::COPLANAR)
    return false;  // along a segment
  auto vec = [](const TreeKernel::Point_3& q) { return Vec3{q.x(), q.y(), q.z()}; };
  const Vec3 a = vec(triangle[0]);
  const Vec3 n = cross(sub(vec(triangle[1]), a), sub(vec(triangle[2]), a));
  const double across = dot(n, direction);
  if (!(across != 0.0)) return false;
  const double t = std::max(0.0, dot(n, sub(a, from)) / across);
  out = add(from, scale(direction, t));
  return true;
}

Vec3 face_normal(const SceneTopology& topo, std::uint32_t t) {
  const auto& tri = topo.tris[t];
  return unit(cross(sub(topo.points[tri[1]], topo.points[tri[0]]),
                    sub(topo.points[tri[2]], topo.points[tri[0]])));
}

Vec3 oriented_normal(const SceneTopology& topo, const SceneMeasures& measures, std::uint32_t t) {
  return scale(face_normal(topo, t), measures.orientation[t] < 0 ? -1.0 : 1.0);
}

Vec3 oriented_vertex_normal(const SceneTopology& topo, const SceneMeasures& measures,
                            std::uint32_t v) {
  Vec3 sum{0.0, 0.0, 0.0};
  for (std::uint32_t j = topo.vertex_edge_begin[v]; j < topo.vertex_edge_begin[v + 1]; ++j) {
    const std::uint32_t e = topo.vertex_edges[j];
    for (std::uint32_t k = topo.edge_face_begin[e]; k < topo.edge_face_begin[e + 1]; ++k) {
      const std::uint32_t t = topo.edge_faces[k];
      const auto& tri = topo.tris[t];
      const Vec3 area = cross(sub(topo.points[tri[1]], topo.points[tri[0]]),
                              sub(topo.points[tri[2]], topo.points[tri[0]]));
      // Each face is met through both its edges at v: twice, which the unit() below forgives.
      sum = add(sum, scale(area, measures.orientation[t] < 0 ? -1.0 : 1.0));
    }
  }
  return unit(sum);
}

bool on_hem(const SceneTopology& topo, std::uint32_t t, const Vec3& c) {
  for (std::uint32_t e : topo.tri_edges[t]) {
    if (!topo.is_boundary(e)) continue;
    const Vec3& a = topo.points[topo.edges[e][0]];
    const Vec3 ab = sub(topo.points[topo.edges[e][1]], a);
    const double len2 = dot(ab, ab);
    const double u = len2 > 0.0 ? std::clamp(dot(sub(c, a), ab) / len2, 0.0, 1.0) : 0.0;
    if (norm(sub(c, add(a, scale(ab, u)))) <= 1e-9 * std::sqrt(len2)) return true;
  }
  return false;
}

const MeshTree& SurfaceTrees::component_tree(std::uint32_t component, FreshTrees& fresh) {
  const std::uint32_t m = topo_.component_mesh[component];
  const bool fixed = measures_.role[m] == Role::kObstacle;
  std::unique_ptr<MeshTree>& tree = fixed ? obstacle_trees_[component] : fresh[component];
  if (!tree) {
    std::vector<std::uint32_t> tris;
    for (std::uint32_t t = topo_.mesh_tri_begin[m]; t < topo_.mesh_tri_begin[m + 1]; ++t)
      if (topo_.tri_component(t) == component) tris.push_back(t);
    if (fixed && measures_.closed[component] != 0) {
      std::vector<std::uint32_t> exposed;
      for (std::uint32_t t : tris)
        if (!measures_.buried[t]) exposed.push_back(t);
      if (!exposed.empty()) tris = std::move(exposed);
    }
    tree = build_tree(topo_, tris);
  }
  return *tree;
}

bool SurfaceTrees::nearest_obstacle_point(const Vec3& p, Vec3& out) {
  double best = INFINITY;
  FreshTrees unused;  // obstacles' trees are kept
  for (std::uint32_t c = 0; c < topo_.component_mesh.size(); ++c) {
    if (measures_.movable_component(topo_, c) || measures_.closed[c] == 0) continue;
    const MeshTree& tree = component_tree(c, unused);
    if (tree.empty()) continue;
    const Vec3 point = closest_on(tree, p).point;
    const double d = norm(sub(p, point));
    if (d < best) {
      best = d;
      out = point;
    }
  }
  return std::isfinite(best);
}

const MeshTree& SurfaceTrees::obstacle_tree(const std::vector<std::uint32_t>& tris) {
  for (const auto& [component, tree] : obstacle_trees_)
    if (tree && tree->ids == tris) return *tree;
  for (const std::unique_ptr<MeshTree>& tree : obstacle_lists_)
    if (tree->ids == tris) return *tree;
  obstacle_lists_.push_back(build_tree(topo_, tris));
  return *obstacle_lists_.back();
}

std::vector<NearPoint> near_points(const SceneTopology& topo, const SceneMeasures& measures,
                                   std::uint32_t component, const MeshTree& tree, double near,
                                   long long& vote) {
  std::vector<NearPoint> out;
  vote = 0;
  const std::uint32_t mesh = topo.component_mesh[component];
  for (std::uint32_t v = topo.mesh_vertex_begin[mesh]; v < topo.mesh_vertex_begin[mesh + 1]; ++v) {
    if (topo.vertex_component[v] != component) continue;
    const Vec3& p = topo.points[v];
    const Closest hit = closest_on(tree, p);
    const Vec3& c = hit.point;
    if (norm(sub(p, c)) > near) continue;
    const std::uint32_t face = hit.face;
    const Vec3 n = oriented_normal(topo, measures, face);
    const double side = dot(sub(p, c), n);
    vote += side > 0 ? 1 : side < 0 ? -1 : 0;
    out.push_back({v, face, c, n, side});
  }
  return out;
}

double area_vote(const SceneTopology& topo, const std::vector<NearPoint>& near) {
  double sum = 0.0, total = 0.0;
  for (const NearPoint& x : near) {
    double area = 0.0;  // twice the vertex area: each face is met through both its edges at v
    for (std::uint32_t j = topo.vertex_edge_begin[x.v]; j < topo.vertex_edge_begin[x.v + 1]; ++j) {
      const std::uint32_t e = topo.vertex_edges[j];
      for (std::uint32_t k = topo.edge_face_begin[e]; k < topo.edge_face_begin[e + 1]; ++k) {
        const auto& tri = topo.tris[topo.edge_faces[k]];
        area += norm(cross(sub(topo.points[tri[1]], topo.points[tri[0]]),
                           sub(topo.points[tri[2]], topo.points[tri[0]])));
      }
    }
    sum += x.side > 0 ? area : x.side < 0 ? -area : 0.0;
    total += area;
  }
  return total > 0.0 ? sum / total : 0.0;
}

}  // namespace untangle
