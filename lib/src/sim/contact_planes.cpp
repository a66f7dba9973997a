// ContactPlanes (contact_planes.h): CGAL AABB trees over the obstacles' exposed faces (kept) and
// over each cloth mesh (built each step: for self-contact, or where a particle of another mesh
// may be within reach).
#include "sim/contact_planes.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "geometry/vec3.h"
#include "resolve/surface_queries.h"

namespace untangle {
namespace {

// The angle defect (radians) beyond which a convex obstacle vertex is a tip, which gets no face
// plane: about 57 degrees. A sheet held on a spike's tip by a face plane stretched round it
// (edges beyond 2x at frame 36 of the spikes example, measured) where the correction and its
// relaxation spread the same load over rings of the sheet (1.27 at frame 40), so tips are left to
// the correction. Measured: 74 of the MakeHuman male body's 13,652 vertices have a defect beyond
// 0.5 (median 0, 99th percentile 0.42), 101 of the cow's 2,903 (horns, hooves, ears), 24 of the
// spikes' 1,842 (the 16 tips among them, at 3.8).
constexpr double kTip = 1.0;

// Self-contact: a triangle of a particle's own mesh is near it on the cloth, and gives it no plane,
// when one of its corners lies within this many reaches of the particle along the cloth's edges
// in the rest shape. Measured: a falling flat sheet (21 x 21) gets self-planes from frame 1 at
// 0.8, none at 1.0 and above; a sheet folded onto itself (Simulate.SelfContactPlanesLeave...)
// left no crossing for the correction in 40 frames at 1.2 and 1.5, but 1,945 at 2 and 2,404 at 3
// (where the fold closes, its two sides are nearer each other along the cloth than that).
constexpr double kSelfApart = 1.5;

TreeKernel::Point_3 point(const Vec3& v) { return TreeKernel::Point_3(v[0], v[1], v[2]); }

struct Bounds {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  void add(const Vec3& p) {
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], p[c]);
      hi[c] = std::max(hi[c], p[c]);
    }
  }
  // Whether p lies within `reach` of the box, coordinate by coordinate.
  bool within(const Vec3& p, double reach) const {
    for (int c = 0; c < 3; ++c)
      if (p[c] < lo[c] - reach || p[c] > hi[c] + reach) return false;
    return true;
  }
};

// The barycentric coordinates of q (a point of triangle a, b, c) in it, clamped to [0, 1].
Vec3 barycentric(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& q) {
  const Vec3 e0 = sub(b, a), e1 = sub(c, a), e2 = sub(q, a);
  const double d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1);
  const double d20 = dot(e2, e0), d21 = dot(e2, e1);
  const double det = d00 * d11 - d01 * d01;
  if (!(det > 0.0)) return {1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0};
  double v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
  v = std::clamp(v, 0.0, 1.0);
  w = std::clamp(w, 0.0, 1.0 - v);
  return {1.0 - v - w, v, w};
}

// The triangles of a tree whose bounding boxes overlap `box`, tested on the boxes alone (doubles;
// the exact intersection with the box is not needed, the caller measures the distance anyway).
struct BoxOverlaps {
  CGAL::Bbox_3 box;
  std::vector<TreePrimitive::Id>* out;
  bool go_further() const { return true; }
  template <class Query, class Primitive>
  void intersection(const Query&, const Primitive& primitive) {
    if (CGAL::do_overlap(box, primitive.datum().bbox())) out->push_back(primitive.id());
  }
  template <class Query, class Node>
  bool do_intersect(const Query&, const Node& node) const {
    return CGAL::do_overlap(box, node.bbox());
  }
};

}  // namespace

ContactPlanes::ContactPlanes(const std::vector<Mesh>& meshes, const ClothModel& model,
                             int threads) {
  std::vector<Mesh> obstacles;
  for (std::uint32_t m = 0; m < meshes.size(); ++m)
    if (meshes[m].role == Role::kObstacle) {
      obstacle_mesh_.push_back(m);
      obstacles.push_back(meshes[m]);
    }
  if (!obstacles.empty()) {
    topo_ = build_topology(obstacles);
    measures_ = measure_scene(topo_, obstacles, {}, threads);
    // Face planes come from the convex vertices (a positive angle defect: the faces round the
    // vertex leave part of the full angle) that are not tips (kTip), where the obstacle pokes out
    // between the cloth's particles: a coarse ball's vertices. Measured on the fitting example,
    // with planes from every vertex facing from the vertex to the face, edges reached 4x within
    // 23 frames (a growing body puts faces behind vertices, and the directions fought the
    // particles' planes); hence the outward side and the normal.
    std::vector<double> angle(topo_.points.size(), 0.0);
    std::vector<std::uint8_t> used(topo_.points.size(), 0);
    for (std::uint32_t t = 0; t < topo_.tris.size(); ++t)
      if (!measures_.buried[t]) {
        exposed_.push_back(t);
        const auto& tri = topo_.tris[t];
        for (int k = 0; k < 3; ++k) {
          const Vec3& a = topo_.points[tri[k]];
          const Vec3 u = sub(topo_.points[tri[(k + 1) % 3]], a);
          const Vec3 w = sub(topo_.points[tri[(k + 2) % 3]], a);
          angle[tri[k]] += std::atan2(norm(cross(u, w)), dot(u, w));
          used[tri[k]] = 1;
        }
      }
    for (std::uint32_t v = 0; v < topo_.points.size(); ++v)
      if (used[v] && 2.0 * M_PI - angle[v] > 0.0 && 2.0 * M_PI - angle[v] <= kTip)
        exposed_vertices_.push_back(v);
    build_obstacle_tree();
  }
  const std::size_t cloth_meshes = model.cloth_mesh.size();
  cloth_triangles_.resize(cloth_meshes);
  cloth_trees_.resize(cloth_meshes);
}

ContactPlanes::~ContactPlanes() = default;

void ContactPlanes::update_obstacles(const std::vector<Mesh>& meshes) {
  if (obstacle_mesh_.empty()) return;
  for (std::size_t k = 0; k < obstacle_mesh_.size(); ++k) {
    const Mesh& mesh = meshes[obstacle_mesh_[k]];
    for (std::size_t i = 0; i < mesh.positions.size(); ++i)
      topo_.points[topo_.welded[k][i]] = mesh.positions[i];
  }
  build_obstacle_tree();
}

void ContactPlanes::build_obstacle_tree() {
  obstacle_triangles_.clear();
  obstacle_tree_.reset();
  std::fill(lower_.begin(), lower_.end(), INFINITY);
  vertex_lower_.assign(exposed_vertices_.size(), -INFINITY);
  // Outward normals of the convex vertices at the obstacles' positions now: their faces'
  // oriented normal turned outward by the component's closed orientation (0 where it is not
  // closed or not consistently oriented: unknown).
  vertex_outward_.resize(exposed_vertices_.size());
  for (std::size_t k = 0; k < exposed_vertices_.size(); ++k) {
    const std::uint32_t v = exposed_vertices_[k];
    vertex_outward_[k] = scale(oriented_vertex_normal(topo_, measures_, v),
                               static_cast<double>(measures_.closed[topo_.vertex_component[v]]));
  }
  vertex_travel_.assign(exposed_vertices_.size(), 0.0);
  for (std::uint32_t t : exposed_) {
    const auto& tri = topo_.tris[t];
    obstacle_triangles_.emplace_back(point(topo_.points[tri[0]]), point(topo_.points[tri[1]]),
                                     point(topo_.points[tri[2]]));
  }
  if (obstacle_triangles_.empty()) return;
  obstacle_tree_ =
      std::make_unique<TriangleTree>(obstacle_triangles_.begin(), obstacle_triangles_.end());
  obstacle_tree_->accelerate_distance_queries();
}

void ContactPlanes::find_near(const SceneTopology& cloth, double radius) {
  const std::size_t n = cloth.points.size();
  near_begin_.assign(n + 1, 0);
  near_.clear();
  stamp_.assign(n, 0);
  // Dijkstra from each particle over the rest lengths of the edges, as far as `radius`.
  std::vector<double> distance(n, INFINITY);
  std::vector<std::uint32_t> reached;
  using Entry = std::pair<double, std::uint32_t>;
  std::vector<Entry> heap;
  for (std::uint32_t i = 0; i < n; ++i) {
    near_begin_[i] = static_cast<std::uint32_t>(near_.size());
    distance[i] = 0.0;
    reached.assign(1, i);
    heap.assign(1, {0.0, i});
    while (!heap.empty()) {
      std::pop_heap(heap.begin(), heap.end(), std::greater<Entry>());
      const auto [d, v] = heap.back();
      heap.pop_back();
      if (d > distance[v]) continue;
      near_.push_back(v);
      for (std::uint32_t k = cloth.vertex_edge_begin[v]; k < cloth.vertex_edge_begin[v + 1]; ++k) {
        const std::uint32_t w = cloth.vertex_neighbors[k];
        const double e = d + norm(sub(cloth.points[w], cloth.points[v]));
        if (e > radius || !(e < distance[w])) continue;
        if (!std::isfinite(distance[w])) reached.push_back(w);
        distance[w] = e;
        heap.emplace_back(e, w);
        std::push_heap(heap.begin(), heap.end(), std::greater<Entry>());
      }
    }
    for (std::uint32_t v : reached) distance[v] = INFINITY;
  }
  near_begin_[n] = static_cast<std::uint32_t>(near_.size());
}

void ContactPlanes::make(const ClothModel& model, const std::vector<Vec3>& x, double reach,
                         double clearance, double gap, bool self, ContactSet& out) {
  const std::size_t n = x.size();
  const SceneTopology& cloth = model.topo;
  const std::size_t meshes = cloth_trees_.size();
  out.begin.assign(n + 1, 0);
  out.planes.clear();
  self_planes_ = 0;
  if (lower_.size() != n) {
    lower_.assign(n, INFINITY);
    at_.assign(n, Vec3{0.0, 0.0, 0.0});
  }
  // Which cloth meshes need a tree this step: those with another mesh's particle within reach of
  // their bounds.
  std::vector<Bounds> bounds(meshes);
  for (std::size_t i = 0; i < n; ++i) bounds[cloth.vertex_mesh[i]].add(x[i]);
  std::vector<std::uint8_t> needed(meshes, 0);
  // How far the cloth may have moved since the last call: the largest particle step, summed.
  if (last_x_.size() == n) {
    double most = 0.0;
    for (std::size_t i = 0; i < n; ++i) most = std::max(most, norm(sub(x[i], last_x_[i])));
    travel_ += most;
  }
  last_x_ = x;
  // The obstacles' vertices are tested against the cloth's faces (face planes); a vertex whose
  // distance to the cloth, measured earlier, less how far the cloth may have moved since, is
  // beyond reach is not measured again.
  std::vector<std::uint32_t> near_vertices;  // entries of exposed_vertices_
  for (std::uint32_t k = 0; k < exposed_vertices_.size(); ++k) {
    if (vertex_lower_[k] - (travel_ - vertex_travel_[k]) > reach) continue;
    const Vec3& p = topo_.points[exposed_vertices_[k]];
    bool near = false;
    for (std::size_t b = 0; b < meshes; ++b)
      if (bounds[b].within(p, reach)) {
        needed[b] = 1;
        near = true;
      }
    if (near) near_vertices.push_back(k);
  }
  if (meshes > 1)
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t b = 0; b < meshes; ++b)
        if (b != cloth.vertex_mesh[i] && !needed[b] && bounds[b].within(x[i], reach)) needed[b] = 1;
  for (std::size_t b = 0; b < meshes; ++b) {
    cloth_trees_[b].reset();
    cloth_triangles_[b].clear();
    if (!needed[b] && !self) continue;
    for (std::uint32_t t = cloth.mesh_tri_begin[b]; t < cloth.mesh_tri_begin[b + 1]; ++t) {
      const auto& tri = cloth.tris[t];
      cloth_triangles_[b].emplace_back(point(x[tri[0]]), point(x[tri[1]]), point(x[tri[2]]));
    }
    if (cloth_triangles_[b].empty()) continue;
    cloth_trees_[b] =
        std::make_unique<TriangleTree>(cloth_triangles_[b].begin(), cloth_triangles_[b].end());
    // Closest-point queries come only from other meshes and obstacle vertices near it; the
    // self-contact candidates are found by box overlaps, which need no search tree.
    if (needed[b]) cloth_trees_[b]->accelerate_distance_queries();
  }
  // The neighbourhoods are found for the reach they were asked with (once: the reach is fixed
  // per simulation), and only when self-contact is on.
  if (self && near_radius_ != reach) {
    find_near(cloth, kSelfApart * reach);
    near_radius_ = reach;
  }
  std::vector<TreePrimitive::Id> candidates;
  auto plane = [&](const Vec3& p, const Vec3& q, bool both_move) {
    const Vec3 off = sub(p, q);
    const double d = norm(off);
    if (!(d > 0.0) || d > reach) return false;
    const Vec3 normal = scale(off, 1.0 / d);
    const double offset = both_move ? (d > gap ? 0.5 * (d + gap) : d)
                                    : std::min(clearance, d);
    out.planes.push_back({add(q, scale(normal, offset)), normal});
    return true;
  };
  // Self-contact: the closest point within reach on a triangle of the particle's own mesh that is
  // far from it on the cloth (no corner among its near_ vertices).
  auto self_plane = [&](std::size_t i) {
    const std::uint32_t b = cloth.vertex_mesh[i];
    if (!cloth_trees_[b]) return;
    const Vec3& p = x[i];
    const std::uint32_t mark = static_cast<std::uint32_t>(i + 1);
    for (std::uint32_t k = near_begin_[i]; k < near_begin_[i + 1]; ++k) stamp_[near_[k]] = mark;
    candidates.clear();
    BoxOverlaps overlaps{CGAL::Bbox_3(p[0] - reach, p[1] - reach, p[2] - reach, p[0] + reach,
                                      p[1] + reach, p[2] + reach),
                         &candidates};
    cloth_trees_[b]->traversal(overlaps.box, overlaps);
    double best = INFINITY;
    Vec3 closest{0.0, 0.0, 0.0};
    for (const TreePrimitive::Id id : candidates) {
      const auto& tri = cloth.tris[cloth.mesh_tri_begin[b] +
                                   static_cast<std::uint32_t>(id - cloth_triangles_[b].begin())];
      if (stamp_[tri[0]] == mark || stamp_[tri[1]] == mark || stamp_[tri[2]] == mark) continue;
      const auto c = TreeKernel::Construct_projected_point_3()(*id, point(p));
      const Vec3 q{c.x(), c.y(), c.z()};
      const double d = dot(sub(p, q), sub(p, q));
      if (d < best) {
        best = d;
        closest = q;
      }
    }
    if (std::isfinite(best) && plane(p, closest, true)) ++self_planes_;
  };
  for (std::size_t i = 0; i < n; ++i) {
    out.begin[i] = static_cast<std::uint32_t>(out.planes.size());
    if (model.unknown[i] == kNone) continue;
    // The obstacles: the distance measured last, less the way moved since, is a lower bound of
    // the distance now; only a particle that may be within reach is measured again.
    if (obstacle_tree_ &&
        !(std::isfinite(lower_[i]) && lower_[i] - norm(sub(x[i], at_[i])) > reach)) {
      const auto hit = obstacle_tree_->closest_point_and_primitive(point(x[i]));
      const Vec3 q{hit.first.x(), hit.first.y(), hit.first.z()};
      lower_[i] = norm(sub(x[i], q));
      at_[i] = x[i];
      // A particle behind the outer side of a closed obstacle's nearest face is inside it (the
      // body grew over it, or a correction failed): a plane there would hold it inside, so it
      // gets none and is left to the correction.
      const std::uint32_t t =
          exposed_[static_cast<std::size_t>(hit.second - obstacle_triangles_.begin())];
      const double outward = measures_.closed[topo_.tri_component(t)];
      if (!(outward * dot(sub(x[i], q), oriented_normal(topo_, measures_, t)) < 0.0))
        plane(x[i], q, false);
    }
    for (std::size_t b = 0; b < meshes; ++b) {
      if (!cloth_trees_[b] || b == cloth.vertex_mesh[i] || !bounds[b].within(x[i], reach)) continue;
      const auto c = cloth_trees_[b]->closest_point(point(x[i]));
      plane(x[i], Vec3{c.x(), c.y(), c.z()}, true);
    }
    if (self) self_plane(i);
  }
  out.begin[n] = static_cast<std::uint32_t>(out.planes.size());
  out.faces.clear();
  for (std::uint32_t k : near_vertices) {
    const Vec3& p = topo_.points[exposed_vertices_[k]];
    double nearest = INFINITY;
    for (std::size_t b = 0; b < meshes; ++b) {
      if (!cloth_trees_[b] || !bounds[b].within(p, reach)) continue;
      const auto hit = cloth_trees_[b]->closest_point_and_primitive(point(p));
      const Vec3 q{hit.first.x(), hit.first.y(), hit.first.z()};
      const Vec3 off = sub(q, p);
      const double d = norm(off);
      nearest = std::min(nearest, d);
      if (!(d > 0.0) || d > reach) continue;
      // The plane faces along the vertex's outward normal (where its faces' outward sides are
      // known; the direction to the face otherwise), the direction the particles' own planes
      // push in too. A face behind the vertex's outward side is inside the obstacle (the body
      // grew over it): a plane would push it further in; it is left to the correction.
      const Vec3& outward = vertex_outward_[k];
      const bool known = outward != Vec3{0.0, 0.0, 0.0};
      if (known && !(dot(off, outward) > 0.0)) continue;
      const Vec3 normal = known ? outward : scale(off, 1.0 / d);
      const double height = dot(off, normal);
      if (!(height > 0.0)) continue;
      const std::uint32_t t = cloth.mesh_tri_begin[b] +
                              static_cast<std::uint32_t>(hit.second - cloth_triangles_[b].begin());
      FacePlane face;
      face.corner = cloth.tris[t];
      face.weight = barycentric(x[face.corner[0]], x[face.corner[1]], x[face.corner[2]], q);
      face.plane.normal = normal;
      face.plane.point = add(p, scale(normal, std::min(clearance, height)));
      out.faces.push_back(face);
    }
    if (std::isfinite(nearest)) {
      vertex_lower_[k] = nearest;
      vertex_travel_[k] = travel_;
    }
  }
}

}  // namespace untangle
